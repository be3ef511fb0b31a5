"""Cycle averages over one 720° four-stroke cycle."""
import numpy as np


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


def angle_of_maximum(crank_angle, values):
    """Crank angle of the first occurrence of the largest value (as MATCH(MAX()) does)."""
    return float(np.asarray(crank_angle)[np.argmax(values)])


def angle_of_minimum(crank_angle, values):
    """Crank angle of the first occurrence of the smallest value."""
    return float(np.asarray(crank_angle)[np.argmin(values)])


def last_value(values):
    """The last element of a series (the converged end of an iteration)."""
    return float(np.asarray(values)[-1])
