"""Cylinder pressure: a closed-form four-stroke pressure model and measured traces.

The model (used when no measured indicator diagram is given) is the blended
two-polytrope model with a Wiebe burn law, chosen because each crank angle is a
closed-form expression — one spreadsheet formula per row, no step-by-step
integration that would depend on the grid step:

* intake stroke (0 ≤ α < 180°): p = p_in
* closed part (180° ≤ α < 540°): p = (1 − x_b)·p_c + x_b·p_e with
  p_c = p_in·(V_max/V)^n_c (compression polytrope),
  p_e = p_3·(V_c/V)^n_e (expansion polytrope through the constant-volume
  combustion pressure p_3 = p_c(V_c) + (κ − 1)·Q/V_c) and
  x_b = 1 − exp(−a·((α − α_s)/Δα)^(m+1)) the Wiebe mass fraction burned
* exhaust stroke (540° ≤ α ≤ 720°): p = p_ex

Firing TDC is at α = 360°.  Reference: J. B. Heywood, *Internal Combustion Engine
Fundamentals*, §9.2 (Wiebe function) and §5.4 (polytropic processes).
"""
import numpy as np

from crankbook.calc.forces import piston_area


def displaced_volume(bore, stroke):
    """Swept volume V_d = πD²/4·H [m³]."""
    return piston_area(bore) * stroke


def clearance_volume(displaced_volume, compression_ratio):
    """Clearance (combustion-chamber) volume V_c = V_d/(ε − 1) [m³]."""
    return displaced_volume / (compression_ratio - 1)


def cylinder_volume(piston_displacement, bore, clearance_volume):
    """Cylinder volume V = V_c + πD²/4·s [m³]; s is the exact displacement from TDC [m]."""
    return clearance_volume + piston_area(bore) * np.asarray(piston_displacement)


def burned_fraction(crank_angle, combustion_start, combustion_duration, wiebe_efficiency,
                    wiebe_shape):
    """Wiebe mass fraction burned x_b [-]; 0 before ``combustion_start``.

    Parameters
    ----------
    crank_angle, combustion_start, combustion_duration : array_like
        α, α_s, Δα [rad] (any consistent angle unit works: only ratios enter).
    wiebe_efficiency, wiebe_shape : float
        a and m of the Wiebe law [-].
    """
    crank_angle = np.asarray(crank_angle, dtype=float)
    progress = np.clip((crank_angle - combustion_start) / combustion_duration, 0, None)
    return np.where(crank_angle < combustion_start, 0.0,
                    1 - np.exp(-wiebe_efficiency * progress ** (wiebe_shape + 1)))


def combustion_pressure(intake_pressure, compression_ratio, compression_exponent,
                        heat_capacity_ratio, heat_released, clearance_volume):
    """Constant-volume combustion pressure at TDC, p_3 = p_in·ε^n_c + (κ−1)·Q/V_c [Pa]."""
    return (intake_pressure * compression_ratio ** compression_exponent
            + (heat_capacity_ratio - 1) * heat_released / clearance_volume)


def model_pressure(crank_angle, cylinder_volume, burned_fraction, clearance_volume,
                   displaced_volume, intake_pressure, exhaust_pressure, compression_exponent,
                   expansion_exponent, combustion_pressure, cycle=4 * np.pi):
    """Cylinder pressure of the blended two-polytrope model [Pa] (see module docstring).

    ``crank_angle`` [rad] runs over the ``cycle`` 0…4π with firing TDC at 2π; the
    four strokes are its quarters.
    """
    crank_angle = np.asarray(crank_angle, dtype=float)
    volume = np.asarray(cylinder_volume, dtype=float)
    compression = intake_pressure * ((clearance_volume + displaced_volume) / volume) \
        ** compression_exponent
    expansion = combustion_pressure * (clearance_volume / volume) ** expansion_exponent
    closed = (1 - burned_fraction) * compression + burned_fraction * expansion
    # Which stroke: 0 intake, 1–2 compression/expansion, 3 exhaust.  The small
    # allowance keeps a grid point at exactly 540° on the exhaust side despite the
    # degree-to-radian rounding, as the workbook's α < 540 test does.
    stroke_number = np.floor(crank_angle / (cycle / 4) + 1e-9)
    return np.where(stroke_number < 1, intake_pressure,
                    np.where(stroke_number < 3, closed, exhaust_pressure))


def trace_segment(crank_angle, trace_crank_angle):
    """1-based index k of the trace segment [A_k, A_k+1] holding each crank angle.

    The workbook's MIN(MATCH(α, A, 1), n − 1): the last point of a trace
    reaching exactly α uses the last segment.  NaN where the trace has fewer than
    two points.
    """
    angles = np.asarray(trace_crank_angle, dtype=float)
    x = np.asarray(crank_angle, dtype=float)
    if angles.size < 2:
        return np.full(x.shape, np.nan)
    # A crank angle equal to a trace angle but for rounding (30° reached as π/6 and
    # back) counts as equal, as the workbook's exact 30 does in MATCH.
    nudge = 1e-12 * np.max(np.abs(angles))
    return np.minimum(np.searchsorted(angles, x + nudge, side="right"),
                      angles.size - 1).astype(float)


def trace_pressure(crank_angle, trace_crank_angle, trace_pressure):
    """Linear interpolation of a measured trace [Pa], exactly as the workbook does it.

    ``trace_crank_angle`` must ascend and bracket every ``crank_angle``; NaN where
    the trace has fewer than two points.
    """
    angles = np.asarray(trace_crank_angle, dtype=float)
    pressures = np.asarray(trace_pressure, dtype=float)
    x = np.asarray(crank_angle, dtype=float)
    segment = trace_segment(x, angles)
    if np.isnan(segment).any():
        return segment
    k = segment.astype(int) - 1
    return pressures[k] + (x - angles[k]) * (pressures[k + 1] - pressures[k]) \
        / (angles[k + 1] - angles[k])


def cylinder_pressure(pressure_source, model_pressure, trace_pressure):
    """The measured trace where ``pressure_source`` is 1, else the model [Pa]."""
    return np.where(np.asarray(pressure_source) == 1, trace_pressure, model_pressure)
