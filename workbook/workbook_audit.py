"""Audit a workbook crankbook wrote: recompute from its p_ cells and report every
q_ cell whose stored value or formula no longer agrees, with its address.

The values are read as saved (Excel, LibreOffice and WPS store them); a formula
replaced by a constant, an error value (#REF!, #NAME?, …) or a cell saved without
a value is reported too.
"""
import math
import tempfile
from dataclasses import dataclass

import numpy as np
from openpyxl.utils.cell import get_column_letter, range_boundaries

from workbook import recalc
from workbook.errors import WorkbookReadError
from workbook.evaluate import evaluate
from workbook.reader import named_values, open_workbook
from workbook.verify import extreme_angle_error, inputs_of, is_extreme_angle, spec_of

TOLERANCE = 1e-6        # relative to the series' peak: saved values carry ≥ 15 digits


@dataclass
class CellFinding:
    address: str
    name: str
    stored: object
    expected: float
    problem: str


def _cells(book, defined):
    sheet, reference = next(iter(defined.destinations))
    min_col, min_row, max_col, max_row = range_boundaries(reference.replace("$", ""))
    ws = book[sheet]
    for r in range(min_row, max_row + 1):
        for c in range(min_col, max_col + 1):
            yield f"'{sheet}'!{get_column_letter(c)}{r}", ws.cell(row=r, column=c)


def _saved_without_values(values_book, formula_book):
    """True when formula cells carry no stored results (e.g. written by openpyxl)."""
    for name, defined in formula_book.defined_names.items():
        if name.startswith("q_"):
            for address, cell in _cells(formula_book, defined):
                if isinstance(cell.value, str) and cell.value.startswith("="):
                    sheet, ref = address.rsplit("!", 1)
                    return values_book[sheet.strip("'")][ref].value is None
    return False


def audit_workbook(path, workdir=None):
    """(spec, findings, recalculated) for the workbook at ``path``; a file saved
    without values is recalculated in LibreOffice first (``recalculated`` True)."""
    values_book = open_workbook(path, data_only=True)
    formula_book = open_workbook(path, data_only=False)
    recalculated = _saved_without_values(values_book, formula_book)
    if recalculated:
        with tempfile.TemporaryDirectory(prefix="crankbook-audit-", dir=workdir) as tmp:
            values_book = open_workbook(recalc.convert([path], tmp)[0], data_only=True)
    names = named_values(values_book)
    if not any(n.startswith("q_") for n in names):
        raise WorkbookReadError(f"{path}: has no q_ names; not a workbook crankbook wrote")
    spec = spec_of(names)
    values, tables, grid = inputs_of(spec, names, path)
    expected = evaluate(spec, values, tables, grid)
    findings = []
    for q in spec.quantities():
        name = f"q_{q.key}"
        if name not in values_book.defined_names:
            findings.append(CellFinding("—", name, None, math.nan, "the defined name is missing"))
            continue
        want = np.atleast_1d(np.asarray(expected[q.key], dtype=float))
        finite = want[np.isfinite(want)]
        scale = float(np.max(np.abs(finite))) if finite.size else 1.0
        formulas = dict(_cells(formula_book, formula_book.defined_names[name]))
        for i, (address, cell) in enumerate(_cells(values_book, values_book.defined_names[name])):
            target = want[i] if i < want.size else math.nan
            stored = cell.value
            has_formula = isinstance(formulas[address].value, str) and \
                formulas[address].value.startswith("=")
            constant = q.formula is None and not (q.is_grid and q.formula)
            if not constant and not has_formula:
                findings.append(CellFinding(address, name, stored, target,
                                            "formula replaced by a constant"))
                continue
            if isinstance(stored, str) and stored.startswith("#"):
                findings.append(CellFinding(address, name, stored, target, f"error value {stored}"))
                continue
            if stored is None or stored == "":
                if np.isfinite(target):
                    findings.append(CellFinding(address, name, stored, target,
                                                "no stored value (saved without calculation?)"))
                continue
            if not isinstance(stored, (int, float)):
                findings.append(CellFinding(address, name, stored, target, "not a number"))
                continue
            if is_extreme_angle(q):
                error, peak = extreme_angle_error(q, expected, stored)
                ok = error <= TOLERANCE * peak
            else:
                ok = np.isfinite(target) and abs(stored - target) <= TOLERANCE * (scale or 1.0)
            if not ok:
                findings.append(CellFinding(address, name, stored, target,
                                            "value differs from the recomputation"))
    return spec, findings, recalculated
