"""Cycle results: means over a periodic grid, extremes and where they occur, work.

The crank angle of an extreme is the first grid angle at which the series comes
within ``tolerance`` of its peak |value| of the extreme: the same angle in numpy,
Excel, LibreOffice and Gnumeric, even where the extreme recurs (at 73° and 433°)
and the two differ in the last bit.
"""
import numpy as np

EXTREME_TOLERANCE = 1e-9


def cycle_mean(values):
    """Mean over a periodic grid whose last point repeats the first (0…720° inclusive).

    The closing point is left out, so every crank angle of the cycle counts once.
    """
    values = np.asarray(values, dtype=float)
    return values[:-1].mean()


def indicated_power(mean_torque, speed):
    """Indicated power P = M_mean·ω [W] (the inertia torque averages to zero)."""
    return mean_torque * speed


def indicated_work(cylinder_pressure, cylinder_volume):
    """Indicated work per cycle ∮p·dV [J], trapezoidal rule over the closed cycle."""
    p = np.asarray(cylinder_pressure, dtype=float)
    v = np.asarray(cylinder_volume, dtype=float)
    return float(np.sum((p[1:] + p[:-1]) / 2 * np.diff(v)))


def mean_effective_pressure(indicated_work, displaced_volume):
    """Indicated mean effective pressure W_i/V_d [Pa]."""
    return indicated_work / displaced_volume


def maximum(values):
    """Largest value of a series."""
    return float(np.max(values))


def minimum(values):
    """Smallest value of a series."""
    return float(np.min(values))


def _first_within(crank_angle, values, largest, tolerance):
    values = np.asarray(values, dtype=float)
    finite = values[np.isfinite(values)]
    if not finite.size:
        return float("nan")
    peak = max(np.max(finite), -np.min(finite))
    if largest:
        reached = values >= np.max(finite) - tolerance * peak
    else:
        reached = values <= np.min(finite) + tolerance * peak
    return float(np.asarray(crank_angle, dtype=float)[np.flatnonzero(reached & np.isfinite(values))[0]])


def angle_of_maximum(crank_angle, values, tolerance=EXTREME_TOLERANCE):
    """The first grid angle where ``values`` comes within ``tolerance``·peak of its maximum
    (peak = the largest |value|) [same unit as ``crank_angle``]."""
    return _first_within(crank_angle, values, True, tolerance)


def angle_of_minimum(crank_angle, values, tolerance=EXTREME_TOLERANCE):
    """The first grid angle where ``values`` comes within ``tolerance``·peak of its minimum."""
    return _first_within(crank_angle, values, False, tolerance)


def last_value(values):
    """The last element of a series (the converged end of an iteration)."""
    return float(np.asarray(values)[-1])


def constant_series(value, crank_angle):
    """A scalar repeated on every grid point (a horizontal line on a chart)."""
    return np.full(np.shape(crank_angle), float(value))


def same(value):
    """The value itself (shown again elsewhere)."""
    return value
