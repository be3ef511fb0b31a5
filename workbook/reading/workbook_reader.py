"""Read a workbook crankbook wrote back into a Results, through its defined names.

Every name's reference is checked against the shape the template gives it before
a cell is touched (no whole rows, columns or sheets, no other files, no missing
sheets), so a damaged or hostile file costs one clear error, not the machine.
"""
import json
import re
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from crankbook.errors import (CrankbookError, StaleWorkbookWarning, UncalculatedWorkbookWarning,
                              WorkbookReadError)
from crankbook.spec.evaluate import MAX_ROWS
from crankbook.reading.xlsx_reader import RECALCULATED_SCALE, Unreadable, XlsxBook
from crankbook.spec.loader import load as load_spec, template_names
from crankbook.support.paths import require_file
from crankbook.writer.build import (PROPERTY_ASSIGNMENT, PROPERTY_PRESET, PROPERTY_ROLE,
                                    PROPERTY_STEPS, PROPERTY_TEMPLATE)

CELL_REF = re.compile(r"\$?([A-Z]{1,3})\$?([0-9]{1,7})\Z")
MAX_NAME_CELLS = (MAX_ROWS + 1) * 64
MAX_SHEET_ROWS, MAX_SHEET_COLS = 1_048_576, 16_384


@dataclass(frozen=True)
class Range:
    sheet: str
    min_row: int
    min_col: int
    max_row: int
    max_col: int

    @property
    def rows(self):
        return self.max_row - self.min_row + 1

    @property
    def cols(self):
        return self.max_col - self.min_col + 1


def _column_number(letters):
    number = 0
    for char in letters:
        number = number * 26 + ord(char) - 64
    return number


def _cell(text):
    match = CELL_REF.match(text)
    if not match:
        return None
    col, row = _column_number(match.group(1)), int(match.group(2))
    if not (1 <= row <= MAX_SHEET_ROWS and 1 <= col <= MAX_SHEET_COLS):
        return None
    return row, col


def parse_reference(name, text, sheets):
    """The Range of a defined name's text ('Sheet'!$A$1:$B$9), or WorkbookReadError
    naming the name and what is wrong with it."""
    text = (text or "").strip().lstrip("=")
    if text.startswith("'"):
        end = 1
        while True:
            end = text.find("'", end)
            if end == -1:
                raise WorkbookReadError(f"name {name}: unterminated quote in its reference")
            if text[end + 1:end + 2] == "'":
                end += 2
                continue
            break
        sheet, rest = text[1:end].replace("''", "'"), text[end + 1:]
    else:
        sheet, _, rest = text.partition("!")
        rest = "!" + rest if rest else ""
    if not rest.startswith("!"):
        raise WorkbookReadError(f"name {name}: its reference {text[:60]!r} names no sheet")
    if "[" in sheet or "]" in sheet:
        raise WorkbookReadError(f"name {name}: refers to another file")
    if sheet not in sheets:
        raise WorkbookReadError(f"name {name}: refers to sheet {sheet!r}, which the workbook "
                                f"does not have")
    first, _, last = rest[1:].partition(":")
    start, stop = _cell(first), _cell(last or first)
    if start is None or stop is None:
        raise WorkbookReadError(f"name {name}: {rest[1:60]!r} is not a cell or a block of "
                                f"cells (whole rows, columns and sheets are refused)")
    (r0, c0), (r1, c1) = start, stop
    if r1 < r0 or c1 < c0:
        raise WorkbookReadError(f"name {name}: reversed range {rest[1:60]!r}")
    found = Range(sheet, r0, c0, r1, c1)
    if found.rows * found.cols > MAX_NAME_CELLS:
        raise WorkbookReadError(f"name {name}: {found.rows * found.cols} cells, more than any "
                                f"crankbook workbook has")
    return found


def defined_ranges(book, prefixes=("p_", "q_")):
    """name -> Range for every defined name with a given prefix."""
    sheets = set(book.sheetnames)
    out = {}
    for name, text in book.defined_names.items():
        if name.startswith(prefixes):
            out[name] = parse_reference(name, text, sheets)
    return out


def _block(read, book, found):
    try:
        return read(found.sheet, found.min_row, found.min_col, found.max_row, found.max_col)
    except Unreadable as reason:
        raise WorkbookReadError(f"{book.path}: {reason}") from None


def cells(book, found):
    """The cell values of a Range, row by row."""
    return _block(book.values, book, found)


def formulas(book, found):
    """True for each cell of a Range that holds a formula."""
    return _block(book.has_formulas, book, found)


def open_book(path):
    """A checked, bounded XlsxBook, or WorkbookReadError with the reason.

    A workbook someone opens with crankbook (verify, audit, export, read) may well
    have been saved by a spreadsheet engine, which writes each shared formula out in
    full: LibreOffice saves the inline-6 at 23 MB, 260 MB unpacked. So it is read with
    the larger limits of RECALCULATED_SCALE, as an engine's recalculated copy is; the
    limits stay bounded. A class's files (grade, check) are read with the plain limits:
    a hundred files from many hands."""
    path = Path(path)
    require_file(path, WorkbookReadError)
    try:
        return XlsxBook(path, scale=RECALCULATED_SCALE)
    except Unreadable as reason:
        raise WorkbookReadError(f"{path}: {reason}") from None


def template_of(book, ranges):
    """The template that wrote the workbook: its document property, else the one
    template whose parameters are all among the file's p_ names."""
    recorded = _property(book, PROPERTY_TEMPLATE)
    if recorded in template_names():
        return recorded
    keys = {n[2:] for n in ranges if n.startswith("p_")}
    for name in template_names():
        try:
            if {p.key for p in load_spec(name).parameters} <= keys:
                return name
        except CrankbookError:
            continue
    raise WorkbookReadError(f"{book.path}: has no p_ and q_ names of a crankbook template; "
                            f"was it written by crankbook?")


def _property(book, name, default=None):
    return book.custom_properties.get(name, default)


def _number(value):
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    return float(value)


def read_inputs(book, spec, ranges, path):
    """(values, tables, grids) as stored in the workbook."""
    values = {}
    for p in spec.parameters:
        name = f"p_{p.key}"
        if name not in ranges:
            # a workbook written before this input existed: its default is the
            # behaviour the earlier version computed with
            values[p.key] = list(p.default) if p.axis else p.default
            continue
        found = ranges[name]
        if p.axis:
            if found.cols != 1 or found.rows > spec.axis[p.axis].max:
                raise WorkbookReadError(f"{path}: name {name} is not a column of at most "
                                        f"{spec.axis[p.axis].max} cells")
            raw = cells(book, found)
            numbers = [_number(v) for v in raw]
            if any(v is None for v in numbers):
                raise WorkbookReadError(f"{path}: {name} holds {raw!r}, not numbers")
            values[p.key] = numbers
            continue
        if found.rows * found.cols != 1:
            raise WorkbookReadError(f"{path}: name {name} is not a single cell")
        raw = cells(book, found)[0]
        if p.kind == "choice":
            if p.choice_number(raw) is None:
                raise WorkbookReadError(f"{path}: {name} holds {raw!r}, not one of "
                                        f"{', '.join(p.choices)}")
            values[p.key] = float(p.choice_number(raw))
        else:
            number = _number(raw)
            if number is None:
                raise WorkbookReadError(f"{path}: parameter {name} holds {raw!r}, not a number")
            values[p.key] = number
    tables = {}
    for key, table_column in spec.table_column.items():
        found = ranges.get(f"p_{key}")
        if found is None:
            raise WorkbookReadError(f"{path}: the defined name p_{key} is missing")
        width = found.cols if table_column.items else 1
        widest = spec.axis[table_column.items].max if table_column.items else 1
        if found.cols > widest or found.rows > 200_000:
            raise WorkbookReadError(f"{path}: name p_{key} is not "
                                    + ("a block of traces" if table_column.items
                                       else "one column of a trace"))
        numbers = [_number(v) for v in cells(book, found)]
        if table_column.items:      # one column per item: the rows where every one is a number
            rows = [numbers[i:i + width] for i in range(0, len(numbers), width)]
            tables[key] = np.array([r for r in rows if None not in r], dtype=float) \
                .reshape(-1, width)
        else:
            tables[key] = np.array([v for v in numbers if v is not None], dtype=float)
    grids = {}
    for grid in spec.grids:
        if not grid.is_numeric_grid:
            continue
        found = ranges.get(f"q_{grid.key}")
        if found is None or found.cols != 1 or found.rows > MAX_ROWS + 1:
            raise WorkbookReadError(f"{path}: the grid q_{grid.key} is missing or not one column")
        column = np.array([_number(v) if _number(v) is not None else np.nan
                           for v in cells(book, found)], dtype=float)
        if column.size < 2 or np.isnan(column).any():
            raise WorkbookReadError(f"{path}: the grid q_{grid.key} is not numeric")
        grids[grid.key] = column
    return values, tables, grids


def expected_shape(spec, key, grid_rows, sizes):
    """The (rows, cols) a q_ name of ``key`` must have."""
    q = spec.quantity[key]
    cols = sizes.get(q.items, 1) if q.items else 1
    if q.is_series:
        return grid_rows[q.grid], cols
    return (cols, 1) if q.items else (1, 1)


def read_results(book, spec, ranges, path, sizes, grid_rows):
    """q_<key> -> values as stored, shaped as the template says (a mismatch is an error)."""
    out = {}
    for q in spec.quantities():
        name = f"q_{q.key}"
        found = ranges.get(name)
        if found is None:
            continue
        rows, cols = expected_shape(spec, q.key, grid_rows, sizes)
        if (found.rows, found.cols) != (rows, cols):
            raise WorkbookReadError(f"{path}: name {name} covers {found.rows}×{found.cols} cells; "
                                    f"the {spec.key} template gives it {rows}×{cols}")
        out[name] = cells(book, found)
    return out


def grid_rows_of(spec, ranges, grids):
    rows = {key: len(values) for key, values in grids.items()}
    for grid in spec.grids:
        if grid.key not in rows:
            found = ranges.get(f"q_{grid.key}")
            if found is None or found.cols != 1 or found.rows > MAX_ROWS + 1:
                raise WorkbookReadError(f"the grid q_{grid.key} is missing or not one column")
            rows[grid.key] = found.rows
    return rows


def role_of(book, ranges):
    """(role, assignment): what crankbook wrote the file as — "workbook", "key" (an
    answer key) or "student" (a student's answer workbook: a_ names, no q_ names) —
    and the assignment of a key or student workbook."""
    role = _property(book, PROPERTY_ROLE)
    if role is None:             # written before the property: tell by the names
        has_answers = any(n.startswith("a_") for n in ranges)
        role = "student" if has_answers and not any(n.startswith("q_") for n in ranges) \
            else "workbook"
    return role, _property(book, PROPERTY_ASSIGNMENT)


def load_named(path):
    """(book, spec, template, ranges, values, tables, grids, sizes, grid rows)."""
    from crankbook.spec.evaluate import axis_sizes
    from crankbook.spec.params import fit_derived_items
    book = open_book(path)
    ranges = defined_ranges(book)
    role, assignment = role_of(book, ranges)
    if role == "student":
        raise WorkbookReadError(
            f"{path}: a crankbook student workbook (assignment {assignment or '?'}): it holds "
            f"a student's answers (a_ names), not results; grade it against its key with "
            f"'crankbook grade'")
    template = template_of(book, ranges)
    spec = load_spec(template)
    values, tables, grids = read_inputs(book, spec, ranges, path)
    try:
        sizes = axis_sizes(spec, values)
        values = fit_derived_items(spec, values, sizes)      # a missing column's default
    except CrankbookError as error:
        raise WorkbookReadError(f"{path}: {error}") from None
    return book, spec, template, ranges, values, tables, grids, sizes, grid_rows_of(
        spec, ranges, grids)


def saved_without_values(book, spec, ranges):
    """True when the template's formula cells carry no stored results (e.g. written by
    openpyxl); only the template's own names are looked at, one cell each, and an
    unguarded one first: a guarded result is blank by design while the inputs break a
    rule, which a calculated workbook may well hold."""
    quantities = sorted(spec.quantities(), key=lambda q: q.guard)
    for q in quantities:
        found = ranges.get(f"q_{q.key}")
        if found is None or q.formula is None:
            continue
        first = Range(found.sheet, found.min_row, found.min_col, found.min_row, found.min_col)
        if formulas(book, first)[0]:
            return cells(book, first)[0] is None
    return False


def stored_results(path, computed=None):
    """The fields of a crankbook.results.Results holding the workbook's own values, or
    with ``computed`` (recalc.computed_values' item for it) the values an engine
    computed for it. A file saved without calculated values (openpyxl writes formulas
    only) and read as it is reads as NaN: a CrankbookWarning says so in one line."""
    from crankbook.reading.compare import as_array
    named = load_named(path)
    book, spec, template, ranges, values, tables, grids, sizes, grid_rows = named
    uncalculated = computed is None and saved_without_values(book, spec, ranges)
    if uncalculated:
        warnings.warn(f"{Path(path).name} holds no calculated values (saved by a program "
                      f"that does not calculate, such as openpyxl): its q_ values read as NaN; "
                      f"read it with recalculate=True", UncalculatedWorkbookWarning,
                      stacklevel=2)
    stored = read_results(book if computed is None else computed, spec, ranges, path, sizes,
                          grid_rows)
    if computed is None and not uncalculated:
        # results read as stored must be the file's own inputs' (numpy's, 0.4 s of a read)
        from crankbook.reading.verification import first_stale
        stale = first_stale(named, stored)
        if stale is not None:
            warnings.warn(StaleWorkbookWarning(
                f"{Path(path).name} holds results its inputs no longer give ({stale}: an "
                f"input changed without recalculating?): read it with recalculate=True",
                stale), stacklevel=2)
    results = {}
    for q in spec.quantities():
        raw = stored.get(f"q_{q.key}")
        if raw is None:
            continue
        array = as_array(raw)
        rows, cols = expected_shape(spec, q.key, grid_rows, sizes)
        if q.is_series:
            results[q.key] = array.reshape(rows, cols) if q.items else array
        elif q.items:
            results[q.key] = array
        else:
            results[q.key] = float(array[0])
    for key, value in grids.items():
        results[key] = value
    steps = json.loads(_property(book, PROPERTY_STEPS, "{}") or "{}")
    preset = {"name": _property(book, PROPERTY_PRESET, "?"), "zh": "", "en": "",
              "template": template}
    return dict(spec=spec, template=template, preset=preset, values=values, tables=tables,
                steps=steps, results=results, axis_sizes=sizes)
