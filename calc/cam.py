"""Disc cams with an offset roller follower (the valve train of the course design,
seed 001: the guides' cam tasks and the worked report R07 §2.2).

A cam turns through the cam angle δ; the follower rises by h over the rise angle Φ,
dwells at the top for Φs, returns over Φ′ and dwells at the bottom for the rest of
the turn.  Each of rise and return follows one motion law, written on the normalised
angle u ∈ [0, 1] as s = h·f(u):

==================  ===========================  ===================
law                 f(u)                         f″(u)
==================  ===========================  ===================
constant velocity   u                            0
constant accel.     2u² | 1 − 2(1 − u)²          4 | −4
cosine (SHM)        (1 − cos πu)/2               π²/2·cos πu
cycloidal (sine)    u − sin(2πu)/2π              2π·sin 2πu
3-4-5 polynomial    10u³ − 15u⁴ + 6u⁵            60u − 180u² + 120u³
==================  ===========================  ===================

Pitch curve (R07 §2.2): s0 = √(r0² − e²), x = (s0 + s)·sin δ + e·cos δ,
y = (s0 + s)·cos δ − e·sin δ; the other sense of rotation mirrors x.  Pressure angle
α = atan((ds/dδ − e)/(s0 + s)).  Angles in radians, lengths in metres, velocities
per second (ω the cam's angular velocity).

References
----------
Seed 001 (guide: 附表1, valve advances; report R07 §2.2); any mechanism-design text
(e.g. 孙桓《机械原理》, cam chapter) for the motion laws and curvature.
"""
from typing import NamedTuple

import numpy as np

LAWS = ("constant_velocity", "constant_acceleration", "cosine", "cycloidal", "3-4-5")


def law_shape(u, law):
    """(f, f′, f″) of motion law ``law`` (1-based index into LAWS) at u ∈ [0, 1]."""
    u = np.asarray(u, dtype=float)
    law = np.asarray(law)
    first_half = u < 0.5
    shapes = {
        1: (u, np.ones_like(u), np.zeros_like(u)),
        2: (np.where(first_half, 2 * u ** 2, 1 - 2 * (1 - u) ** 2),
            np.where(first_half, 4 * u, 4 * (1 - u)),
            np.where(first_half, 4.0, -4.0)),
        3: ((1 - np.cos(np.pi * u)) / 2, np.pi / 2 * np.sin(np.pi * u),
            np.pi ** 2 / 2 * np.cos(np.pi * u)),
        4: (u - np.sin(2 * np.pi * u) / (2 * np.pi), 1 - np.cos(2 * np.pi * u),
            2 * np.pi * np.sin(2 * np.pi * u)),
        5: (10 * u ** 3 - 15 * u ** 4 + 6 * u ** 5, 30 * u ** 2 - 60 * u ** 3 + 30 * u ** 4,
            60 * u - 180 * u ** 2 + 120 * u ** 3),
    }
    out = [np.zeros_like(u) for _ in range(3)]
    for number, (f, df, ddf) in shapes.items():
        chosen = law == number
        for k, part in enumerate((f, df, ddf)):
            out[k] = np.where(chosen, part, out[k])
    return tuple(out)


def piece(cam_angle, rise_angle, far_dwell, return_angle):
    """0 rise, 1 far dwell, 2 return, 3 near dwell: the piece each δ belongs to (a
    boundary belongs to the piece that starts there; 2π to the near dwell)."""
    delta = np.mod(np.asarray(cam_angle, dtype=float), 2 * np.pi)
    delta = np.where(np.isclose(np.asarray(cam_angle, dtype=float), 2 * np.pi), 2 * np.pi,
                     delta)
    ends = np.cumsum([rise_angle, far_dwell, return_angle])
    tol = 1e-12
    return np.where(delta < ends[0] - tol, 0,
                    np.where(delta < ends[1] - tol, 1, np.where(delta < ends[2] - tol, 2, 3)))


class Motion(NamedTuple):
    """The follower's motion: s [m], ds/dδ [m/rad], d²s/dδ² [m/rad²]."""
    displacement: np.ndarray
    slope: np.ndarray
    second_slope: np.ndarray


class Point(NamedTuple):
    """A curve's coordinates [m]."""
    x: np.ndarray
    y: np.ndarray


class PitchDerivatives(NamedTuple):
    """dx/dδ, dy/dδ [m/rad] and d²x/dδ², d²y/dδ² [m/rad²] of the (unmirrored) pitch
    curve."""
    dx: np.ndarray
    dy: np.ndarray
    ddx: np.ndarray
    ddy: np.ndarray


def follower_derivatives(cam_angle, lift, rise_angle, far_dwell, return_angle, rise_law,
                         return_law):
    """(s, ds/dδ, d²s/dδ²) of the follower [m, m/rad, m/rad²], a :class:`Motion`."""
    delta = np.asarray(cam_angle, dtype=float)
    part = piece(delta, rise_angle, far_dwell, return_angle)
    u_rise = np.clip(delta / rise_angle, 0, 1)
    u_return = np.clip((delta - rise_angle - far_dwell) / return_angle, 0, 1)
    f, df, ddf = law_shape(u_rise, rise_law)
    g, dg, ddg = law_shape(u_return, return_law)
    s = np.select([part == 0, part == 1, part == 2], [lift * f, lift, lift * (1 - g)], 0.0)
    ds = np.select([part == 0, part == 2], [lift * df / rise_angle, -lift * dg / return_angle],
                   0.0)
    dds = np.select([part == 0, part == 2], [lift * ddf / rise_angle ** 2,
                                             -lift * ddg / return_angle ** 2], 0.0)
    return Motion(s, ds, dds)


def pitch_curve(cam_angle, displacement, offset, base_radius, rotation):
    """(x, y) of the roller centre on the cam [m] (R07's sense for rotation = +1)."""
    delta = np.asarray(cam_angle, dtype=float)
    s0 = np.sqrt(base_radius ** 2 - offset ** 2)
    x = (s0 + displacement) * np.sin(delta) + offset * np.cos(delta)
    y = (s0 + displacement) * np.cos(delta) - offset * np.sin(delta)
    return Point(rotation * x, y)


def pitch_derivatives(cam_angle, displacement, slope, offset, base_radius, second_slope=0.0):
    """First and second derivatives in δ of the unmirrored pitch curve, a
    :class:`PitchDerivatives` (the second ones need ``second_slope``)."""
    delta = np.asarray(cam_angle, dtype=float)
    r = np.sqrt(base_radius ** 2 - offset ** 2) + displacement
    ds, dds = slope, second_slope
    x1 = ds * np.sin(delta) + r * np.cos(delta) - offset * np.sin(delta)
    y1 = ds * np.cos(delta) - r * np.sin(delta) - offset * np.cos(delta)
    x2 = dds * np.sin(delta) + 2 * ds * np.cos(delta) - r * np.sin(delta) \
        - offset * np.cos(delta)
    y2 = dds * np.cos(delta) - 2 * ds * np.sin(delta) - r * np.cos(delta) \
        + offset * np.sin(delta)
    return PitchDerivatives(x1, y1, x2, y2)


def pitch_curvature_radius(cam_angle, displacement, slope, curvature, offset, base_radius):
    """Radius of curvature of the pitch curve, positive where convex [m].

    ``slope`` and ``curvature`` are ds/dδ and d²s/dδ² [m/rad, m/rad²].
    """
    x1, y1, x2, y2 = pitch_derivatives(cam_angle, displacement, slope, offset, base_radius,
                                       curvature)
    with np.errstate(divide="ignore", invalid="ignore"):
        return -(x1 ** 2 + y1 ** 2) ** 1.5 / (x1 * y2 - y1 * x2)


def roller_profile(cam_angle, displacement, slope, offset, base_radius, roller_radius,
                   rotation):
    """(x, y) of the actual (roller) profile: the inner envelope of the roller [m]."""
    x, y = pitch_curve(cam_angle, displacement, offset, base_radius, 1)
    x1, y1, _, _ = pitch_derivatives(cam_angle, displacement, slope, offset, base_radius)
    length = np.hypot(x1, y1)
    return Point(rotation * (x + roller_radius * y1 / length), y - roller_radius * x1 / length)


def pressure_angle(displacement, slope, offset, base_radius):
    """α = atan((ds/dδ − e)/(s0 + s)) [rad]."""
    s0 = np.sqrt(base_radius ** 2 - offset ** 2)
    return np.arctan((slope - offset) / (s0 + displacement))


def required_base_radius(displacement, slope, offset, allowable):
    """The smallest base radius keeping |α| ≤ ``allowable`` at each δ [m]:
    s0 ≥ |ds/dδ − e|/tan[α] − s, r0 = √(s0² + e²)."""
    s0 = np.maximum(np.abs(slope - offset) / np.tan(allowable) - displacement, 0.0)
    return np.sqrt(s0 ** 2 + offset ** 2)


def cam_angular_velocity(crank_speed, gear_ratio):
    """ω_cam = ω_crank/i [rad/s] (a four-stroke camshaft turns at half the crank speed)."""
    return crank_speed / gear_ratio


# ---------------------------------------------------------------- the workbook's columns
# Columns the physics above does not already give (a template takes one part of a
# function of several with ``part``, and names its arguments with ``args``).
def times_speed(value, cam_angular_velocity, power=1):
    """A derivative in δ times ω^power: per second [m/s or m/s²]."""
    return np.asarray(value) * cam_angular_velocity ** power


def times_speed_squared(value, cam_angular_velocity):
    """d²s/dδ²·ω² [m/s²]."""
    return times_speed(value, cam_angular_velocity, 2)


def required_base_radius_column(cam_angle, cam_displacement, cam_slope, cam_offset,
                                cam_rise_angle, cam_far_dwell, cam_allowable_pressure_angle,
                                cam_allowable_return_pressure_angle):
    """The smallest base radius meeting [α] on the rise (and far dwell) and [α]′ on the
    return (and near dwell), at each δ [m]."""
    allowed = np.where(piece(cam_angle, cam_rise_angle, cam_far_dwell, 1.0) <= 1,
                       cam_allowable_pressure_angle, cam_allowable_return_pressure_angle)
    return required_base_radius(cam_displacement, cam_slope, cam_offset, allowed)


def rise_part_max(values, cam_angle, cam_rise_angle, cam_far_dwell):
    """Largest |value| over the rise and the far dwell."""
    mask = np.mod(np.asarray(cam_angle), 2 * np.pi) < cam_rise_angle + cam_far_dwell - 1e-12
    mask &= np.asarray(cam_angle) < 2 * np.pi - 1e-12
    return float(np.max(np.abs(np.asarray(values)[mask])))


def return_part_max(values, cam_angle, cam_rise_angle, cam_far_dwell):
    """Largest |value| over the return and the near dwell."""
    mask = ~(np.mod(np.asarray(cam_angle), 2 * np.pi) < cam_rise_angle + cam_far_dwell - 1e-12)
    mask |= np.asarray(cam_angle) >= 2 * np.pi - 1e-12
    return float(np.max(np.abs(np.asarray(values)[mask])))


def convex_min(values):
    """Smallest positive value (the sharpest convex part) [same unit]."""
    values = np.asarray(values, dtype=float)
    positive = values[np.isfinite(values) & (values > 0)]
    return float(positive.min()) if positive.size else np.nan


def base_offset(cam_base_radius, cam_offset):
    """s0 = √(r0² − e²) [m]."""
    return np.sqrt(cam_base_radius ** 2 - cam_offset ** 2)


def checks_pass(cam_max_pressure_angle, cam_allowable_pressure_angle,
                cam_max_return_pressure_angle, cam_allowable_return_pressure_angle,
                cam_min_curvature_radius, cam_roller_radius, cam_base_radius,
                cam_min_base_radius_allowed):
    """1 when the pressure angles are within [α] and [α]′, the convex pitch curve is
    sharper nowhere than the roller, and r0 ≥ r0min; else 0."""
    ok = (cam_max_pressure_angle <= cam_allowable_pressure_angle
          and cam_max_return_pressure_angle <= cam_allowable_return_pressure_angle
          and cam_min_curvature_radius > cam_roller_radius
          and cam_base_radius >= cam_min_base_radius_allowed)
    return 1.0 if ok else 0.0


# ---------------------------------------------------------------- valve timing
def event_after(dead_centre, event):
    """A valve event's crank angle: the dead centre plus the event [rad]."""
    return dead_centre + event


def event_after_second_bdc(dead_centre, event):
    """An event about the second revolution's BDC, 2π + (π + θ) + event [rad]."""
    return 2 * np.pi + dead_centre + event


def event_after_cycle(event):
    """An event about the end of the cycle (TDC at 4π) [rad]."""
    return 4 * np.pi + event


def duration(opens, closes):
    """closes − opens [rad]."""
    return closes - opens


def working_angle(ratio, rise_angle, far_dwell, return_angle):
    """The crank angle a cam keeps its valve open, i·(Φ + Φs + Φ′) [rad]."""
    return ratio * (rise_angle + far_dwell + return_angle)


def durations_match(intake_open_duration, intake_cam_working_angle, exhaust_open_duration,
                    exhaust_cam_working_angle):
    """1 when both open durations equal their cams' working angles within 0.5°, else 0."""
    half = np.radians(0.5)
    return 1.0 if (abs(intake_open_duration - intake_cam_working_angle) <= half + 1e-12
                   and abs(exhaust_open_duration - exhaust_cam_working_angle) <= half + 1e-12) \
        else 0.0


def mounting_angle(open_angle, ratio):
    """Cam angle at crank angle 0: (−φ_open/i) mod 2π [rad]."""
    return np.mod(-open_angle / ratio, 2 * np.pi)


def cam_angle_at(crank_angle, open_angle, ratio):
    """The cam angle at each crank angle, ((φ − φ_open)/i) mod 2π [rad]."""
    return np.mod((np.asarray(crank_angle, dtype=float) - open_angle) / ratio, 2 * np.pi)


def roller_fits(cam_min_curvature_radius, cam_roller_radius):
    """1 where the roller is smaller than the sharpest convex part of the pitch curve."""
    return 1.0 if cam_min_curvature_radius > cam_roller_radius else 0.0


def rise_progress(cam_angle, cam_rise_angle):
    """u = δ/Φ (a helper column: the laws' argument on the rise) [-]."""
    return np.asarray(cam_angle, dtype=float) / cam_rise_angle


def return_progress(cam_angle, cam_rise_angle, cam_far_dwell, cam_return_angle):
    """u′ = (δ − Φ − Φs)/Φ′ (the laws' argument on the return) [-]."""
    return (np.asarray(cam_angle, dtype=float) - cam_rise_angle - cam_far_dwell) \
        / cam_return_angle
