"""Check a workbook's formulas in a real spreadsheet engine against numpy.

The engine recalculates the file (LibreOffice with recalculation forced, or
Gnumeric); every q_ name read back is compared, by crankbook.compare's one rule,
with the calc functions evaluated on the workbook's own inputs.
"""

import pandas as pd

from crankbook import params, recalc
from crankbook.compare import compare, noise_floors
from crankbook.errors import CrankbookError, WorkbookReadError
from crankbook.evaluate import evaluate
from crankbook.workbook_reader import load_named, open_book, defined_ranges, read_results
from crankbook.workspace import temporary_directory


def expected_values(spec, values, tables, grids):
    """(numpy results, rounding floors) for the inputs, or (None, None) when the inputs
    break a rule (then the sheet must be blank, and q_inputs_valid 0)."""
    try:
        params.validate(spec, dict(values), tables=tables, grids=grids)
    except CrankbookError:
        return None, None
    expected = evaluate(spec, values, tables, grids)
    return expected, noise_floors(spec, values, tables, grids)


def verify_workbook(path, engine="libreoffice", workdir=None):
    """A DataFrame of per-name comparisons (see crankbook.verify)."""
    book, spec, template, ranges, values, tables, grids, sizes, grid_rows = load_named(path)
    cached = read_results(book, spec, ranges, path, sizes, grid_rows)
    if not cached:
        raise WorkbookReadError(f"{path}: has no q_ names, so nothing to verify (a student "
                                f"workbook is checked with 'crankbook grade')")
    with temporary_directory("verify", workdir) as tmp:
        converted = recalc.convert([path], tmp, engine=engine)[0]
        book_after = open_book(converted)
        ranges_after = defined_ranges(book_after)
        recalculated = read_results(book_after, spec, ranges_after, path, sizes, grid_rows)
        status = _single(book_after, ranges_after, "q_input_status")
        valid = _single(book_after, ranges_after, "q_inputs_valid")
    expected, floors = expected_values(spec, values, tables, grids)
    rows = []
    if expected is not None:
        now = {c.name: c for c in compare(spec, expected, recalculated, floors)}
        stored = {c.name: c for c in compare(spec, expected, cached, floors)}
        for name, c in now.items():
            rows.append({"name": name, "unit": c.unit, "cells": c.cells, "error": c.error,
                         "allowed": c.allowed, "ratio": c.ratio,
                         "cached_ratio": stored[name].ratio, "ok": c.ok})
    frame = pd.DataFrame(rows, columns=["name", "unit", "cells", "error", "allowed", "ratio",
                                        "cached_ratio", "ok"])
    frame.attrs.update({"status": status, "valid": valid, "template": template,
                        "engine": engine, "inputs_break_rules": expected is None})
    return frame


def _single(book, ranges, name):
    from crankbook.workbook_reader import cells
    found = ranges.get(name)
    return cells(book, found)[0] if found is not None else None
