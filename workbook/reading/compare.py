"""The one rule by which a spreadsheet's number agrees with numpy (verify and audit).

A cell agrees when |sheet − numpy| ≤ RELATIVE·peak + FLOOR_FACTOR·floor, where
``peak`` is the largest |numpy value| of the quantity (a whole series, not one
cell) and ``floor`` is the rounding noise the quantity can carry: rounding of
ROUNDING relative at every input and every intermediate result, propagated to
first order through each calc function (one argument at a time).  So a mean
torque that is zero up to rounding agrees when the spreadsheet's rounding gives
3e-14 instead of 1e-14, because its floor comes from the torque it averages.
Discrete results (the crank angle of an extreme, a segment number) must agree
exactly: their floor is zero.  A cell whose floor is infinite — a ratio of two
numbers that are 0 up to rounding, such as the stroke study's change of the powers of
a constant-pressure trace — is determined by no input, and agrees whatever it holds.
"""
import math
from dataclasses import dataclass

import numpy as np

from crankbook.spec import units
from crankbook.spec.evaluate import Evaluator

RELATIVE = 1e-9
ROUNDING = 1e-14
FLOOR_FACTOR = 1e4


@dataclass
class Comparison:
    name: str
    unit: str
    error: float          # largest |sheet − numpy|
    allowed: float        # the tolerance at the worst cell
    ratio: float          # largest error/allowed over the cells (≤ 1 agrees)
    cells: int = 1
    worst: int = 0        # index of the worst cell
    shape_ok: bool = True

    @property
    def ok(self):
        return self.shape_ok and self.ratio <= 1.0


def _pattern(shape):
    """A fixed ±1 pattern, so a difference of neighbours does not cancel the shift."""
    size = int(np.prod(shape)) if shape else 1
    signs = np.where(np.arange(size) % 3 == 1, -1.0, 1.0)
    return signs.reshape(shape) if shape else 1.0


def _peak(values):
    values = np.asarray(values, dtype=float)
    finite = values[np.isfinite(values)]
    return float(np.max(np.abs(finite))) if finite.size else 0.0


def noise_floors(spec, values, tables=None, grids=None):
    """Quantity key -> absolute rounding floor in sheet units (same shape as its value)."""
    evaluator = Evaluator(spec, values, tables, grids)
    memo = {}

    def floor(key):
        if key in memo:
            return memo[key]
        memo[key] = 0.0                    # cycles cannot occur; this guards recursion
        q = spec.quantity.get(key)
        base = evaluator.si(key)
        parameter = spec.parameter.get(key)
        if parameter is not None and parameter.kind in ("flag", "integer", "choice") or \
                q is not None and (q.discrete or (q.formula is None and not q.is_grid)):
            # a switch, an index, or a decision cell holding numpy's own number: exact
            result = np.zeros(np.shape(base))
        elif q is None or q.is_numeric_grid:
            result = ROUNDING * np.abs(np.asarray(base, dtype=float))
        elif q.is_series:
            # every cell computes with terms of the series' magnitude, so its own
            # rounding is relative to the series' peak (x = 200 − 50 − 150 at TDC)
            result = _propagated(q, base, ROUNDING * _peak(base))
        else:
            result = _propagated(q, base, ROUNDING * np.abs(np.asarray(base, dtype=float)))
        memo[key] = result
        return result

    def _propagated(q, base, own):
        kwargs = evaluator.arguments(q)
        total = own
        for name, source in q.calc_arguments().items():
            if name not in kwargs:
                continue
            shift = floor(source)
            if np.all(np.asarray(shift) == 0):
                continue
            shift = np.asarray(shift, dtype=float)
            argument = np.asarray(kwargs[name], dtype=float)
            if shift.shape != argument.shape:
                shift = np.broadcast_to(shift.reshape(shift.shape + (1,) * (
                    argument.ndim - shift.ndim)), argument.shape) \
                    if shift.ndim <= argument.ndim else np.max(shift)
            moved = dict(kwargs)
            moved[name] = argument + shift * _pattern(argument.shape)
            changed = evaluator.call(q, moved)
            delta = np.abs(np.asarray(changed, dtype=float) - np.asarray(base, dtype=float))
            total = total + np.where(np.isfinite(delta), delta, 0.0)
        return total

    out = {}
    for q in spec.quantities():
        out[q.key] = np.asarray(floor(q.key), dtype=float) / units.si_factor(q.unit)
    return out


def as_array(value):
    """A number, a blank or error text, or a list of them, as floats (NaN for non-numbers)."""
    items = value if isinstance(value, (list, tuple, np.ndarray)) else [value]
    return np.array([math.nan if v is None or isinstance(v, (str, bool)) else float(v)
                     for v in items], dtype=float)


def allowances(want, floor):
    """The tolerance of each cell of a quantity whose numpy value is ``want``."""
    want = np.atleast_1d(np.asarray(want, dtype=float)).ravel()
    floor = np.atleast_1d(np.asarray(floor, dtype=float)).ravel()
    floor = np.broadcast_to(floor, want.shape) if floor.size in (1, want.size) else \
        np.zeros(want.shape)
    finite = want[np.isfinite(want)]
    peak = float(np.max(np.abs(finite))) if finite.size else 0.0
    allowed = RELATIVE * peak + FLOOR_FACTOR * floor
    return np.where(allowed > 0, allowed, 1e-300)


def compare_values(name, unit, want, got, floor):
    """Comparison of one quantity's numpy value ``want`` with the sheet's ``got``."""
    want = np.atleast_1d(np.asarray(want, dtype=float)).ravel()
    got = np.atleast_1d(as_array(got)).ravel()
    if got.shape != want.shape:
        return Comparison(name, unit, math.inf, 0.0, math.inf, want.size, 0, shape_ok=False)
    allowed = allowances(want, floor)
    # an infinite floor: the cell is a ratio of rounding noise (the change of two
    # powers that are 0 up to rounding), which no input determines — any value agrees
    undetermined = np.isinf(allowed)
    both_blank = np.isnan(want) & np.isnan(got)
    error = np.where(both_blank | undetermined, 0.0, np.abs(got - want))
    error = np.where(np.isnan(error), math.inf, error)
    ratios = error / allowed
    worst = int(np.argmax(ratios)) if ratios.size else 0
    return Comparison(name, unit, float(error[worst]), float(allowed[worst]),
                      float(ratios[worst]) if ratios.size else 0.0, want.size, worst)


def compare(spec, expected, actual, floors):
    """One Comparison per q_ name of ``spec``; ``actual`` maps q_<key> to sheet values."""
    out = []
    for q in spec.quantities():
        name = f"q_{q.key}"
        if name not in actual:
            out.append(Comparison(name, q.unit, math.inf, 0.0, math.inf, shape_ok=False))
            continue
        out.append(compare_values(name, q.unit, expected[q.key], actual[name],
                                  floors.get(q.key, 0.0)))
    return out
