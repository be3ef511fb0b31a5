"""Compute every quantity of a specification with its calc function (numpy).

Values go in and come out in sheet units; calc functions see SI units.  This is
the independent half of each quantity: the workbook's formulas are the other.
"""
import math

import numpy as np

from workbook import units
from workbook.errors import BuildOptionError


def numeric_grid(grid):
    """start, start+step, …, stop of a numeric grid."""
    count = round((grid.stop - grid.start) / grid.step)
    return grid.start + grid.step * np.arange(count + 1)


def crank_angle_grid(spec, step=None):
    """The shared crank-angle grid start, start+step, …, stop [deg]."""
    step = spec.grid_step if step is None else step
    span = spec.grid_stop - spec.grid_start
    if not (isinstance(step, (int, float)) and math.isfinite(step) and 0 < step <= span / 4):
        raise BuildOptionError(f"--step {step!r}: the grid step must be a number > 0 and "
                               f"≤ {span / 4:g}°")
    count = round(span / step)
    if abs(count * step - span) > 1e-9 * span:
        raise BuildOptionError(f"--step {step:g}: the grid step must divide {span:g}° evenly")
    return spec.grid_start + step * np.arange(count + 1)


def evaluate(spec, values, tables, grid, overrides=None):
    """Every quantity of ``spec`` in sheet units.

    Parameters
    ----------
    values : dict
        Parameter key -> value in its sheet unit.
    tables : dict
        Input-table column key -> 1-D array in its sheet unit (may be empty).
    grid : numpy.ndarray
        The crank-angle grid [deg].
    overrides : dict, optional
        Computed quantity key -> value in its sheet unit to use instead of its calc
        function (e.g. a student's own crank radius, for consequential credit).
    """
    overrides = overrides or {}
    si = {}
    shapes = {spec.grid.key: np.shape(grid)}

    def si_value(key):
        if key in si:
            return si[key]
        q = spec.quantity.get(key)
        if key in overrides:
            result = np.asarray(overrides[key], dtype=float) * units.si_factor(spec.unit_of(key))
            if result.ndim == 0:
                result = float(result)
        elif key == spec.grid.key:
            result = np.asarray(grid, dtype=float) * units.si_factor(spec.grid.unit)
        elif q is not None and q.is_grid and q.formula is None:
            points = numeric_grid(q)
            shapes[key] = points.shape
            result = points * units.si_factor(q.unit)
        elif key in spec.parameter:
            result = float(values[key]) * units.si_factor(spec.parameter[key].unit)
        elif key in spec.table_column:
            result = np.asarray(tables.get(key, []), dtype=float) \
                * units.si_factor(spec.table_column[key].unit)
        else:
            q = spec.quantity[key]
            kwargs = {name: si_value(source) for name, source in q.calc_arguments().items()}
            result = q.calc_function()(**kwargs)
            if q.is_grid:
                result = np.asarray(result, dtype=float)
                shapes[key] = result.shape
            elif q.kind == "series":
                si_value(q.grid)
                result = np.broadcast_to(np.asarray(result, dtype=float), shapes[q.grid])
            else:
                result = float(result)
        si[key] = result
        return result

    out = {}
    for q in spec.quantities():
        value = si_value(q.key)
        out[q.key] = value / units.si_factor(q.unit)
    # Numeric grids as given, not through the SI round trip (462° must stay 462,
    # not 461.99999999999994, or an exact MATCH against a trace shifts a row).
    out[spec.grid.key] = np.asarray(grid, dtype=float)
    for g in spec.grids:
        if g.formula is None and g is not spec.grid:
            out[g.key] = numeric_grid(g)
    return out
