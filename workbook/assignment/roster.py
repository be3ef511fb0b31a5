"""Class rosters as teachers have them.

A CSV saved by Excel in UTF-8 (with or without BOM), GBK/GB18030 (Excel on a
Chinese Windows), UTF-16 ("Unicode text", tab-separated), or an .xlsx (its first
sheet).  The header names the id and name columns in English or Chinese
(student_id/id/学号, name/姓名); other columns are kept.  Every problem is one
RosterError naming the row and the rule.

Student ids become file names and LMS identifiers, so they are plain: letters
(any script), digits, '-', '_' and '.', at most 64 characters, not starting with
'.', '-', '=', '+' or '@' — an id stays exactly what the LMS matches on.
"""
import csv
import io
import unicodedata
from pathlib import Path

from crankbook.errors import RosterError
from crankbook.reading.xlsx_reader import Unreadable, XlsxBook, sheet_rows
from crankbook.support.paths import require_file

ALIASES = {
    "student_id": ("student_id", "student id", "id", "student number", "学号", "学生编号",
                   "学生学号"),
    "name": ("name", "student name", "full name", "姓名", "名字", "学生姓名"),
}
MAX_BYTES = 10 * 1024 * 1024
MAX_STUDENTS = 5000


def excel_text(raw, what, error=RosterError):
    """Text of a file as Excel saves it — UTF-8 (with or without BOM), GBK/GB18030 or
    UTF-16 — or ``error`` naming ``what`` (rosters, group tables, overrides)."""
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        try:
            return raw.decode("utf-16")
        except UnicodeDecodeError:
            raise error(f"{what}: damaged UTF-16 text") from None
    if raw.startswith(b"\xef\xbb\xbf"):
        raw = raw[3:]
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError:
        pass
    try:
        text = raw.decode("gb18030")
    except UnicodeDecodeError:
        text = None
    if text is None or _misread(text):
        for encoding, where in (("big5", "Big5 (Excel on a Traditional Chinese Windows)"),
                                ("shift_jis", "Shift-JIS (Excel on a Japanese Windows)")):
            try:
                raw.decode(encoding)
            except UnicodeDecodeError:
                continue
            raise error(f"{what}: looks like {where} text, which crankbook does not guess; "
                        f"save it from Excel as 'CSV UTF-8' or as .xlsx")
    if text is not None:
        return text
    raise error(f"{what}: not UTF-8, GBK/GB18030 or UTF-16 text; save it from Excel as "
                f"'CSV UTF-8' or as .xlsx")


def _misread(text):
    """Whether GB18030 text reads like another encoding's bytes: kana, Greek, Cyrillic,
    box drawing or private-use characters among Chinese ones, or more than a third of
    the Chinese characters outside GB2312 (a roster typed in GBK uses them seldom)."""
    odd = sum(1 for c in text if "\u3040" <= c <= "\u30ff" or "\u0370" <= c <= "\u04ff"
              or "\u2500" <= c <= "\u257f" or "\ue000" <= c <= "\uf8ff")
    chinese = [c for c in text if "\u4e00" <= c <= "\u9fff"]
    rare = 0
    for c in chinese:
        try:
            c.encode("gb2312")
        except UnicodeEncodeError:
            rare += 1
    return odd > 0 or (len(chinese) >= 4 and rare * 3 > len(chinese))


def _rows(path):
    """(rows of text, {(row, col) holding a formula}, whether rows may be short): an
    .xlsx's rows lose their trailing empty cells, a CSV's never do."""
    path = Path(path)
    require_file(path, RosterError, "roster")
    if path.stat().st_size > MAX_BYTES:
        raise RosterError(f"roster {path}: larger than {MAX_BYTES // 2**20} MB")
    if path.suffix.lower() in (".xlsx", ".xlsm"):
        try:
            book = XlsxBook(path)
            rows = [["" if v is None else (str(int(v)) if isinstance(v, float) and v.is_integer()
                                           else str(v)) for v in row] for row in sheet_rows(book)]
            first = next(s for s in book.sheetnames if s not in book.chart_sheets)
            numbers = {(r, c) for (r, c), (v, _) in book._sheet(first).items()
                       if isinstance(v, float)}
            return rows, {key for key in book.formula_cells(first)}, numbers
        except Unreadable as reason:
            raise RosterError(f"roster {path}: {reason}") from None
    text = excel_text(path.read_bytes(), f"roster {path}")
    if "\x00" in text:
        raise RosterError(f"roster {path}: contains NUL characters; not a text file")
    sample = text[:4096]
    try:
        dialect = csv.Sniffer().sniff(sample, delimiters=",;\t")
    except csv.Error:
        dialect = csv.excel_tab if "\t" in sample and "," not in sample else csv.excel
    try:
        return list(csv.reader(io.StringIO(text), dialect)), set(), None
    except csv.Error as error:
        raise RosterError(f"roster {path}: not a readable CSV ({error})") from None


def _column(header, field):
    for index, title in enumerate(header):
        if title.strip().lower().replace("_", " ") in {a.replace("_", " ") for a in ALIASES[field]}:
            return index
    return None


RESERVED = {"CON", "PRN", "AUX", "NUL", *(f"COM{i}" for i in range(1, 10)),
            *(f"LPT{i}" for i in range(1, 10))}


def id_problem(sid):
    """Why ``sid`` cannot be a student id (None when it can)."""
    if not sid:
        return "is empty"
    if len(sid) > 64:
        return "is longer than 64 characters"
    if sid[0] in ".-=+@":
        return f"starts with {sid[0]!r} (ids become file names and LMS identifiers)"
    if sid.split(".")[0].upper() in RESERVED:
        return "is a name Windows reserves for a device (ids become file names)"
    for char in sid:
        if not (char.isalnum() or char in "-_.") or unicodedata.category(char).startswith("C"):
            return (f"holds {char!r}; ids may hold only letters, digits, '-', '_' and '.' "
                    f"(they become file names)")
    return None


def read_roster(path):
    """(rows, fields): each row a dict with student_id, name and the other columns."""
    table, formulas, numbers = _rows(path)
    skipped = _title_rows(table)
    table = table[skipped:]
    if not table:
        raise RosterError(f"roster {path}: is empty")
    header = [cell.strip().lstrip("\ufeff") for cell in table[0]]
    while header and not header[-1]:
        header.pop()
    positions = {field: _column(header, field) for field in ALIASES}
    for field, index in positions.items():
        if index is None:
            names = "/".join(ALIASES[field][:1] + ALIASES[field][4:5] if field == "student_id"
                             else ALIASES[field][:1] + ALIASES[field][3:4])
            raise RosterError(f"roster {path}: needs a {names} column (has: "
                              f"{', '.join(h for h in header if h) or 'no header'})")
    extras = [(i, h) for i, h in enumerate(header) if i not in positions.values() and h]
    rows, seen, stored = [], {}, []
    for number, cells in enumerate(table[1:], start=2):
        if not any(cell.strip() for cell in cells):
            continue
        used = len(cells)
        while used and not cells[used - 1].strip():
            used -= 1
        short = numbers is None and len(cells) < len(header)     # a CSV row cut short
        if used > len(header) or short:
            raise RosterError(f"roster {path}, row {number + skipped}: "
                              f"{used if used > len(header) else len(cells)} cells but the "
                              f"header has {len(header)} columns")
        cells = cells + [""] * (len(header) - len(cells))
        for field in ("student_id", "name"):
            if (number + skipped, positions[field] + 1) in formulas:
                raise RosterError(f"roster {path}, row {number + skipped}: the {field.replace('_', ' ')} "
                                  f"cell holds a formula; type the {field.replace('_', ' ')} "
                                  f"as text")
        sid = cells[positions["student_id"]].strip()
        if numbers and (number + skipped, positions["student_id"] + 1) in numbers:
            stored.append(number + skipped)
        problem = id_problem(sid)
        if problem:
            raise RosterError(f"roster {path}, row {number + skipped}: student id {sid[:40]!r} {problem}")
        if sid.casefold() in seen:             # s1 and S1 are one file on Windows and macOS
            other, row = seen[sid.casefold()]
            same = "is also" if other == sid else f"differs only in case from {other!r},"
            raise RosterError(f"roster {path}, row {number}: student id {sid!r} {same} in row "
                              f"{row} (ids become file names)")
        seen[sid.casefold()] = (sid, number)
        row = {"student_id": sid, "name": cells[positions["name"]].strip()}
        row.update({title: cells[i].strip() for i, title in extras})
        rows.append(row)
        if len(rows) > MAX_STUDENTS:
            raise RosterError(f"roster {path}: more than {MAX_STUDENTS} students")
    if not rows:
        raise RosterError(f"roster {path}: has no students")
    _warn_about_ids(path, rows, stored)
    return rows, ["student_id", "name"] + [title for _, title in extras]


def _title_rows(table, looked_at=10):
    """Rows above the header: empty ones, and a title ("2023级机械1班名单", merged
    across the columns) — the header is the first of the first ``looked_at`` rows
    that names both an id and a name column."""
    for index, cells in enumerate(table[:looked_at]):
        header = [cell.strip().lstrip("\ufeff") for cell in cells]
        if all(_column(header, field) is not None for field in ALIASES):
            return index
    index = 0
    while index < len(table) and not any(cell.strip() for cell in table[index]):
        index += 1
    return index


def _warn_about_ids(path, rows, stored):
    """A warning where ids look mangled: stored as numbers in an .xlsx (leading zeros
    gone) or all digits of different lengths (one lost a zero?)."""
    import warnings
    from crankbook.errors import CrankbookWarning
    if stored:
        warnings.warn(CrankbookWarning(
            f"roster {path}: {len(stored)} student id(s) are stored as numbers in the "
            f"workbook (row {stored[0]} first): a leading zero would be lost; format the "
            f"id column as text"), stacklevel=3)
    lengths = sorted({len(r["student_id"]) for r in rows if r["student_id"].isdigit()})
    if len(lengths) > 1:
        warnings.warn(CrankbookWarning(
            f"roster {path}: the all-digit student ids have {' and '.join(map(str, lengths))} "
            f"digits: did a spreadsheet drop leading zeros?"), stacklevel=3)
