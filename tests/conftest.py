"""Shared fixtures.  The spreadsheet-engine tests fail, never skip, when LibreOffice
or Gnumeric is missing: the cross-checks are the point of the suite, and ./dev test
installs both."""
import contextlib
import copy
import html
import io
import os
import re
import subprocess
import sys
import traceback
import zipfile
from pathlib import Path

import openpyxl
import pytest
from openpyxl.utils import coordinate_to_tuple, get_column_letter

from crankbook.reading.recalc import find_soffice, find_ssconvert
from crankbook.reading.workbook_reader import cells, defined_ranges, open_book

ROOT = Path(__file__).resolve().parent.parent


def _engine(find, what, package):
    path = find()
    if path is None:
        pytest.fail(f"{what} is not installed: run ./dev test, or apt-get install {package}")
    return path


def dev_programs():
    """{program: Debian package} of every external program ./dev test installs (its
    PROGRAMS list: the one place that says which package brings which program)."""
    text = (ROOT / "dev").read_text(encoding="utf-8")
    listed = re.search(r'^PROGRAMS="([^"]*)"', text, re.M).group(1)
    return dict(pair.split(":", 1) for pair in listed.split())


def run_program(program, *args):
    """Run an external program the tests need (pdftotext, …) and return its standard
    output; fail in one line naming the package when the machine lacks it."""
    import shutil
    if shutil.which(program) is None:
        package = dev_programs().get(program, "the package that provides it")
        pytest.fail(f"{program} is not installed: run ./dev test, or apt-get install {package}",
                    pytrace=False)
    return subprocess.run([program, *map(str, args)], capture_output=True, text=True,
                          check=True).stdout


ENGINE_FIXTURES = {"soffice": "libreoffice", "ssconvert": "gnumeric",
                   "checked": ("libreoffice", "gnumeric")}


@pytest.hookimpl(tryfirst=True)     # before xdist reads the groups into the node ids
def pytest_collection_modifyitems(items):
    """Mark every test that reaches a spreadsheet engine (``./dev test --quick`` leaves
    them out) and group tests for the workers: the users of the shared cross-check
    fixture together (it is built once per worker), a file with module fixtures on
    one worker; every other test goes wherever a worker is free."""
    for item in items:
        used = set(getattr(item, "fixturenames", ()))
        for fixture, marks in ENGINE_FIXTURES.items():
            if fixture in used:
                for mark in (marks if isinstance(marks, tuple) else (marks,)):
                    item.add_marker(getattr(pytest.mark, mark))
        if "checked" in used:
            item.add_marker(pytest.mark.xdist_group("checked"))
        elif _module_fixtures(item):        # built once per worker: keep the file together
            item.add_marker(pytest.mark.xdist_group(item.nodeid.split("::")[0]))


def _module_fixtures(item):
    info = getattr(item, "_fixtureinfo", None)
    return info is not None and any(
        definitions[-1].scope == "module" for definitions in info.name2fixturedefs.values())


@pytest.fixture(scope="session")
def soffice():
    return _engine(find_soffice, "LibreOffice (soffice)", "libreoffice-calc-nogui")


@pytest.fixture(scope="session")
def ssconvert():
    return _engine(find_ssconvert, "Gnumeric (ssconvert)", "gnumeric")


def run_cli(*args, cwd=None, timeout=None, stdin=None):
    """Run the command line as a user would; returns a CompletedProcess.

    In this process (crankbook.cli.main, stdout and stderr captured, an exception
    turned into exit 1 and its traceback, as Python would print it): a new Python
    per call would cost half a second of imports and template loading, a third of
    the quick suite.  A separate ``python -m crankbook`` where the call needs one —
    another directory, input on stdin, a time limit (a run that could hang) — or
    everywhere with CRANKBOOK_TEST_SUBPROCESS=1."""
    argv = [str(a) for a in args]
    if cwd is not None or stdin is not None or timeout is not None or \
            os.environ.get("CRANKBOOK_TEST_SUBPROCESS") or Path.cwd() != ROOT:
        return subprocess.run([sys.executable, "-m", "crankbook", *argv], capture_output=True,
                              text=True, cwd=cwd or ROOT, timeout=timeout or 600, input=stdin)
    from crankbook import cli
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = cli.main(argv)
        except SystemExit as exit_:              # argparse: --help, usage errors
            code = exit_.code if isinstance(exit_.code, int) else (0 if exit_.code is None
                                                                   else 1)
        except Exception:                        # what Python would print and exit with
            traceback.print_exc()
            code = 1
    return subprocess.CompletedProcess(["crankbook", *argv], code, out.getvalue(),
                                       err.getvalue())


_NAMED = {}


def named(path, prefixes=("p_", "q_"), only=None):
    """name -> value (one cell) or list of values, of a workbook's defined names
    (``only``: just these names — only their sheets are parsed; remembered per file
    version: many tests read the same key workbooks)."""
    stat = Path(path).stat()
    only = tuple(sorted(only)) if only else None
    memo = (str(Path(path).resolve()), stat.st_mtime_ns, stat.st_size, tuple(prefixes), only)
    if memo not in _NAMED:
        _NAMED[memo] = _read_named(path, only or prefixes, only)
    return copy.deepcopy(_NAMED[memo])


def _read_named(path, prefixes, only=None, computed=None):
    book = open_book(path)
    source = computed if computed is not None else book
    out = {}
    for name, found in defined_ranges(book, prefixes).items():
        if only and name not in only:
            continue
        values = cells(source, found)
        out[name] = values[0] if found.rows * found.cols == 1 else values
    return out


class Recalculated:
    """A workbook as LibreOffice recalculates it, read from the engine's values
    (recalc.computed_values): ``names`` as ``named`` gives them, ``cell(sheet, row,
    col)`` any cell — no saved copy for openpyxl to load."""

    def __init__(self, path, tmp, engine="libreoffice"):
        from crankbook.reading import recalc
        self.path = Path(path)
        self.values = recalc.computed_values([path], Path(tmp), engine=engine)[0]
        self.names = named_computed(path, self.values)
        book = open_book(path)
        self.sheetnames = book.sheetnames           # in the workbook's order
        book.close()

    def cell(self, sheet, row, col):
        return self.values.values(sheet, row, col, row, col)[0]


def named_computed(path, computed, prefixes=("p_", "q_")):
    """``named`` of the workbook ``path``, with the values an engine computed for it
    (a recalc.computed_values item) in place of the ones stored in the file."""
    return _read_named(path, prefixes, computed=computed)


def edit_cells(source, target, edits, tables=None):
    """Save ``source`` as ``target`` with input cells changed as a user would type them:
    ``edits`` key -> value (a list for a per-item parameter), ``tables`` key -> column.

    Only the typed cells' XML changes — the formula cells keep their (now stale) cached
    values, as in a file saved before recalculation — so the engines do the same work
    as on a built file (an openpyxl round trip, which drops every cached value, makes
    LibreOffice's load twice as slow) and a stale value left unrecalculated fails."""
    book = openpyxl.load_workbook(source, read_only=True)
    sheet_files = _sheet_files(source)
    changes = {}                                    # part -> {cell ref: new value}
    for key, value in {**edits, **(tables or {})}.items():
        sheet, ref = next(iter(book.defined_names[f"p_{key}"].destinations))
        refs = [f"{get_column_letter(col)}{row}" for row, col in _cells_of(ref)]
        column = list(value) if hasattr(value, "__len__") and not isinstance(value, str) \
            else [value]
        for cell, new in zip(refs, column + [None] * len(refs)):
            changes.setdefault(sheet_files[sheet], {})[cell] = new
    book.close()
    with zipfile.ZipFile(source) as zin, zipfile.ZipFile(target, "w", zipfile.ZIP_DEFLATED) as zout:
        for item in zin.infolist():
            data = zin.read(item.filename)
            if item.filename in changes:
                data = _retype(data.decode(), changes[item.filename]).encode()
            zout.writestr(item, data)


def _sheet_files(path):
    """sheet name -> its part in the package (through workbook.xml and its rels)."""
    with zipfile.ZipFile(path) as z:
        sheets = re.findall(r'<sheet [^>]*name="([^"]+)"[^>]*r:id="([^"]+)"',
                            z.read("xl/workbook.xml").decode())
        rels = re.findall(r"<Relationship [^>]*>", z.read("xl/_rels/workbook.xml.rels").decode())
    targets = {re.search(r' Id="([^"]+)"', rel).group(1):
               re.search(r' Target="([^"]+)"', rel).group(1) for rel in rels}
    return {html.unescape(name): "xl/" + targets[rid].lstrip("/").removeprefix("xl/")
            for name, rid in sheets}


def legend_names(path):
    """[(cell reference, cached text)] of every chart series name given by a cell."""
    with zipfile.ZipFile(path) as z:
        xml = "".join(z.read(n).decode() for n in sorted(z.namelist())
                      if n.startswith("xl/charts/chart"))
    return re.findall(r"<c:tx><c:strRef><c:f>([^<]+)</c:f><c:strCache>.*?<c:v>([^<]*)</c:v>",
                      xml)


def text_formulas(path, holding):
    """{(sheet, row, col): cached text} of every text formula cell whose formula holds
    ``holding`` (1-based row and column, as ComputedValues.values takes them)."""
    out = {}
    with zipfile.ZipFile(path) as z:
        for sheet, part in _sheet_files(path).items():
            xml = z.read(part).decode()
            for ref, formula, value in re.findall(
                    r'<c r="([A-Z]+[0-9]+)"[^>]*t="str"[^>]*><f>([^<]*)</f><v>([^<]*)</v>', xml):
                if holding in html.unescape(formula):
                    out[(sheet, *coordinate_to_tuple(ref))] = html.unescape(value)
    return out


def unwrapped_texts(ws, **bounds):
    """(cell, its merged span or None) of every text of ``ws`` that does not wrap (a
    formula's text excepted), within iter_rows' ``bounds``: such a text runs on into
    the empty cells to its right and is cut where they end."""
    merged = {(r.min_row, r.min_col): r for r in ws.merged_cells.ranges}
    for row in ws.iter_rows(**bounds):
        for cell in row:
            if isinstance(cell.value, str) and not cell.value.startswith("=") and \
                    not (cell.alignment and cell.alignment.wrap_text):
                yield cell, merged.get((cell.row, cell.column))


def column_width(ws, col):
    """Characters of a column's width (Excel's default where none is set)."""
    return ws.column_dimensions[get_column_letter(col)].width or 8.43


def texts_cut_by_a_neighbour(path):
    """(sheet, cell, text) of every unwrapped text wider than its column (or merged
    span) whose right neighbour holds a value: the engines stop it at the column's
    edge, on the screen and on paper.  Widths by print_setup's glyph model (Arial
    10); a key's monospaced glyphs are wider, as KEY_COLUMNS_PER_CHARACTER says."""
    from crankbook.writer.print_setup import KEY_COLUMNS_PER_CHARACTER, text_lines
    book, cut = openpyxl.load_workbook(path), []
    for ws in book.worksheets:
        inside = {(row, col) for r in ws.merged_cells.ranges
                  for row in range(r.min_row, r.max_row + 1)
                  for col in range(r.min_col, r.max_col + 1)}
        for cell, span in unwrapped_texts(ws):
            cols = range(span.min_col, span.max_col + 1) if span else [cell.column]
            neighbour = (cell.row, cols[-1] + 1)
            if ws.cell(*neighbour).value in (None, "") and neighbour not in inside:
                continue
            room = sum(column_width(ws, c) for c in cols)
            text = cell.value.split("\n")[0]
            monospaced = cell.font is not None and cell.font.name == "Consolas"
            if (monospaced and len(text) * KEY_COLUMNS_PER_CHARACTER + 1 > room) or \
                    (not monospaced and text_lines(text, room) > 1):
                cut.append((ws.title, cell.coordinate, text[:40]))
    return cut


def cells_under_charts(path):
    """(sheet, cell, value) of every written cell that a chart covers: a chart
    anchored over a table hides it on the screen and on paper.  The anchors are the
    file's own (xl/drawings), which the writer computed from the rows' heights."""
    book = openpyxl.load_workbook(path)
    hidden = []
    with zipfile.ZipFile(path) as z:
        for sheet, part in _sheet_files(path).items():
            folder, name = part.rsplit("/", 1)
            rels = f"{folder}/_rels/{name}.rels"
            if rels not in z.namelist():
                continue
            drawings = re.findall(r'Target="\.\./drawings/(drawing\d+\.xml)"',
                                  z.read(rels).decode())
            for drawing in drawings:
                xml = z.read(f"xl/drawings/{drawing}").decode()
                for anchor in re.findall(r"<xdr:twoCellAnchor.*?</xdr:twoCellAnchor>", xml,
                                         flags=re.S):
                    (c0, r0), (c1, r1) = [tuple(int(v) for v in re.search(
                        rf"<xdr:{end}><xdr:col>(\d+)</xdr:col>.*?<xdr:row>(\d+)</xdr:row>",
                        anchor, flags=re.S).groups()) for end in ("from", "to")]
                    ws = book[sheet]
                    for row in ws.iter_rows(min_row=r0 + 1, max_row=r1 + 1, min_col=c0 + 1,
                                            max_col=c1 + 1):
                        hidden += [(sheet, c.coordinate, c.value) for c in row
                                   if c.value not in (None, "")]
    return hidden


def _cells_of(ref):
    """(row, column) of every cell of an A1 reference such as $B$5 or $B$5:$B$9."""
    first, _, last = ref.replace("$", "").partition(":")
    (r0, c0), (r1, c1) = (coordinate_to_tuple(first), coordinate_to_tuple(last or first))
    return [(r, c) for r in range(r0, r1 + 1) for c in range(c0, c1 + 1)]


def _retype(xml, cells):
    """The sheet XML with each cell's constant replaced (a number, a string, or blank)."""
    def replace(match):
        ref, style = match.group(1), match.group(2) or ""
        new = cells.pop(ref)
        if new is None:
            return f'<c r="{ref}"{style}/>'
        if isinstance(new, str):
            return f'<c r="{ref}"{style} t="inlineStr"><is><t>{html.escape(new)}</t></is></c>'
        return f'<c r="{ref}"{style}><v>{float(new)!r}</v></c>'
    pattern = r'<c r="(%s)"( s="\d+")?(?: t="\w+")?(?:/>|>.*?</c>)' % "|".join(cells)
    xml = re.sub(pattern, replace, xml, flags=re.S)
    assert not cells, f"input cells not in the file (blank and unformatted?): {sorted(cells)}"
    return xml


@pytest.fixture(scope="session")
def checked(soffice, ssconvert, tmp_path_factory):
    """Every workbook of tests/cross_check.py, built and recalculated in both engines."""
    from tests.cross_check import build_all, recalculate_all
    tmp = tmp_path_factory.mktemp("cross-check")
    return recalculate_all(tmp, build_all(tmp))


def assert_build_refused_in_one_line(tmp_path, preset, sets, words):
    """``crankbook build --preset PRESET --set …`` in its own Python, as a user runs it:
    exit 2, one line holding ``words``, no traceback, no file written."""
    out = tmp_path / "bad.xlsx"
    args = [sys.executable, "-m", "crankbook", "build", "--preset", preset, "-o", str(out)]
    for value in sets:
        args += ["--set", value]
    run = subprocess.run(args, capture_output=True, text=True)
    assert run.returncode == 2, run.stderr
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and words in lines[0], run.stderr
    assert "Traceback" not in run.stderr and not out.exists()


def assert_slip_warned(preset, inputs, flag, words, step=5.0):
    """A legal value an engineer rarely means (a unit slip): ``compute`` sets the
    plausibility flag and warns in words naming the likely unit, and goes on; the
    preset's own values raise neither."""
    import warnings

    import crankbook
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        slipped = crankbook.compute(preset, step=step, **inputs)
    assert slipped.scalars[flag] == 1, flag
    messages = [str(w.message) for w in caught]
    assert any(words in m for m in messages), messages
    assert crankbook.compute(preset, step=step).scalars[flag] == 0
