"""The offset-crank optimisation of seed 003 ("内燃机活塞机构的优化设计").

With stroke H and time ratio K held, the crank radius a and rod length b follow
from the offset e (:func:`calc.mechanism.crank_radius_from_design`), so the
paper's five variables reduce to one.  The objective is the sum over the power
stroke of the ineffective component F·cosγ of a unit rod force,
S = ∫ |a·cosφ + e|/b dφ from φ0 to φ0 + π + θ, in closed form (seed 003 §三.3):
S = (a/b)·[4·sinα − sinφ0 − sin(φ0 + θ)] + (e/b)·(θ + π − 4α),
φ0 = asin(e/(a + b)) + π/2, cosα = e/a.
"""
import numpy as np

from crankbook.calc.mechanism import (crank_radius_from_design, extreme_angle, min_transmission_angle,
                            rod_length_from_design)

GOLDEN = (np.sqrt(5) - 1) / 2


def start_angle(crank_radius, rod_length, offset):
    """φ0 = asin(e/(a + b)) + π/2, the crank angle where the power stroke starts [rad]."""
    return np.arcsin(offset / (crank_radius + rod_length)) + np.pi / 2


def right_angle_position(crank_radius, offset):
    """α with cosα = e/a: the transmission angle is 90° at φ = π ± α [rad]."""
    return np.arccos(offset / crank_radius)


def ineffective_force_sum(crank_radius, rod_length, offset, time_ratio):
    """The objective S of seed 003 [rad] (a unit force summed over the power stroke)."""
    a, b, e = crank_radius, rod_length, offset
    theta = extreme_angle(time_ratio)
    phi0 = start_angle(a, b, e)
    alpha = right_angle_position(a, e)
    return (a / b * (4 * np.sin(alpha) - np.sin(phi0) - np.sin(phi0 + theta))
            + e / b * (theta + np.pi - 4 * alpha))


def centric_ineffective_force_sum(crank_radius, rod_length):
    """S of the centric mechanism (e = 0, K = 1): 2a/b."""
    return 2 * crank_radius / rod_length


def _objective(offset, stroke, time_ratio, max_crank_radius, min_transmission_angle_allowed):
    """S at ``offset`` with H and K held, +inf where a constraint is broken."""
    with np.errstate(invalid="ignore", divide="ignore"):
        a = crank_radius_from_design(stroke, offset, time_ratio)
        b = rod_length_from_design(stroke, offset, time_ratio)
        feasible = (np.isfinite(a) & (a <= max_crank_radius) & (offset <= a)
                    & (a + offset <= b)
                    & (min_transmission_angle(a, b, offset) >= min_transmission_angle_allowed))
        value = ineffective_force_sum(a, b, offset, time_ratio)
    return np.where(feasible & np.isfinite(value), value, np.inf)


def optimum_offset(stroke, time_ratio, max_crank_radius, min_transmission_angle):
    """The offset e minimising S under the constraints [m]: a scan, then golden sections.

    Parameters
    ----------
    stroke : float
        H [m], held.
    time_ratio : float
        K [-], held.
    max_crank_radius : float
        Upper bound on a [m].
    min_transmission_angle : float
        [γ], lower bound on the minimum transmission angle [rad].
    """
    args = (stroke, time_ratio, max_crank_radius, min_transmission_angle)
    grid = np.linspace(stroke * 1e-4, stroke / 2, 4001)
    values = _objective(grid, *args)
    best = int(np.argmin(values))
    if not np.isfinite(values[best]):
        return float("nan")
    lo, hi = grid[max(best - 1, 0)], grid[min(best + 1, grid.size - 1)]
    for _ in range(200):
        x1, x2 = hi - GOLDEN * (hi - lo), lo + GOLDEN * (hi - lo)
        if _objective(x1, *args) <= _objective(x2, *args):
            hi = x2
        else:
            lo = x1
        if hi - lo < 1e-15 * stroke:
            break
    return float((lo + hi) / 2)


def reduction_percent(objective, baseline):
    """How much smaller the objective is than the baseline, in percent."""
    return (1 - objective / baseline) * 100


def crank_margin(crank_radius, rod_length, offset):
    """b − (a + e): non-negative when the crank exists [m]."""
    return rod_length - crank_radius - offset


def radius_margin(crank_radius, max_crank_radius):
    """a_max − a [m]."""
    return max_crank_radius - crank_radius


def time_ratio_of(crank_radius, rod_length, offset):
    """K from the geometry: (π + θ′)/(π − θ′), θ′ = asin(e/(b−a)) − asin(e/(b+a)) [-]."""
    theta = (np.arcsin(offset / (rod_length - crank_radius))
             - np.arcsin(offset / (rod_length + crank_radius)))
    return (np.pi + theta) / (np.pi - theta)


def crank_radius_or_nan(stroke, offset, time_ratio):
    """:func:`crank_radius_from_design`, NaN where no crank exists [m]."""
    with np.errstate(invalid="ignore"):
        return crank_radius_from_design(stroke, offset, time_ratio)


def feasible(crank_radius, rod_length, offset, max_crank_radius, min_transmission_angle):
    """1 where every constraint of the optimisation holds, else 0."""
    a, b, e = (np.asarray(v, dtype=float) for v in (crank_radius, rod_length, offset))
    with np.errstate(invalid="ignore"):
        gamma = np.arccos(np.minimum(1.0, (a + e) / b))
        ok = ((a <= max_crank_radius) & (e <= a) & (a + e <= b)
              & (gamma >= min_transmission_angle))
    return np.where(np.isfinite(a) & ok, 1.0, 0.0)


def feasible_objective(crank_radius, rod_length, offset, time_ratio, feasible):
    """S where feasible, NaN elsewhere [rad]."""
    with np.errstate(invalid="ignore"):
        value = ineffective_force_sum(crank_radius, rod_length, offset, time_ratio)
    return np.where(np.asarray(feasible) == 1, value, np.nan)


def peak_acceleration(crank_radius, rod_length, offset, speed, samples=72001):
    """Largest piston acceleration over a revolution [m/s²] (dense sampling)."""
    from crankbook.calc.kinematics import piston_acceleration_exact
    phi = np.linspace(0, 2 * np.pi, samples)
    return float(np.max(np.abs(piston_acceleration_exact(phi, crank_radius, rod_length, offset,
                                                          speed))))


def peak_side_force_power_stroke(crank_radius, rod_length, offset, axial_force,
                                 samples=72001):
    """Largest piston side force P·|tanβ| over the power stroke (TDC to BDC) [N]."""
    from crankbook.calc.kinematics import rod_angle
    a, b, e = crank_radius, rod_length, offset
    bdc = np.pi + np.arcsin(e / (b - a)) - np.arcsin(e / (a + b))
    phi = np.linspace(0, bdc, samples)
    return float(axial_force * np.max(np.abs(np.tan(rod_angle(phi, a, b, e)))))


def peak_side_force(crank_radius, rod_length, offset, axial_force, samples=72001):
    """Largest piston side force P·|tanβ| over a whole revolution [N] (dense sampling).

    Parameters
    ----------
    crank_radius, rod_length, offset : float
        a, b, e [m].
    axial_force : float
        The piston's axial force P [N], held constant.
    """
    from crankbook.calc.kinematics import rod_angle
    phi = np.linspace(0, 2 * np.pi, samples)
    return float(axial_force * np.max(np.abs(np.tan(rod_angle(phi, crank_radius, rod_length,
                                                                offset)))))


def where_feasible(value, feasible):
    """``value`` where ``feasible`` is 1, NaN elsewhere (a blank cell)."""
    return np.where(np.asarray(feasible) == 1, value, np.nan)
