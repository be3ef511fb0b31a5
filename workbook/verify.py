"""Check a workbook's formulas in a real spreadsheet engine against numpy.

LibreOffice recalculates the file (recalculation forced); every q_ name read back
is compared with the calc functions evaluated on the workbook's own p_ cells.
"""
import math
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from workbook import params, recalc, spec as specs
from workbook.errors import WorkbookReadError
from workbook.evaluate import evaluate
from workbook.reader import named_values, open_workbook

TOLERANCE = 1e-9


@dataclass
class Comparison:
    name: str
    unit: str
    worst: float        # largest |LibreOffice − numpy|
    scale: float        # the series' peak |numpy| (or the scalar's magnitude)
    cached_worst: float  # largest |cached − LibreOffice|

    @property
    def relative(self):
        return self.worst / self.scale if self.scale else self.worst

    @property
    def cached_relative(self):
        return self.cached_worst / self.scale if self.scale else self.cached_worst

    @property
    def ok(self):
        return self.relative <= TOLERANCE


def _as_array(value):
    items = value if isinstance(value, list) else [value]
    return np.array([math.nan if v is None or isinstance(v, str) else float(v) for v in items])


def is_extreme_angle(quantity):
    return quantity.key.endswith(("_max_angle", "_min_angle"))


def extreme_angle_error(quantity, expected, angle):
    """(|series(angle) − extreme|, series peak) for a q_<x>_max_angle/_min_angle value.

    The same extreme can occur twice (at 0° and 720°), so the angle itself is
    ambiguous; what must hold is that the series reaches its extreme there.
    """
    values = np.asarray(expected[quantity.args["values"]], dtype=float)
    grid = np.asarray(expected[quantity.args["crank_angle"]], dtype=float)
    extreme = np.nanmax(values) if quantity.key.endswith("_max_angle") else np.nanmin(values)
    scale = float(np.nanmax(np.abs(values))) or 1.0
    if not np.isfinite(angle):
        return math.inf, scale
    error = abs(values[np.argmin(np.abs(grid - angle))] - extreme)
    return (error if np.isfinite(error) else math.inf), scale


def spec_of(names):
    """The workbook specification whose parameters the file's p_ names are."""
    keys = {n[2:] for n in names if n.startswith("p_")}
    for path in sorted(specs.TEMPLATES.glob("*.toml")):
        if path.stem == "units":
            continue
        spec = specs.load(path.stem)
        if set(spec.parameter) <= keys:
            return spec
    raise WorkbookReadError("the workbook has no p_ names of any crankbook template; "
                            "was it written by crankbook?")


def inputs_of(spec, names, path):
    """(parameter values, input tables, grid) as stored in the workbook."""
    values = {}
    for key in spec.parameter:
        value = names.get(f"p_{key}")
        if not isinstance(value, (int, float)) or isinstance(value, bool):
            raise WorkbookReadError(f"{path}: parameter p_{key} holds {value!r}, not a number")
        values[key] = float(value)
    tables = {}
    for key in spec.table_column:
        column = names.get(f"p_{key}") or []
        tables[key] = np.array([v for v in column if isinstance(v, (int, float))], float)
    grid = _as_array(names.get(f"q_{spec.grid.key}", []))
    if grid.size < 2 or np.isnan(grid).any():
        raise WorkbookReadError(f"{path}: the crank-angle grid q_{spec.grid.key} is missing "
                                f"or not numeric")
    return values, tables, grid


def compare(spec, expected, recalculated, cached):
    """One Comparison per q_ name of the specification."""
    out = []
    for q in spec.quantities():
        name = f"q_{q.key}"
        if name not in recalculated:
            out.append(Comparison(name, q.unit, math.inf, 1.0, math.inf))
            continue
        want = np.atleast_1d(np.asarray(expected[q.key], float))
        got = _as_array(recalculated[name])
        stored = _as_array(cached.get(name))
        if is_extreme_angle(q):
            worst, scale = extreme_angle_error(q, expected, got[0])
            out.append(Comparison(name, q.unit, worst, scale,
                                  0.0 if stored[0] == got[0] else abs(stored[0] - got[0])))
            continue
        if got.shape != want.shape:
            out.append(Comparison(name, q.unit, math.inf, 1.0, math.inf))
            continue
        both_missing = np.isnan(want) & np.isnan(got)
        diff = np.where(both_missing, 0.0, np.abs(got - want))
        diff = np.where(np.isnan(diff), math.inf, diff)
        stored_diff = np.where(np.isnan(stored) & np.isnan(got), 0.0, np.abs(stored - got)) \
            if stored.shape == got.shape else np.array([math.inf])
        stored_diff = np.where(np.isnan(stored_diff), math.inf, stored_diff)
        # The scale is the series' peak; a max/min is judged against its series' peak.
        basis = np.asarray(expected[q.args["values"]]) if q.key.endswith(("_max", "_min")) \
            and "values" in q.args else want
        finite = basis[np.isfinite(basis)]
        scale = float(np.max(np.abs(finite))) if finite.size else 1.0
        out.append(Comparison(name, q.unit, float(diff.max()), scale or 1.0,
                              float(stored_diff.max())))
    return out


def verify(path, workdir=None):
    """(spec, comparisons, status text) for the workbook at ``path``."""
    path = Path(path)
    book = open_workbook(path)
    cached = named_values(book)
    if not any(name.startswith("q_") for name in cached):
        raise WorkbookReadError(f"{path}: has no q_ names, so nothing to verify (a student "
                                f"workbook is checked with 'crankbook grade')")
    spec = spec_of(cached)
    values, tables, grid = inputs_of(spec, cached, path)
    status = cached.get("q_input_status")
    with tempfile.TemporaryDirectory(prefix="crankbook-verify-", dir=workdir) as tmp:
        converted = recalc.convert([path], tmp)[0]
        recalculated = named_values(open_workbook(converted))
    try:
        params.validate(spec, dict(values), trace_points=len(tables.get("trace_crank_angle", [])))
        expected = evaluate(spec, values, tables, grid)
    except Exception:
        expected = {q.key: np.full(np.shape(grid) if q.kind == "series" else (), math.nan)
                    for q in spec.quantities()}
        expected[spec.grid.key] = grid
    return spec, compare(spec, expected, recalculated, cached), recalculated.get(
        "q_input_status", status)
