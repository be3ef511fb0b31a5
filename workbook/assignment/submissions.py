"""Returned workbooks: found, read and recalculated one at a time.

Every file under the submissions folder is seen: .xlsx read as it is; .ods, .xls,
.xlsb, WPS's .et (and their templates) made .xlsx by LibreOffice first; a .zip
unpacked (bounded: 100 files, no nesting, no bombs, no encryption) with each
workbook inside a submission of its own; anything else (a .pdf, a photo) is a
submission whose reason says it is no workbook, so a student who handed in only
that is "unreadable: …", never "missing", and a file nobody owns is listed for the
teacher.  Suffixes are read in any case and with trailing spaces ("作业.XLSX ");
only what an operating system leaves (Office lock files, Thumbs.db, .DS_Store,
__MACOSX) is passed over.

Every submission is untrusted.  Each is read by the bounded reader
(crankbook.reading.xlsx_reader) on its own; any failure — a refusal, a damaged part, or an
error no one foresaw — makes that file ``unreadable`` with a reason in words and
touches nothing else.  Files saved without values (formulas written by a script)
are recalculated in LibreOffice, first together and, if that run fails or times
out, each on its own with its own time limit; the LibreOffice process and its
copies are gone afterwards whatever happened.  Reasons never name a path on the
grading machine.
"""
import hashlib
import os
import re
import stat
import time
from dataclasses import dataclass, field
from pathlib import Path

from crankbook.reading import recalc
from crankbook.errors import CrankbookError
from crankbook.reading.dependencies import MachineTrace
from crankbook.reading.workbook_reader import parse_reference
from crankbook.reading.xlsx_reader import MAX_FILE, Unreadable, XlsxBook
from crankbook.support.paths import not_a_file
from crankbook.support.progress import waiting
from crankbook.support.workspace import temporary_directory

READ = (".xlsx", ".xltx", ".xlsm", ".xltm")     # read as they are (macros: refused)
# converted to .xlsx by LibreOffice first: Excel 97–2003, binary, OpenDocument, WPS
CONVERT = (".xls", ".xlt", ".xlsb", ".ods", ".ots", ".fods", ".et", ".ett")
ARCHIVES = (".zip",)
# what an operating system leaves in a folder: never a student's work, never listed
SYSTEM_FILES = ("thumbs.db", "desktop.ini", ".ds_store")
SYSTEM_FOLDERS = ("__MACOSX",)
MAX_FILES = 20_000
MAX_MEMBERS = 100                  # files in one handed-in zip
MAX_CELLS = 10_000                 # per answer name: far more than any task has
EXTRA_ROWS = 40                    # rows a student may insert into a table (notes, …)
RECALC_LIMIT = 60                  # seconds per file in LibreOffice
MAX_FORMULA_SHOWN = 120            # characters of a refused answer's formula kept
RECALC_BUDGET = 300                # seconds of LibreOffice for all of one grade run


class MachineDependent(str):
    """An answer refused because its value would be the grading machine's: the
    answer cell's own formula, as text (crankbook.reading.dependencies)."""
    machine_dependent = True


@dataclass
class Submission:
    path: Path
    relative: str                  # shown to people: relative to the submissions folder
    size: int = 0
    mtime: float = 0.0
    student_id: str | None = None  # the roster student it belongs to (its LMS folder)
    other_ids: list = field(default_factory=list)   # other roster ids deeper in its path
    ambiguous: list = field(default_factory=list)   # ids of a path part naming several
    inside_id: str | None = None   # s_student_id in the file
    answers: dict = field(default_factory=dict)
    parameters: dict = field(default_factory=dict)
    problem: str | None = None     # why it is unreadable
    needs_recalc: bool = False
    digest: str = ""
    row_labels: dict = field(default_factory=dict)   # answer key -> labels beside its rows
    metadata: dict = field(default_factory=dict)     # creator, last saved by, created, …
    placement: dict = field(default_factory=dict)    # answer key -> key row of each file row
    needs_conversion: bool = False # a .ods, .xls, .et, …: LibreOffice makes it an .xlsx
    is_key: bool = False           # an answer key crankbook wrote: a leaked key?


def shown_name(path, root):
    """A path relative to ``root`` as text a person can read (undecodable bytes replaced)."""
    relative = os.fsencode(os.path.relpath(path, root))
    return relative.decode("utf-8", "replace").replace("\ufffd", "?")


def suffix_of(name):
    """A file's kind as a person names it: the suffix in lower case, trailing spaces
    and dots (a Windows upload's "作业.XLSX ") ignored."""
    return os.path.splitext(name.rstrip(" .\t"))[1].lower()


def _system_file(name):
    return name.lower() in SYSTEM_FILES or name.startswith(("~$", "._", "."))


def discover(root):
    """Every file under ``root`` (nested folders, any names), sorted — workbooks of
    any format, archives and whatever else a student uploaded (a .pdf is listed for
    the teacher, never dropped unseen); only what an operating system leaves (Office
    lock files, Thumbs.db, .DS_Store, __MACOSX) is passed over."""
    root = Path(root)
    found = []
    for folder, directories, files in os.walk(root):
        directories[:] = sorted(d for d in directories if d not in SYSTEM_FOLDERS)
        for name in sorted(files):
            if not _system_file(name):
                found.append(Path(folder) / name)
                if len(found) > MAX_FILES:
                    raise CrankbookError(f"{root}: more than {MAX_FILES} files; give the "
                                         f"folder of one class")
    return found


def _not_regular(path, root):
    """Why ``path`` must not be read — a named pipe (reading it would wait forever), a
    device, a socket, a link leaving the submissions folder — or None."""
    status = os.lstat(path)
    if stat.S_ISLNK(status.st_mode):
        real, top = os.path.realpath(path), os.path.realpath(root)
        if os.path.commonpath([real, top]) != top:
            return "a link that leaves the submissions folder: not read"
    reason = not_a_file(path)
    return f"{reason}: not read" if reason else None


def prepare(paths, root, scratch=None):
    """A Submission per file (a zip: one per workbook inside, unpacked into
    ``scratch``); what cannot be graded carries its reason."""
    subs = []
    for path in paths:
        sub = Submission(path=path, relative=shown_name(path, root))
        try:
            sub.problem = _not_regular(path, root)
            if sub.problem:
                subs.append(sub)
                continue
            status = path.stat()
            sub.size, sub.mtime = status.st_size, status.st_mtime
            if sub.size > MAX_FILE:
                sub.problem = f"file is {sub.size / 1e6:.0f} MB, more than {MAX_FILE // 2**20} MB"
            else:
                data = path.read_bytes()
                sub.digest = hashlib.sha256(data).hexdigest()
                if suffix_of(path.name) in ARCHIVES and scratch is not None:
                    inner = _unpack(sub, data, Path(scratch))
                    if inner:
                        subs.extend(inner)
                        continue
                else:
                    _classify(sub, path.name, data)
        except OSError as error:
            sub.problem = f"cannot be opened ({error.strerror})"
        subs.append(sub)
    return subs


def _classify(sub, name, data):
    """Whether ``sub`` is read as it is, converted first, or not a workbook (reason)."""
    suffix = suffix_of(name)
    # an Office Open zip names its content types in the local header or the directory
    office_open = data.startswith(b"PK") and (b"[Content_Types].xml" in data[:65536] or
                                              b"[Content_Types].xml" in data[-65536:])
    if suffix in CONVERT and not office_open:
        sub.needs_conversion = True           # an .xlsx named .xls is read as it is
    elif suffix not in READ and suffix not in CONVERT:
        sub.problem = f"not a workbook ({suffix or 'a file without a suffix'}): hand in " \
                      f"the task's .xlsx"


def _unpack(sub, data, scratch):
    """The workbooks inside a handed-in zip, each a Submission of its own (named
    ``archive.zip/inner.xlsx``), unpacked under numbered names into ``scratch`` —
    or [] with ``sub.problem`` saying why none."""
    import io
    import zipfile
    from crankbook.reading.xlsx_reader import MAX_RATIO, MAX_UNPACKED
    try:
        archive = zipfile.ZipFile(io.BytesIO(data))
        members = [m for m in archive.infolist() if not m.is_dir() and not any(
            part in SYSTEM_FOLDERS for part in m.filename.split("/")) and
            not _system_file(m.filename.rsplit("/", 1)[-1])]
        if len(members) > MAX_MEMBERS:
            sub.problem = f"a zip of {len(members)} files: hand in the task's .xlsx"
            return []
        if sum(m.file_size for m in members) > MAX_UNPACKED or any(
                m.file_size > MAX_FILE or (m.file_size > 2**20 and
                                           m.file_size > MAX_RATIO * max(m.compress_size, 1))
                for m in members):
            sub.problem = "a zip that unpacks to more than any task (zip bomb?): not opened"
            return []
        if any(m.flag_bits & 0x1 for m in members):
            sub.problem = "an encrypted zip: not opened"
            return []
        out = []
        for member in members:
            name = member.filename.rsplit("/", 1)[-1]
            inner = Submission(path=sub.path, relative=f"{sub.relative}/{member.filename}",
                               size=member.file_size, mtime=sub.mtime)
            if suffix_of(name) in ARCHIVES:
                inner.problem = "a zip inside a zip: not opened"
            else:
                body = archive.read(member)
                inner.digest = hashlib.sha256(body).hexdigest()
                _classify(inner, name, body)
                if not inner.problem:           # named by content: no student's name
                    scratch.mkdir(parents=True, exist_ok=True)
                    inner.path = scratch / f"zip-{inner.digest[:24]}{suffix_of(name)}"
                    inner.path.write_bytes(body)
            out.append(inner)
        if not any(not s.problem for s in out):
            sub.problem = "a zip with no workbook inside: hand in the task's .xlsx"
            return []
        return out
    except (zipfile.BadZipFile, zipfile.LargeZipFile, NotImplementedError, EOFError,
            RuntimeError, ValueError) as error:
        sub.problem = f"a damaged zip ({type(error).__name__})"
        return []


class EngineBudget:
    """The LibreOffice seconds one grading run may spend, converting and recalculating
    together (RECALC_BUDGET): hostile files cost the run at most this."""

    def __init__(self, seconds=RECALC_BUDGET):
        self.deadline = time.monotonic() + seconds

    def left(self):
        return self.deadline - time.monotonic()


def convert_foreign(subs, scratch, progress=None, what="grade: converting to .xlsx",
                    budget=None):
    """.ods, .xls, .xlsb, .et, … made .xlsx by LibreOffice (within the run's engine
    ``budget``); a file it cannot convert keeps the reason."""
    pending = [s for s in subs if s.needs_conversion and not s.problem]
    if not pending:
        return
    with waiting(f"{what} ({len(pending)})", progress):
        for sub, output in zip(pending, _through_engine(pending, Path(scratch) / "convert",
                                                        budget or EngineBudget())):
            suffix = suffix_of(sub.relative)
            if isinstance(output, Path):
                sub.path, sub.needs_conversion = output, False
            else:
                sub.problem = f"a {suffix} file LibreOffice could not convert to .xlsx " \
                              f"({output})"


def _through_engine(subs, tmp, budget):
    """Each submission's file through LibreOffice, saved as .xlsx: the output path, or
    the reason in words.  All together first; where that fails or times out, one by
    one with RECALC_LIMIT s each, within what is ``left`` of the run's budget."""
    tmp = Path(tmp)
    staged = []
    for number, sub in enumerate(subs):
        target = tmp / "in" / f"{number:05d}{suffix_of(sub.path.name) or '.xlsx'}"
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(sub.path.read_bytes())
        staged.append(target)
    if budget.left() < 5:
        return [f"the run's LibreOffice time ({RECALC_BUDGET} s) was spent on other files"] \
            * len(staged)
    try:
        outputs = recalc.convert(staged, tmp / "batch",
                                 timeout=int(min(RECALC_LIMIT + 5 * len(staged),
                                                 budget.left())))
    except CrankbookError:
        outputs = [None] * len(staged)
    results = []
    for source, output in zip(staged, outputs):
        if output is not None and output.is_file():
            results.append(output)
            continue
        left = budget.left()
        if left < 5:
            results.append(f"the run's LibreOffice time ({RECALC_BUDGET} s) was spent on "
                           f"other files")
            continue
        try:
            results.append(recalc.convert([source], tmp / f"one-{source.stem}",
                                          timeout=min(RECALC_LIMIT, int(left)))[0])
        except CrankbookError as error:
            results.append(_safe_reason(error))
    return results


def _named_cells(book, prefix, shapes=None, labels=None):
    """name (without prefix) -> [(value, has formula)], every reference checked first.
    A table's block may have grown by rows the student inserted (up to EXTRA_ROWS);
    ``labels`` then gets the row labels beside it (column A of its rows)."""
    sheets = set(book.sheetnames)
    trace = MachineTrace(book)
    out = {}
    for name, text in book.defined_names.items():
        if not name.startswith(prefix):
            continue
        key = name[len(prefix):]
        try:
            found = parse_reference(name, text, sheets)
        except CrankbookError as error:
            raise Unreadable(str(error).split(": ", 1)[-1] if ": " in str(error)
                             else str(error)) from None
        cells = found.rows * found.cols
        if shapes is None and cells > 1:
            continue                         # only single cells are read (parameters, id)
        if shapes is not None and key not in shapes:
            continue                         # not an answer of the task: never read
        limit = shapes.get(key, MAX_CELLS) if shapes is not None else 1
        allowed = limit + EXTRA_ROWS if limit > 1 and found.cols == 1 else max(limit, 1)
        if cells > allowed or cells > MAX_CELLS:
            raise Unreadable(f"name {name} covers {cells} cells; the task gives it "
                             f"{limit}")
        values = book.values(found.sheet, found.min_row, found.min_col, found.max_row,
                             found.max_col)
        positions = [(r, c) for r in range(found.min_row, found.max_row + 1)
                     for c in range(found.min_col, found.max_col + 1)]
        formulas = [book.formula_at(found.sheet, r, c) for r, c in positions]
        # an answer whose value would be the machine's (CELL, INFO, the network, another
        # file — directly or down a chain of cells and names) is refused: its own
        # formula is kept as text, never its value
        refused = [formula is not None and trace.depends(found.sheet, r, c)
                   for formula, (r, c) in zip(formulas, positions)]
        values = [MachineDependent(f"={formula}"[:MAX_FORMULA_SHOWN]) if no else value
                  for value, formula, no in zip(values, formulas, refused)]
        out[key] = [(value, formula is not None and not no)
                    for value, formula, no in zip(values, formulas, refused)]
        if labels is not None and limit > 1 and found.min_col > 1:
            labels[key] = book.values(found.sheet, found.min_row, 1, found.max_row, 1)
    return out


def read(sub, shapes, path=None):
    """Fill ``sub`` from its file (or ``path``, a recalculated copy); never raises."""
    try:
        book = XlsxBook(path or sub.path)
        try:
            if book.custom_properties.get("crankbook_role") == "key":
                # the teacher must hear of it (whose key, by its parameters)
                sub.is_key = True
                sub.parameters = {k: cells[0][0] for k, cells in
                                  _named_cells(book, "p_").items() if len(cells) == 1}
                sub.problem = "not a crankbook student workbook (an answer key)"
                return
            labels = {}
            answers = _named_cells(book, "a_", shapes, labels)
            if not answers:
                sub.problem = "no a_ answer blocks: not a crankbook student workbook"
                return
            sub.answers = {k: [v for v, _ in cells] for k, cells in answers.items()}
            sub.row_labels = labels
            sub.parameters = {k: cells[0][0] for k, cells in _named_cells(book, "p_").items()
                              if len(cells) == 1}
            sub.metadata = dict(book.core_properties)
            ident = _named_cells(book, "s_").get("student_id")
            sub.inside_id = str(ident[0][0]).strip()[:64] if ident and ident[0][0] is not None \
                else None
            sub.needs_recalc = any(value is None and formula for cells in answers.values()
                                   for value, formula in cells)
        finally:
            book.close()
    except Unreadable as reason:
        sub.problem = str(reason)
    except RecursionError:
        sub.problem = "cannot be read (nested too deeply)"
    except MemoryError:
        sub.problem = "cannot be read (too large)"
    except Exception as error:      # a file no one foresaw: it alone is unreadable
        sub.problem = f"cannot be read ({type(error).__name__})"


def _safe_reason(error):
    text = str(error)
    return re.sub(r"(/[^\s:]+)+", "…", text)[:200]


def recalculate(subs, shapes, progress=None, what="grade: recalculating in LibreOffice",
                budget=None):
    """Recalculate the submissions saved without values, one bad file costing only
    itself."""
    pending = [s for s in subs if s.needs_recalc and not s.problem]
    if not pending:
        return
    with temporary_directory("grade") as tmp, waiting(f"{what} ({len(pending)})", progress):
        for sub, output in zip(pending, _through_engine(pending, Path(tmp),
                                                        budget or EngineBudget())):
            if not isinstance(output, Path):
                sub.problem = f"saved without values, and LibreOffice could not " \
                              f"recalculate it ({output})"
                continue
            read(sub, shapes, path=output)
            if not sub.problem and sub.needs_recalc:
                sub.needs_recalc = False
