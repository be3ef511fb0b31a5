"""Audit a workbook crankbook wrote: recompute from its p_ cells and report every
q_ cell whose stored value or formula no longer agrees, with its address.

The values are read as saved (Excel, LibreOffice, Gnumeric and WPS store them); a
formula replaced by a constant, an error value (#REF!, #NAME?, …), a cell saved
without a value, or a name whose range no longer has the template's shape is
reported too.  Agreement is crankbook.reading.compare's one rule, as in verify.

Two findings stand for many cells: a workbook whose inputs were changed without
recalculating (manual calculation, a script that wrote a value) — its results all
agree with the inputs it was built with (its preset's), so one finding names the
changed inputs and counts the stale cells per name — and a workbook of this
crankbook version from which an input name (``p_…``) was deleted (the file was
altered: never "every q_ cell agrees").  Many cells of one name that differ for no
reason found are one finding with their count and the first address.
"""
import math
from dataclasses import dataclass

import numpy as np
from openpyxl.utils.cell import get_column_letter

from crankbook.errors import WorkbookReadError
from crankbook.reading import recalc
from crankbook.reading.compare import allowances
from crankbook.reading.verification import expected_values
from crankbook.reading.workbook_reader import (cells, expected_shape, formulas, load_named,
                                              saved_without_values)
from crankbook.support.workspace import temporary_directory


DIFFERS = "value differs from the recomputation"
MISSING = "the defined name is missing"
GROUPED = 4                        # differing cells of one name shown one by one, at most
STORY = 0.9                        # share of them that must follow the built inputs


@dataclass
class CellFinding:
    address: str
    name: str
    stored: object
    expected: float
    problem: str
    index: int | None = None       # the cell's place in its name's range


def _addresses(found):
    for r in range(found.min_row, found.max_row + 1):
        for c in range(found.min_col, found.max_col + 1):
            yield f"'{found.sheet}'!{get_column_letter(c)}{r}"


def audit_workbook(path, workdir=None):
    """(spec, findings, recalculated, rule_message) for the workbook at ``path``.

    The file is opened once (one time limit for all of it); a file saved without
    values is recalculated in LibreOffice first, and its cells are then read from the
    values LibreOffice computed (recalc.computed_values).  When its inputs break a rule,
    the results that hang on them must be blank (``rule_message`` says why).
    """
    loaded = load_named(path)
    book, spec, ranges = loaded[0], loaded[1], loaded[3]
    recalculated = saved_without_values(book, spec, ranges)
    try:
        if recalculated:
            with temporary_directory("audit", workdir) as tmp:
                computed = recalc.computed_values([path], tmp)[0]
                return _audit(loaded, (computed, *loaded[1:]), recalculated)
        return _audit(loaded, loaded, recalculated)
    except (IndexError, ValueError, ZeroDivisionError, OverflowError) as error:
        # a damaged file whose grid or inputs still read as numbers (a grid of four
        # rows where the template writes hundreds) cannot be recomputed: one line
        raise WorkbookReadError(f"{path}: its grid or inputs are not what crankbook "
                                f"writes ({type(error).__name__}); rebuild it") from None


def _shape_findings(spec, ranges, grid_rows, sizes):
    """A finding for each result name that covers other cells than the template's."""
    out = []
    for q in spec.quantities():
        found = ranges.get(f"q_{q.key}")
        if found is None:
            continue
        rows, cols = expected_shape(spec, q.key, grid_rows, sizes)
        if (found.rows, found.cols) != (rows, cols):
            out.append(CellFinding(f"'{found.sheet}'!…", f"q_{q.key}", None, math.nan,
                                   f"covers {found.rows}×{found.cols} cells; the template "
                                   f"gives it {rows}×{cols}"))
    return out


def _audit(original, calculated, recalculated):
    formula_book, formula_ranges = original[0], original[3]
    book, spec, template, ranges, values, tables, grids, sizes, grid_rows = calculated
    try:
        expected, floors = expected_values(spec, values, tables, grids)
    except (IndexError, ValueError, ZeroDivisionError, OverflowError):
        # a name cut short (a grid of four rows) cannot be recomputed: its shape is
        # the finding; with no name out of shape the caller refuses the file in a line
        shapes = _shape_findings(spec, ranges, grid_rows, sizes)
        if not shapes:
            raise
        return spec, shapes, recalculated, None
    rule_message = None
    if expected is None:
        # inputs that break a rule: one finding (the rule, and the status cell's words);
        # the results are blank by design, and the cells that do not hang on the broken
        # inputs (the crank angles, the checks themselves) still must agree
        rule_message = _broken_rule(spec, values, tables, grids)
        status = ranges.get("q_input_status")
        words = cells(book, status)[0] if status is not None else None
        if words:
            rule_message += f"; the workbook's status cell says: {words}"
        expected, floors = _unchecked(spec, values, tables, grids), {}
    findings = []
    for q in spec.quantities():
        name = f"q_{q.key}"
        if name not in ranges:
            findings.append(CellFinding("—", name, None, math.nan, MISSING))
            continue
        found = ranges[name]
        rows, cols = expected_shape(spec, q.key, grid_rows, sizes)
        if (found.rows, found.cols) != (rows, cols):
            findings.append(CellFinding(
                f"'{found.sheet}'!…", name, None, math.nan,
                f"covers {found.rows}×{found.cols} cells; the template gives it {rows}×{cols}"))
            continue
        stored_cells = cells(book, found)
        written = formulas(formula_book, formula_ranges[name]) if name in formula_ranges \
            else [False] * len(stored_cells)
        want = np.atleast_1d(np.asarray(expected.get(q.key, math.nan), dtype=float)).ravel()
        allowed = allowances(want, floors.get(q.key, 0.0))
        constant = q.formula is None
        for i, (address, stored, formula) in enumerate(zip(_addresses(found), stored_cells,
                                                            written)):
            target = want[i] if i < want.size else math.nan
            if not constant and not formula:
                findings.append(CellFinding(address, name, stored, target,
                                            "formula replaced by a constant"))
            elif isinstance(stored, str) and stored.startswith("#"):
                findings.append(CellFinding(address, name, stored, target,
                                            f"error value {stored}"))
            elif stored is None or stored == "":
                if np.isfinite(target) and rule_message is None:
                    findings.append(CellFinding(address, name, stored, target,
                                                "no stored value (saved without calculation?)"))
            elif isinstance(stored, bool) or not isinstance(stored, (int, float)):
                findings.append(CellFinding(address, name, stored, target, "not a number"))
            elif not np.isfinite(target):
                findings.append(CellFinding(address, name, stored, target,
                                            "a value where the inputs give none"))
            elif abs(stored - target) > allowed[i]:
                findings.append(CellFinding(address, name, stored, target, DIFFERS, i))
    if rule_message is None and not recalculated:
        findings = _stale(findings, spec, values, tables, grids, formula_book)
    return spec, _missing_inputs(spec, ranges, formula_book) + _grouped(findings), \
        recalculated, rule_message


def _missing_inputs(spec, ranges, book):
    """An input name deleted from a workbook this crankbook version wrote (an older
    version's workbook may lack inputs added since: those take their defaults)."""
    from crankbook import __version__
    from crankbook.writer.build import PROPERTY_VERSION
    if book.custom_properties.get(PROPERTY_VERSION) != __version__:
        return []
    return [CellFinding("—", f"p_{p.key}", None, math.nan,
                        "the input name is missing: the file was altered (its results were "
                        "recomputed with the input's default)")
            for p in spec.parameters if f"p_{p.key}" not in ranges]


def _stale(findings, spec, values, tables, grids, book):
    """The differing cells as one finding when they all follow the inputs the workbook
    was built with: its preset's values of the inputs that now differ."""
    from crankbook.errors import CrankbookError
    from crankbook.spec import params
    from crankbook.writer.build import PROPERTY_PRESET
    differing = [f for f in findings if f.problem == DIFFERS]
    if len(differing) < GROUPED:
        return findings
    try:
        _, base, _ = params.load_preset(book.custom_properties.get(PROPERTY_PRESET) or "")
    except (CrankbookError, OSError, ValueError):
        return findings
    changed = [k for k in values if k in base and np.shape(values[k]) == np.shape(base[k])
               and not np.allclose(np.asarray(values[k], float), np.asarray(base[k], float),
                                   rtol=1e-12, atol=0.0)]
    if not changed:
        return findings
    old = dict(values, **{k: base[k] for k in changed})
    with np.errstate(all="ignore"):
        before, floors = expected_values(spec, old, tables, grids)
    if before is None:
        return findings
    following = []                     # the cells that hold the built inputs' results
    limits = {}                        # name -> its built values and their allowances
    for f in differing:
        key = f.name[2:]
        if key not in limits:
            want = np.atleast_1d(np.asarray(before.get(key, math.nan), dtype=float)).ravel()
            limits[key] = want, allowances(want, floors.get(key, 0.0))
        want, allowed = limits[key]
        if f.index is not None and f.index < want.size and np.isfinite(want[f.index]) and \
                abs(f.stored - want[f.index]) <= allowed[f.index]:
            following.append(f)
    if len(following) < STORY * len(differing):
        return findings                     # not the built inputs' values: no such story
    grouped = {id(f) for f in following}    # by identity, in one pass: a stale engine
    others = [f for f in findings if id(f) not in grouped]   # workbook has ~10⁵ of them
    counts = {}
    for f in following:
        counts[f.name] = counts.get(f.name, 0) + 1
    names = ", ".join(f"p_{k}" for k in changed)
    shown = ", ".join(f"{name} {count:,}" for name, count in
                      sorted(counts.items(), key=lambda item: -item[1])[:6])
    more = f", … {len(counts) - 6} more names" if len(counts) > 6 else ""
    summary = CellFinding("—", names, None, math.nan,
                          f"not recalculated after {names} changed: {len(following):,} cells "
                          f"still hold the results of the inputs it was built with ({shown}"
                          f"{more})")
    return [summary] + others


def _grouped(findings):
    """Many differing cells of one name: one finding with their count and the first."""
    counts = {}
    for f in findings:
        if f.problem == DIFFERS:
            counts[f.name] = counts.get(f.name, 0) + 1
    out, done = [], set()
    for f in findings:
        if f.problem != DIFFERS or counts[f.name] <= GROUPED:
            out.append(f)
        elif f.name not in done:
            done.add(f.name)
            out.append(CellFinding(f.address, f.name, f.stored, f.expected,
                                   f"{DIFFERS} in {counts[f.name]:,} cells (the first "
                                   f"shown)", f.index))
    return out


def _broken_rule(spec, values, tables, grids):
    from crankbook.spec import params
    from crankbook.errors import CrankbookError
    try:
        params.validate(spec, dict(values), tables=tables, grids=grids)
    except CrankbookError as error:
        return str(error)
    return "a rule is broken"


def _unchecked(spec, values, tables, grids):
    """The numpy results of inputs that break a rule, quantity by quantity, where they
    can be computed at all (NaN elsewhere): what a cell that still shows a value
    must agree with."""
    from crankbook.spec.evaluate import evaluate
    try:
        with np.errstate(all="ignore"):
            return dict(evaluate(spec, values, tables, grids))
    except Exception:            # noqa: BLE001 — impossible geometry may raise anywhere
        return {}
