"""Compute every quantity of a specification with its calc function (numpy).

Values go in and come out in sheet units; calc functions see SI units.  This is
the independent half of each quantity: the workbook's formulas are the other.

Shapes: a scalar is a float, a series on a grid of N points an (N,) array, a
per-item quantity of an axis with n items an (n,) array, a per-item series (N, n).
A calc function of a per-item series receives 1-D series as (N, 1) columns, so
that numpy broadcasting pairs every grid point with every item.
"""
import math

import numpy as np

from crankbook.spec import units
from crankbook.errors import BuildOptionError, LayoutError, SpecError
from crankbook.spec.model import calc_function

MIN_STEP = 0.1           # deg: a V8 at 0.1° builds in 1.3 GB; 0.01° needed 3.7 GB
MAX_ROWS = 100_000       # rows of one grid: beyond that a workbook is no longer usable


def numeric_grid(grid, step=None):
    """start, start+step, …, stop of a numeric grid."""
    step = grid.step if step is None else step
    count = round((grid.stop - grid.start) / step)
    return grid.start + step * np.arange(count + 1)


def checked_step(grid, step, option="step"):
    """``step`` if it divides the grid's span into at most MAX_ROWS rows, else
    BuildOptionError naming the keyword (``step=…``; the command line shows its flag)
    and the rule."""
    span = grid.stop - grid.start
    if step is None:
        return grid.step
    if isinstance(step, bool) or not isinstance(step, (int, float)) or not math.isfinite(step):
        raise BuildOptionError(f"{option}={step!r}: the grid step must be a number", option)
    lowest = max(MIN_STEP, span / MAX_ROWS)
    if not (lowest <= step <= span / 4):
        raise BuildOptionError(f"{option}={step:g}: the grid step must be ≥ {lowest:g} and "
                               f"≤ {span / 4:g} {'°' if grid.unit == 'deg' else grid.unit}",
                               option)
    count = round(span / step)
    if abs(count * step - span) > 1e-9 * span:
        raise BuildOptionError(f"{option}={step:g}: the grid step must divide {span:g} evenly",
                               option)
    return float(step)


def crank_angle_grid(spec, step=None):
    """The main grid start, start+step, …, stop (e.g. 0…720° of crank angle)."""
    return numeric_grid(spec.grid, checked_step(spec.grid, step))


def build_grids(spec, steps=None):
    """Grid key -> values of every numeric grid, with build-option steps applied.

    ``steps``: build option name (``step``, ``cam_step``, …) -> step.
    """
    steps = steps or {}
    out = {}
    for option, grid in spec.grid_options().items():
        out[grid.key] = numeric_grid(grid, checked_step(grid, steps.get(option), option))
    for grid in spec.grids:
        if grid.is_numeric_grid and grid.key not in out:
            out[grid.key] = numeric_grid(grid)
    return out


def axis_sizes(spec, values):
    """Axis key -> number of items, from the per-item parameters (a product axis: the
    product of its two axes' sizes)."""
    sizes = {}
    for axis in spec.axes:
        if axis.product:
            continue
        if axis.size_calc:
            function = calc_function(axis.size_calc)
            args = {name: np.asarray(values[source], dtype=float)
                    for name, source in axis.size_args.items()}
            sizes[axis.key] = int(function(**args))
            continue
        columns = spec.item_parameters(axis.key)
        lengths = {p.key: len(values[p.key]) for p in columns if not p.fill} or \
            {p.key: len(values[p.key]) for p in columns}
        if len(set(lengths.values())) != 1:
            listing = ", ".join(f"{k} has {n}" for k, n in lengths.items())
            raise LayoutError(f"the {axis.en.lower()} table's columns are set together: "
                              f"{listing} values")
        sizes[axis.key] = next(iter(lengths.values()))
    for axis in spec.axes:
        if axis.product:
            first, second = axis.product
            sizes[axis.key] = sizes[first] * sizes[second]
    return sizes


def _as_grid_dict(spec, grids):
    if grids is None:
        return build_grids(spec)
    if isinstance(grids, dict):
        return {**build_grids(spec), **grids}
    return {**build_grids(spec), spec.grid.key: np.asarray(grids, dtype=float)}


def named_part(result, q):
    """The part ``q.part`` of a calc result of several named parts (a NamedTuple's
    field or a mapping's key): ``part = "x"`` of ``calc.cam.pitch_curve``."""
    if hasattr(result, "_fields") and q.part in result._fields:
        return getattr(result, q.part)
    if isinstance(result, dict) and q.part in result:
        return result[q.part]
    raise SpecError(q.source, q.key, f"calc {q.calc!r} has no part {q.part!r}")


class Evaluator:
    """Lazily computes quantities in SI units, each once, from the inputs."""

    def __init__(self, spec, values, tables=None, grids=None, overrides=None, layout=None):
        self.spec = spec
        # computed grid -> its rows as a workbook read back laid them out when it was
        # built (None when building): a grid's calc function taking ``rows`` gets them,
        # and any other computed grid is cut or padded to them, as the sheet is
        self.layout = layout or {}
        self.values = values
        self.tables = tables or {}
        self.overrides = overrides or {}
        self.grids = _as_grid_dict(spec, grids)
        self.sizes = axis_sizes(spec, values)
        self.memo, self.shapes = {}, {}
        # a calc function of several parts (the journal orbit's fourteen columns) runs
        # once per evaluation: its parts share the function and the arguments' keys
        self.whole = {}

    def is_known(self, key):
        spec = self.spec
        return (key in spec.quantity or key in spec.parameter or key in spec.table_column
                or key in spec.constant or key in self.grids)

    def shape_of(self, q):
        if q.is_grid:
            return self.shapes[q.key]
        if q.is_series:
            self.si(q.grid)
            rows = self.shapes[q.grid]
            return rows + (self.sizes[q.items],) if q.items else rows
        return (self.sizes[q.items],) if q.items else ()

    def argument(self, source, consumer):
        """An argument as ``consumer``'s calc function receives it."""
        value = self.si(source)
        q = self.spec.quantity.get(source)
        if consumer.items and consumer.is_series and isinstance(value, np.ndarray) and \
                q is not None and q.is_series and not q.items and value.ndim == 1:
            return value[:, None]
        return value

    def arguments(self, q):
        kwargs = {name: self.argument(source, q) for name, source in q.calc_arguments().items()
                  if self.is_known(source)}
        if q.is_grid and "rows" in q.takes_rows:
            kwargs["rows"] = self.layout.get(q.key)
        return kwargs

    def call(self, q, kwargs):
        """``q``'s calc function on ``kwargs``, shaped as ``q`` is."""
        shared = None
        if q.part is not None and not q.is_grid:
            # the arguments' shapes follow the consumer (a per-item series gets (N, 1)
            # columns): its kind is part of what the parts share
            shared = (q.calc, tuple(sorted(q.calc_arguments().items())), tuple(sorted(kwargs)),
                      q.items, q.is_series, q.grid)
        if shared in self.whole:
            result = self.whole[shared]
        else:
            with np.errstate(all="ignore"):
                result = q.calc_function()(**kwargs)
            if shared is not None:
                self.whole[shared] = result
        if q.part is not None:
            result = named_part(result, q)
        if q.is_grid:
            result = np.asarray(result, dtype=float)
            rows = self.layout.get(q.key)
            if rows is not None and result.ndim == 1 and result.size != rows:
                result = np.concatenate([result, np.full(rows, np.nan)])[:rows]
            return result
        if q.is_series or q.items:
            result, shape = np.asarray(result, dtype=float), self.shape_of(q)
            if result.shape != shape and result.size == int(np.prod(shape)) and result.ndim:
                result = result.reshape(shape)      # one case of a per-case series: (N, 1)
            elif q.items and self.spec.axis[q.items].aligned and result.ndim and \
                    result.shape[-1] > shape[-1] == 1:
                # one case of an aligned axis reads item 1 of the axis it is aligned to
                result = result[..., :1]
            result = np.broadcast_to(result, shape).copy()
        else:
            # numpy scalars: a division by 0 (an underflowed tiny input) gives inf or NaN —
            # a blank cell — instead of stopping the build
            result = np.float64(np.asarray(result, dtype=float))
        if q.kind == "rule":
            result = np.where(np.isfinite(result) & (np.asarray(result) == 0), 0.0, 1.0)
            result = np.float64(result) if result.ndim == 0 else result
        return result

    def si(self, key):
        if key in self.memo:
            return self.memo[key]
        spec = self.spec
        if key in self.overrides:
            result = np.asarray(self.overrides[key], dtype=float) \
                * units.si_factor(spec.unit_of(key))
            result = np.float64(result) if result.ndim == 0 else result
        elif key in self.grids:
            result = np.asarray(self.grids[key], dtype=float) * units.si_factor(spec.unit_of(key))
            self.shapes[key] = result.shape
        elif key in spec.constant:
            c = spec.constant[key]
            result = np.float64(c.value * units.si_factor(c.unit))
        elif key in spec.parameter:
            p = spec.parameter[key]
            raw = self.values[key]
            result = (np.asarray(raw, dtype=float) if p.axis else np.float64(raw)) \
                * units.si_factor(p.unit)
        elif key in spec.table_column:
            column = spec.table_column[key]
            empty = np.zeros((0, self.sizes[column.items])) if column.items else []
            result = np.asarray(self.tables.get(key, empty), dtype=float) \
                * units.si_factor(column.unit)
        else:
            q = spec.quantity[key]
            result = self.call(q, self.arguments(q))
            if q.is_grid:
                self.shapes[key] = result.shape
        self.memo[key] = result
        return result

    def _snapped(self, q, key, value):
        """A discrete result that picks one of a per-item input's values (the speed of
        the peak torque), exactly as the input holds it (3000, not 3000.0000000000005
        after the trip through SI units)."""
        unit = self.spec.unit_of(key)
        for source in q.args.values():
            parameter = self.spec.parameter.get(source)
            if parameter is None or parameter.axis is None or parameter.unit != unit:
                continue
            points = np.asarray(self.values[source], dtype=float)
            nearest = float(points[np.argmin(np.abs(points - value))])
            if abs(nearest - value) <= 1e-12 * max(abs(nearest), 1.0):
                return nearest
        return value

    def sheet_value(self, key):
        value = self.si(key) / units.si_factor(self.spec.unit_of(key))
        q = self.spec.quantity.get(key)
        grid = q.args.get("crank_angle") if q is not None and q.discrete else None
        if q is not None and q.discrete and np.ndim(value) == 0 and np.isfinite(value):
            value = self._snapped(q, key, value)
        if grid in self.grids and np.ndim(value) == 0 and np.isfinite(value):
            # a grid angle, exactly as the grid holds it (245, not 245.00000000000003)
            points = np.asarray(self.grids[grid], dtype=float)
            value = float(points[np.argmin(np.abs(points - value))])
        return float(value) if np.ndim(value) == 0 else value


def evaluate(spec, values, tables=None, grids=None, overrides=None, keys=None, layout=None):
    """Every quantity of ``spec`` in sheet units (or only ``keys``, and what they need).

    Parameters
    ----------
    values : dict
        Parameter key -> value in its sheet unit (a list for per-item parameters;
        a choice parameter's 1-based index).
    tables : dict, optional
        Input-table column key -> 1-D array in its sheet unit (a measured trace).
    grids : dict or numpy.ndarray, optional
        Grid key -> values of the numeric grids, or the main grid alone [deg].
    overrides : dict, optional
        Computed quantity key -> value in its sheet unit to use instead of its calc
        function (e.g. a student's own crank radius, for consequential credit).
    keys : iterable, optional
        Compute only these (used by the input rules).
    layout : dict, optional
        Grid key -> rows of a workbook read back: its computed grids keep the rows
        they were laid out with when it was built (a torsional sweep's speeds).
    """
    evaluator = Evaluator(spec, values, tables, grids, overrides, layout)
    wanted = spec.quantities() if keys is None else [spec.quantity[k] for k in keys]
    out = {q.key: evaluator.sheet_value(q.key) for q in wanted}
    # Numeric grids as given, not through the SI round trip (462° must stay 462,
    # not 461.99999999999994, or an exact MATCH against a trace shifts a row).
    for key, value in evaluator.grids.items():
        if key in out or keys is None:
            out[key] = np.asarray(value, dtype=float)
    return out
