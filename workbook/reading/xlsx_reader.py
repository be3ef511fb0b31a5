"""A small, bounded reader of .xlsx files: defined names, cell values (as saved),
whether a cell holds a formula, and custom document properties.

It reads only what crankbook needs, straight from the zip, and refuses before
parsing what could exhaust the machine: too large on disk or unpacked, too many
parts, a part compressed beyond any real workbook, an unknown compression method,
XML entity or DOCTYPE declarations (in UTF-8 or UTF-16), macro and ActiveX parts
(found by content type and by content, not by file name), and encrypted or legacy
files.  Every refusal is an Unreadable with the reason in words.
"""
import io
import re
import time
import zipfile
import zlib
from pathlib import Path
from xml.etree import ElementTree

MAX_FILE = 20 * 1024 * 1024           # bytes on disk
MAX_UNPACKED = 100 * 1024 * 1024      # bytes, all parts together
MAX_PART = 60 * 1024 * 1024           # bytes, one part
MAX_RATIO = 200                       # per part above 1 MB: unpacked / packed
MAX_PARTS = 2000
MAX_SHEETS = 255                      # sheets of one workbook (crankbook's have ~40)
MAX_NAMES = 20_000                    # defined names
MAX_CELLS = 2_000_000                 # cells kept from all sheets together (~100 B each)
MAX_STRINGS = 1_000_000               # shared strings
MAX_ELEMENTS = 20_000_000             # XML elements parsed from one file
MAX_DEPTH = 64                        # XML element nesting
MAX_FORMULA = 2000                    # characters of a formula kept (to look at, not run)
# CPU seconds to read one file: a hostile file's cost is its parsing, and a busy
# machine (a class graded beside a build) must not refuse a legitimate file
TIME_LIMIT = 30.0
OLE_MAGIC = b"\xd0\xcf\x11\xe0"
MAIN = "http://schemas.openxmlformats.org/spreadsheetml/2006/main"
REL = "http://schemas.openxmlformats.org/officeDocument/2006/relationships"
PACKAGE_REL = "http://schemas.openxmlformats.org/package/2006/relationships"
MACRO_TYPES = ("vbaProject", "macroEnabled", "activeX", "ms-office.vbaProject", "vnd.ms-excel.macro",
               "ms-excel.intlmacrosheet", "ms-excel.macrosheet", "oleObject")
MACRO_MAGIC = (OLE_MAGIC, b"Attribute VB_Name")
DECLARATION = re.compile(rb"<!\s*(DOCTYPE|ENTITY)", re.I)
CELL = re.compile(r"([A-Z]{1,3})([0-9]{1,7})\Z")
SHEET_NAME_FORBIDDEN = re.compile(r"[/\\?*\[\]:]")     # Excel refuses these in a name
AREA = re.compile(r"\$?([A-Z]{1,3})\$?([0-9]{1,7}):\$?([A-Z]{1,3})\$?([0-9]{1,7})\Z")
MAX_ARRAYS = 10_000                   # array formulas kept per sheet
# LibreOffice writes every shared formula out in full: its recalculated copy of a
# workbook that passed these limits, or a user's copy it saved, may unpack, and take
# to read, this many times more (the speed-range sheet of an inline-4 with a pressure
# per speed: 116 MB of XML; the inline-6 saved: 23 MB, 260 MB unpacked, a 119 MB part)
RECALCULATED_SCALE = 4
# the document properties an integrity check reads (who made the file, and when)
CORE_PROPERTIES = ("creator", "lastModifiedBy", "created", "modified")


class Unreadable(Exception):
    """Why a file could not be read."""


def _column(letters):
    number = 0
    for char in letters:
        number = number * 26 + ord(char) - 64
    return number


def _text_of(data, name):
    """The part as text, decoded by its BOM; Unreadable for declarations in any encoding."""
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):
        try:
            text = data.decode("utf-16")
        except UnicodeDecodeError:
            raise Unreadable(f"{name} is not valid UTF-16") from None
        encoded = text.encode("utf-8")
    else:
        encoded = data[3:] if data.startswith(b"\xef\xbb\xbf") else data
    if DECLARATION.search(encoded) or DECLARATION.search(data.replace(b"\x00", b"")):
        raise Unreadable(f"{name} declares XML entities or a DOCTYPE (entity bomb?): not parsed")
    return encoded


def _value(cell, shared, tag_v, tag_is):
    """A cell's saved value: a number, a string, a bool, or None."""
    kind = cell.get("t", "n")
    v = cell.find(tag_v)
    text = v.text if v is not None else None
    if kind == "s":
        try:
            return shared[int(text)] if text is not None else None
        except (ValueError, IndexError):
            return None
    if kind in ("str", "e"):
        return text
    if kind == "inlineStr":
        inline = cell.find(tag_is)
        return "".join(t.text or "" for t in inline.iter(f"{{{MAIN}}}t")) \
            if inline is not None else None
    if kind == "b":
        return text == "1"
    try:
        return float(text) if text not in (None, "") else None
    except ValueError:
        return None


class XlsxBook:
    """The parts of one .xlsx that crankbook reads; see the module docstring."""

    def __init__(self, path, time_limit=TIME_LIMIT, scale=1):
        """``scale`` multiplies the size, element, cell and time limits: a spreadsheet
        engine's recalculated copy of a checked file (RECALCULATED_SCALE)."""
        self.path = Path(path)
        self.scale = scale
        time_limit *= scale
        self.deadline = time.process_time() + time_limit
        self.time_limit = time_limit
        self.max_unpacked, self.max_part = MAX_UNPACKED * scale, MAX_PART * scale
        self._elements = 0
        self._cells = 0
        self._check_file()
        try:
            self.zip = zipfile.ZipFile(self.path)
            self._check_parts()
            self._read_workbook()
        except zipfile.BadZipFile as error:
            raise Unreadable(f"corrupt zip ({error})") from None
        except (zlib.error, EOFError, OSError, NotImplementedError, RuntimeError) as error:
            raise Unreadable(f"damaged compressed data ({type(error).__name__})") from None
        except ElementTree.ParseError as error:
            raise Unreadable(f"damaged XML ({error})") from None
        self._sheets = {}
        self._shared_formulas = {}

    # ------------------------------------------------------------ checks
    def _check_file(self):
        try:
            size = self.path.stat().st_size
        except OSError as error:
            raise Unreadable(f"cannot be opened ({error.strerror})") from None
        if size > MAX_FILE * self.scale:
            raise Unreadable(f"file is {size / 1e6:.0f} MB, more than "
                             f"{MAX_FILE * self.scale // 2**20} MB")
        with open(self.path, "rb") as handle:
            head = handle.read(8)
        if head.startswith(OLE_MAGIC):
            raise Unreadable("password-protected (encrypted) or legacy .xls workbook")
        if self.path.suffix.lower() in (".xlsm", ".xltm", ".xlam"):
            raise Unreadable("macro-enabled workbook: not opened; save it as .xlsx")
        if not head.startswith(b"PK"):
            raise Unreadable("not an .xlsx file (not a zip container)")

    def _check_parts(self):
        members = self.zip.infolist()
        if len(members) > MAX_PARTS:
            raise Unreadable(f"{len(members)} parts in the zip: not a workbook")
        names = [m.filename for m in members]
        if len(set(names)) != len(names):
            raise Unreadable("the zip holds two parts of the same name")
        total = 0
        for member in members:
            if member.compress_type not in (zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED):
                raise Unreadable(f"{member.filename} uses an unsupported compression method")
            if member.flag_bits & 0x1:
                raise Unreadable("encrypted zip parts: not opened")
            total += member.file_size
            if total > self.max_unpacked or member.file_size > self.max_part:
                raise Unreadable(f"unpacks to more than {self.max_unpacked // 2**20} MB "
                                 f"(zip bomb?)")
            if member.file_size > 1024 * 1024 and \
                    member.file_size > MAX_RATIO * max(member.compress_size, 1):
                raise Unreadable(f"{member.filename} is compressed {MAX_RATIO}:1 or more "
                                 f"(zip bomb?)")
        if "xl/workbook.xml" not in names and "[Content_Types].xml" not in names:
            raise Unreadable("a zip file but not an .xlsx workbook")
        types = self._part("[Content_Types].xml", required=False) or b""
        lowered = types.lower()
        if any(t.lower().encode() in lowered for t in MACRO_TYPES):
            raise Unreadable("contains macros or ActiveX controls: not opened")
        for member in members:
            if member.filename.endswith((".xml", ".rels", ".vml")):
                _text_of(self._part(member.filename), member.filename)
            elif not member.filename.endswith("/"):
                head = self._part(member.filename)[:4096]
                if any(magic in head for magic in MACRO_MAGIC):
                    raise Unreadable(f"{member.filename} holds macro code: not opened")

    def _tick(self):
        if time.process_time() > self.deadline:
            raise Unreadable(f"took longer than {self.time_limit:g} s of CPU time to read")

    def _part(self, name, required=True):
        self._tick()
        try:
            with self.zip.open(name) as stream:
                data = stream.read(self.max_part + 1)
        except KeyError:
            if required:
                raise Unreadable(f"the part {name} is missing") from None
            return None
        if len(data) > self.max_part:
            raise Unreadable(f"{name} unpacks to more than {self.max_part // 2**20} MB")
        return data

    def _stream(self, name, tags):
        """Each element of ``tags`` in the part, parsed as a stream: the deadline and
        the element budget are checked inside the part, and every element leaves the
        tree once it has ended (after its ``tags`` ancestor is read), so memory stays
        that of the values kept, whatever the part's size."""
        data = self._part(name)
        stack, open_targets = [], 0
        push, pop = stack.append, stack.pop        # the loop runs once per element
        for event, element in ElementTree.iterparse(io.BytesIO(_text_of(data, name)),
                                                    events=("start", "end")):
            if event == "start":
                push(element)
                if len(stack) > MAX_DEPTH:
                    raise Unreadable(f"{name} nests XML deeper than {MAX_DEPTH} levels")
                if element.tag in tags:
                    open_targets += 1
                continue
            pop()
            self._elements += 1
            if not self._elements % 20000:
                self._tick()
                if self._elements > MAX_ELEMENTS * self.scale:
                    raise Unreadable(f"more than {MAX_ELEMENTS * self.scale:,} XML elements: "
                                     f"not a workbook crankbook wrote")
            if element.tag in tags:
                open_targets -= 1
                yield element
            if not open_targets and stack:
                stack[-1].remove(element)       # the last child: its siblings are gone

    def _xml(self, name, required=True):
        data = self._part(name, required)
        if data is None:
            return None
        root = ElementTree.fromstring(_text_of(data, name))
        self._check_depth(root, name)
        return root

    def _check_depth(self, root, name):
        stack = [(root, 1)]
        while stack:
            node, depth = stack.pop()
            if depth > MAX_DEPTH:
                raise Unreadable(f"{name} nests XML deeper than {MAX_DEPTH} levels")
            stack.extend((child, depth + 1) for child in node)

    # ------------------------------------------------------------ workbook part
    def _read_workbook(self):
        book = self._xml("xl/workbook.xml")
        rels = self._xml("xl/_rels/workbook.xml.rels")
        targets = {r.get("Id"): (r.get("Target") or "", r.get("Type") or "")
                   for r in rels.iter(f"{{{PACKAGE_REL}}}Relationship")}
        self.sheet_part, self.chart_sheets, self.sheetnames = {}, set(), []
        sheets = list(book.iter(f"{{{MAIN}}}sheet"))
        if len(sheets) > MAX_SHEETS:
            raise Unreadable(f"{len(sheets)} sheets, more than {MAX_SHEETS}: not a workbook "
                             f"crankbook wrote")
        for sheet in sheets:
            name = sheet.get("name")
            if name is None or not name or SHEET_NAME_FORBIDDEN.search(name):
                # Excel's rule; an engine that writes each sheet to <file>-<sheet>.csv
                # would otherwise put a '../' sheet outside its folder
                raise Unreadable(f"sheet name {name!r} is not one Excel allows (empty, or "
                                 f"holding one of / \\ ? * [ ] :)")
            target, kind = targets.get(sheet.get(f"{{{REL}}}id"), ("", ""))
            self.sheetnames.append(name)
            if kind.endswith("/chartsheet"):
                self.chart_sheets.add(name)
                continue
            target = target.lstrip("/")
            self.sheet_part[name] = target if target.startswith("xl/") else "xl/" + target
        self.defined_names = {}
        self.local_names = {}            # name -> text of a name local to one sheet
        for item in book.iter(f"{{{MAIN}}}definedName"):
            if item.get("localSheetId") is None and item.text:
                self.defined_names[item.get("name")] = item.text
            elif item.text:
                self.local_names[item.get("name")] = item.text[:MAX_FORMULA]
                if len(self.defined_names) > MAX_NAMES:
                    raise Unreadable(f"more than {MAX_NAMES:,} defined names: not a workbook "
                                     f"crankbook wrote")
        self.shared = []
        if "xl/sharedStrings.xml" in self.zip.namelist():
            for si in self._stream("xl/sharedStrings.xml", {f"{{{MAIN}}}si"}):
                self.shared.append("".join(t.text or "" for t in si.iter(f"{{{MAIN}}}t"))[:32767])
                if len(self.shared) > MAX_STRINGS:
                    raise Unreadable(f"more than {MAX_STRINGS:,} shared strings")
        self.core_properties = {}
        core = self._xml("docProps/core.xml", required=False)
        if core is not None:
            for node in core:
                name = node.tag.rsplit("}", 1)[-1]
                if name in CORE_PROPERTIES and node.text:
                    self.core_properties[name] = node.text.strip()[:200]
        self.external_links = any(n.startswith("xl/externalLinks/")
                                  for n in self.zip.namelist())
        self.custom_properties = {}
        custom = self._xml("docProps/custom.xml", required=False)
        if custom is not None:
            for prop in custom:
                value = next(iter(prop), None)
                self.custom_properties[prop.get("name")] = value.text if value is not None \
                    else None

    # ------------------------------------------------------------ cells
    def _sheet(self, name):
        if name in self._sheets:
            return self._sheets[name]
        if name in self.chart_sheets:
            raise Unreadable(f"sheet {name!r} is a chart sheet, not cells")
        if name not in self.sheet_part:
            raise Unreadable(f"sheet {name!r} does not exist")
        cells = {}
        shared_masters, followers = {}, {}   # si -> (row, col, text); (row, col) -> si
        arrays = []                          # (first row, col, last row, col, master)
        tag_c, tag_v, tag_f, tag_is = (f"{{{MAIN}}}c", f"{{{MAIN}}}v", f"{{{MAIN}}}f",
                                       f"{{{MAIN}}}is")
        columns = {}                     # letters -> number: a sheet has few columns
        try:
            for cell in self._stream(self.sheet_part[name], {tag_c}):
                match = CELL.match(cell.get("r") or "")
                if not match:
                    continue
                letters = match.group(1)
                column = columns.get(letters)
                if column is None:
                    column = columns[letters] = _column(letters)
                key = (int(match.group(2)), column)
                formula = cell.find(tag_f)
                cells[key] = (_value(cell, self.shared, tag_v, tag_is),
                              False if formula is None else (formula.text or "")[:MAX_FORMULA]
                              or True)
                if formula is not None and formula.get("t") == "array" and formula.get("ref"):
                    area = AREA.match(formula.get("ref"))
                    if area and len(arrays) < MAX_ARRAYS:
                        arrays.append((int(area.group(2)), _column(area.group(1)),
                                       int(area.group(4)), _column(area.group(3)), key))
                if formula is not None and formula.get("t") == "shared":
                    if formula.text:
                        shared_masters[formula.get("si")] = (*key, formula.text[:MAX_FORMULA])
                    else:
                        followers[key] = formula.get("si")
                self._cells += 1
                if self._cells > MAX_CELLS * self.scale:
                    raise Unreadable(f"more than {MAX_CELLS * self.scale:,} cells: not a workbook "
                                     f"crankbook wrote")
        except ElementTree.ParseError as error:
            raise Unreadable(f"sheet {name!r} is damaged XML ({error})") from None
        except (zlib.error, EOFError, zipfile.BadZipFile, OSError) as error:
            raise Unreadable(f"sheet {name!r}: damaged compressed data "
                             f"({type(error).__name__})") from None
        self._sheets[name] = cells
        self._shared_formulas[name] = (shared_masters, followers, arrays)
        return cells

    def formula_at(self, sheet, row, col):
        """The formula of one cell as written there (a shared formula's follower gets
        its master's text moved to the follower's place), or None."""
        cells = self._sheet(sheet)
        formula = cells.get((row, col), (None, False))[1]
        masters, followers, arrays = self._shared_formulas[sheet]
        if formula is False:             # a cell of an array formula's area is its master's
            for r1, c1, r2, c2, master in arrays:
                if r1 <= row <= r2 and c1 <= col <= c2 and master != (row, col):
                    text = cells[master][1]
                    return text if isinstance(text, str) else ""
            return None
        if formula is not True:
            return formula
        master = masters.get(followers.get((row, col)))
        if master is None:
            return ""
        from crankbook.reading.dependencies import moved
        return moved(master[2], row - master[0], col - master[1])

    def formula_cells(self, sheet):
        """(row, col) of every cell of ``sheet`` holding a formula (an array formula's
        area: its master)."""
        return [key for key, (_, formula) in self._sheet(sheet).items() if formula is not False]

    def array_areas(self, sheet):
        """(first row, first col, last row, last col) of each array formula's area."""
        self._sheet(sheet)
        return [area[:4] for area in self._shared_formulas[sheet][2]]

    def values(self, sheet, min_row, min_col, max_row, max_col):
        """Cell values row by row (None for empty cells)."""
        cells = self._sheet(sheet)
        return [cells.get((r, c), (None, False))[0] for r in range(min_row, max_row + 1)
                for c in range(min_col, max_col + 1)]

    def has_formulas(self, sheet, min_row, min_col, max_row, max_col):
        cells = self._sheet(sheet)
        return [bool(cells.get((r, c), (None, False))[1]) for r in range(min_row, max_row + 1)
                for c in range(min_col, max_col + 1)]

    def formula_texts(self, sheet, min_row, min_col, max_row, max_col):
        """Each cell's formula (without '='; '' for a shared formula's follower), or None."""
        cells = self._sheet(sheet)
        out = []
        for r in range(min_row, max_row + 1):
            for c in range(min_col, max_col + 1):
                formula = cells.get((r, c), (None, False))[1]
                out.append(None if formula is False else ("" if formula is True else formula))
        return out

    def close(self):
        self.zip.close()


def sheet_rows(book, sheet=None, limit=100_000):
    """All rows of a sheet (the first one by default) as lists of values, empty cells
    None, trailing empty cells dropped."""
    name = sheet or next((s for s in book.sheetnames if s not in book.chart_sheets), None)
    if name is None:
        raise Unreadable("the workbook has no sheet of cells")
    cells = book._sheet(name)
    if not cells:
        return []
    last_row = max(r for r, _ in cells)
    if last_row > limit:
        raise Unreadable(f"more than {limit} rows")
    rows = [[] for _ in range(last_row)]
    for (r, c), (value, _) in sorted(cells.items()):
        if c > 1000:
            continue
        row = rows[r - 1]
        row.extend([None] * (c - 1 - len(row)))
        row.append(value)
    for row in rows:
        while row and (row[-1] is None or row[-1] == ""):
            row.pop()
    return rows
