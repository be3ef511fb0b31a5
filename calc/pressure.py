"""Cylinder pressure: a closed-form four-stroke pressure model and measured traces.

The model (used when no measured indicator diagram is given) is the blended
two-polytrope model with a Wiebe burn law, chosen because each crank angle is a
closed-form expression — one spreadsheet formula per row, no step-by-step
integration that would depend on the grid step:

* intake stroke (0 ≤ α < 180°): p = p_in, reached from p_ex over the first 30°
  (valve overlap) so that the cycle closes, p(0) = p(720°) = p_ex
* closed part: p = (1 − x_b)·p_c + x_b·p_e with
  p_c = p_in·(V_max/V)^n_c (compression polytrope),
  p_e = p_3·(V_c/V)^n_e (expansion polytrope through the constant-volume
  combustion pressure p_3 = p_c(V_c) + (κ − 1)·Q/V_c) and
  x_b = 1 − exp(−a·((α − α_s)/Δα)^(m+1)) the Wiebe mass fraction burned
* from the exhaust valve opening (EVO) on: a blowdown to p_ex over 60° (a half
  cosine), then p = p_ex through the exhaust stroke

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


def closed_pressure(cylinder_volume, burned_fraction, clearance_volume, displaced_volume,
                    intake_pressure, compression_exponent, expansion_exponent,
                    combustion_pressure):
    """Pressure while the valves are closed: the compression and expansion polytropes
    blended by the burned fraction, (1 − x_b)·p_c + x_b·p_e [Pa]."""
    volume = np.asarray(cylinder_volume, dtype=float)
    compression = intake_pressure * ((clearance_volume + displaced_volume) / volume) \
        ** compression_exponent
    expansion = combustion_pressure * (clearance_volume / volume) ** expansion_exponent
    return (1 - burned_fraction) * compression + burned_fraction * expansion


def smooth_step(x, start, width):
    """0 before ``start``, 1 after ``start + width``, a half cosine between [-]."""
    x = np.asarray(x, dtype=float)
    progress = np.clip((x - start) / width, 0.0, 1.0)
    return (1 - np.cos(np.pi * progress)) / 2


def model_pressure(crank_angle, closed_pressure, intake_pressure, exhaust_pressure,
                   exhaust_valve_opening, intake_transition, blowdown_duration,
                   cycle=4 * np.pi):
    """Cylinder pressure of the model over the working cycle [Pa].

    * intake stroke (α < cycle/4): from the exhaust pressure at TDC to the intake
      pressure over the first ``intake_transition`` (valve overlap), so the cycle
      closes: p(0) = p(cycle) = p_ex;
    * closed valves: ``closed_pressure``;
    * from the exhaust valve opening on, a blowdown to the exhaust pressure over
      ``blowdown_duration`` (a half cosine: no vertical drop at BDC).

    Angles [rad]; ``cycle`` 4π for a four-stroke, firing TDC at half of it.
    """
    crank_angle = np.asarray(crank_angle, dtype=float)
    intake = exhaust_pressure + (intake_pressure - exhaust_pressure) \
        * smooth_step(crank_angle, 0.0, intake_transition)
    blown = closed_pressure + (exhaust_pressure - closed_pressure) \
        * smooth_step(crank_angle, exhaust_valve_opening, blowdown_duration)
    # the small allowance keeps a grid point at exactly 180° on the closed side
    # despite the degree-to-radian rounding, as the workbook's α < 180 test does
    return np.where(crank_angle / (cycle / 4) < 1 - 1e-12, intake, blown)


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
    if pressures.ndim == 2:
        # one trace per column at the same angles (a trace per speed); rows the sheet
        # leaves blank read as 0, as the workbook's INDEX of an empty cell does
        missing = max(angles.size - pressures.shape[0], 0)
        pressures = np.vstack([pressures[:angles.size], np.zeros((missing, pressures.shape[1]))])
        return np.column_stack([_interpolated(x.ravel(), angles, pressures[:, c])
                                for c in range(pressures.shape[1])])
    return _interpolated(x, angles, pressures)


def _interpolated(x, angles, pressures):
    """The workbook's interpolation of one trace at the crank angles ``x``."""
    segment = trace_segment(x, angles)
    if np.isnan(segment).any():
        return segment
    k = segment.astype(int) - 1
    return pressures[k] + (x - angles[k]) * (pressures[k + 1] - pressures[k]) \
        / (angles[k + 1] - angles[k])


def cylinder_pressure(pressure_source, model_pressure, trace_pressure):
    """The measured trace where ``pressure_source`` is 1, else the model [Pa]."""
    return np.where(np.asarray(pressure_source) == 1, trace_pressure, model_pressure)
