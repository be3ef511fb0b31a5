"""Check a workbook's formulas in a real spreadsheet engine against numpy.

The engine recalculates the file (LibreOffice with recalculation forced, or
Gnumeric) and writes the values it computed (recalc.computed_values: every sheet as
CSV, half the engine's time of saving the workbook); every q_ name, read there through
the workbook's own defined names, is compared by crankbook.reading.compare's one rule
with the calc functions evaluated on the workbook's own inputs.
"""
from concurrent.futures import ThreadPoolExecutor

from crankbook.spec import params

from crankbook.reading import recalc
from crankbook.reading.compare import compare, noise_floors
from crankbook.errors import CrankbookError, WorkbookReadError
from crankbook.spec.evaluate import evaluate
from crankbook.reading.workbook_reader import load_named, read_results
from crankbook.support.progress import steps, waiting
from crankbook.support.workspace import temporary_directory


def expected_values(spec, values, tables, grids, layout=None):
    """(numpy results, rounding floors) for the inputs, or (None, None) when the inputs
    break a rule (then the sheet must be blank, and q_inputs_valid 0); ``layout``: the
    workbook's grid rows (its computed grids keep the rows they were built with)."""
    try:
        params.validate(spec, dict(values), tables=tables, grids=grids, layout=layout)
    except CrankbookError:
        return None, None
    expected = evaluate(spec, values, tables, grids, layout=layout)
    return expected, noise_floors(spec, values, tables, grids)


def verify_workbook(path, engine="libreoffice", workdir=None, progress=None):
    """A DataFrame of per-name comparisons (see crankbook.verify)."""
    return verify_workbooks([path], engine, workdir, progress)[0]


def verify_workbooks(paths, engine="libreoffice", workdir=None, progress=None):
    """One DataFrame per workbook, every workbook recalculated in one engine start.
    The engine runs while the workbooks' own cached values are read and numpy
    evaluates their inputs, so the two cost as long as the longer of them."""
    recalc.require_engine(engine)               # a missing engine says so at once
    opened = [(path, load_named(path))          # a file that is no workbook fails here,
              for path in steps(paths, "verify: opening", progress=progress)]  # engine idle
    frames = []
    with temporary_directory("verify", workdir) as tmp:
        with ThreadPoolExecutor(max_workers=1) as pool:
            cancel = recalc.Cancel()
            engine_run = pool.submit(recalc.computed_values, paths, tmp, engine=engine,
                                     cancel=cancel)
            try:
                loaded = [_loaded(path, named) for path, named in
                          steps(opened, "verify: reading", progress=progress)]
                with waiting(f"verify: recalculating {len(paths)} workbook(s) in {engine}",
                             progress):
                    converted = engine_run.result()
            except BaseException:
                cancel.cancel()               # Ctrl-C or a bad file: do not wait for it
                raise
        for (path, named, cached, expected), after in steps(
                list(zip(loaded, converted)), "verify: comparing", progress=progress):
            frames.append(_compared(path, named, cached, expected, after, engine))
    return frames


def stale_result(path):
    """The first q_ name whose stored values do not follow the workbook's own inputs
    (edited with calculation set to manual, or a script that typed an input), or None:
    no recalculation, numpy against the file as saved.  A file whose inputs break a
    rule gives None when its results are blank, as they are by design (what reads them
    says so), and q_inputs_valid when it still holds the results of valid inputs."""
    named = load_named(path)
    _, _, cached, _ = _loaded(path, named)
    return first_stale(named, cached)


def first_stale(named, cached):
    """``stale_result`` for a workbook already loaded (``load_named``) and its stored
    q_ values (``read_results``): what ``read`` checks without a second load."""
    book, spec, template, ranges, values, tables, grids, sizes, grid_rows = named
    if not cached:
        return None
    expected, floors = expected_values(spec, values, tables, grids, layout=grid_rows)
    if expected is None:
        # the inputs break a rule, so the sheets must be blank: a file that still says
        # its inputs are valid holds the results of the inputs before the one typed
        return "q_inputs_valid" if _single(book, ranges, "q_inputs_valid") == 1 else None
    for comparison in compare(spec, expected, cached, floors):
        if comparison.name in ranges and not comparison.ok:
            return comparison.name
    return None


def _loaded(path, named):
    """A workbook's cached values and numpy's values for its inputs."""
    book, spec, template, ranges, values, tables, grids, sizes, grid_rows = named
    cached = read_results(book, spec, ranges, path, sizes, grid_rows)
    if not cached:
        raise WorkbookReadError(
            f"{path}: has no q_ names, so nothing to verify (a student workbook "
            f"is checked with 'crankbook grade')")
    expected = expected_values(spec, values, tables, grids, layout=grid_rows)
    return path, named, cached, expected


def _compared(path, named, cached, expected_floors, computed, engine):
    """``computed``: the engine's values (engine_values.ComputedValues), read through
    the names of the workbook it computed."""
    book, spec, template, ranges, values, tables, grids, sizes, grid_rows = named
    recalculated = read_results(computed, spec, ranges, path, sizes, grid_rows)
    status = _single(computed, ranges, "q_input_status")
    valid = _single(computed, ranges, "q_inputs_valid")
    expected, floors = expected_floors
    rows = []
    if expected is not None:
        now = {c.name: c for c in compare(spec, expected, recalculated, floors)}
        stored = {c.name: c for c in compare(spec, expected, cached, floors)}
        for name, c in now.items():
            # a name this crankbook computes that the file does not define: a workbook
            # built before the quantity existed (or one whose name was deleted) — not
            # verified, and said so rather than reported as an infinite difference
            rows.append({"name": name, "unit": c.unit, "cells": c.cells, "error": c.error,
                         "allowed": c.allowed, "ratio": c.ratio,
                         "cached_ratio": stored[name].ratio, "ok": c.ok,
                         "absent": name not in ranges})
    import pandas as pd           # only here: the command line starts without it
    frame = pd.DataFrame(rows, columns=["name", "unit", "cells", "error", "allowed", "ratio",
                                        "cached_ratio", "ok", "absent"])
    frame.attrs.update({"status": status, "valid": valid, "template": template,
                        "engine": engine, "inputs_break_rules": expected is None,
                        "path": str(path)})
    return frame


def _single(book, ranges, name):
    from crankbook.reading.workbook_reader import cells
    found = ranges.get(name)
    return cells(book, found)[0] if found is not None else None
