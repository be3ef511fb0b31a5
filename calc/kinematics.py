"""Piston and connecting-rod kinematics of the (offset) crank–slider mechanism.

Geometry (seed 003, §二; thesis 000, §2.2.1): the crank of radius ``r`` turns about
O with constant angular speed ``ω``; the piston pin moves on a line parallel to the
cylinder axis at distance ``e`` (the pin-axis offset) from O.  ``α`` is the crank
angle measured from top dead centre (TDC), ``ψ = α + θ1`` the crank angle measured
from the cylinder axis, where ``θ1 = asin(e/(r+l))`` is the crank position at TDC.
The rod angle is ``β = asin((r·sin ψ − e)/l)``.  Displacement ``s`` is measured from
TDC, positive toward the crankshaft; velocity and acceleration are its first and
second time derivatives.

Seed 003 prints the velocity as ``ω[r·tanβ·cosψ + sinψ]``: the second term lacks the
factor ``r``.  Differentiating ``s`` gives ``ds/dψ = r·sin(ψ+β)/cosβ``, used here.
"""
import numpy as np


def offset_angle(crank_radius, rod_length, offset):
    """Crank angle from the cylinder axis at TDC, θ1 = asin(e/(r+l)) [rad]."""
    return np.arcsin(np.asarray(offset) / (np.asarray(crank_radius) + rod_length))


def crank_angle_from_axis(crank_angle, crank_radius, rod_length, offset):
    """ψ = α + θ1: crank angle measured from the cylinder axis [rad].

    Parameters
    ----------
    crank_angle : array_like
        α, crank angle from TDC [rad].
    crank_radius, rod_length, offset : float
        r, l, e [m].
    """
    return np.asarray(crank_angle) + offset_angle(crank_radius, rod_length, offset)


def rod_angle(crank_angle, crank_radius, rod_length, offset):
    """Connecting-rod angle to the cylinder axis, β = asin((r·sinψ − e)/l) [rad]."""
    psi = crank_angle_from_axis(crank_angle, crank_radius, rod_length, offset)
    return np.arcsin((crank_radius * np.sin(psi) - offset) / rod_length)


def stroke(crank_radius, rod_length, offset):
    """Piston stroke, √((l+r)² − e²) − √((l−r)² − e²) [m]; 2r when e = 0."""
    return (np.sqrt((rod_length + crank_radius) ** 2 - offset ** 2)
            - np.sqrt((rod_length - crank_radius) ** 2 - offset ** 2))


def piston_displacement_exact(crank_angle, crank_radius, rod_length, offset):
    """Piston displacement from TDC, exact (seed 003) [m].

    s = √((r+l)² − e²) − r·cosψ − l·cosβ
    """
    psi = crank_angle_from_axis(crank_angle, crank_radius, rod_length, offset)
    beta = rod_angle(crank_angle, crank_radius, rod_length, offset)
    return (np.sqrt((crank_radius + rod_length) ** 2 - offset ** 2)
            - crank_radius * np.cos(psi) - rod_length * np.cos(beta))


def piston_velocity_exact(crank_angle, crank_radius, rod_length, offset, speed):
    """Piston velocity, positive toward the crankshaft, exact [m/s].

    v = ω·r·sin(ψ+β)/cosβ   (derivative of :func:`piston_displacement_exact`)

    Parameters
    ----------
    speed : float
        ω, crankshaft angular speed [rad/s].
    """
    psi = crank_angle_from_axis(crank_angle, crank_radius, rod_length, offset)
    beta = rod_angle(crank_angle, crank_radius, rod_length, offset)
    return speed * crank_radius * np.sin(psi + beta) / np.cos(beta)


def piston_acceleration_exact(crank_angle, crank_radius, rod_length, offset, speed):
    """Piston acceleration, positive toward the crankshaft, exact [m/s²].

    a = ω²·r·[cosψ − sinψ·tanβ + r·cos²ψ / (l·cos³β)]   (seed 003)
    """
    psi = crank_angle_from_axis(crank_angle, crank_radius, rod_length, offset)
    beta = rod_angle(crank_angle, crank_radius, rod_length, offset)
    return speed ** 2 * crank_radius * (
        np.cos(psi) - np.sin(psi) * np.tan(beta)
        + crank_radius * np.cos(psi) ** 2 / (rod_length * np.cos(beta) ** 3))


# --- the thesis's second-order series (centric mechanism, thesis §2.2.1) -------

def piston_displacement_first_order(crank_angle, crank_radius):
    """First-order part of the series displacement, r·(1 − cosα) [m]."""
    return crank_radius * (1 - np.cos(crank_angle))


def piston_displacement_second_order(crank_angle, crank_radius, rod_length):
    """Second-order part of the series displacement, r·λ/4·(1 − cos2α) [m]."""
    return crank_radius ** 2 / rod_length / 4 * (1 - np.cos(2 * np.asarray(crank_angle)))


def piston_displacement_series(crank_angle, crank_radius, rod_length):
    """Series displacement r·[(1 − cosα) + λ/4·(1 − cos2α)], λ = r/l [m]."""
    return (piston_displacement_first_order(crank_angle, crank_radius)
            + piston_displacement_second_order(crank_angle, crank_radius, rod_length))


def piston_velocity_first_order(crank_angle, crank_radius, speed):
    """First-order series velocity r·ω·sinα [m/s]."""
    return crank_radius * speed * np.sin(crank_angle)


def piston_velocity_second_order(crank_angle, crank_radius, rod_length, speed):
    """Second-order series velocity r·ω·λ/2·sin2α [m/s]."""
    return crank_radius ** 2 / rod_length * speed / 2 * np.sin(2 * np.asarray(crank_angle))


def piston_velocity_series(crank_angle, crank_radius, rod_length, speed):
    """Series velocity r·ω·(sinα + λ/2·sin2α) [m/s]."""
    return (piston_velocity_first_order(crank_angle, crank_radius, speed)
            + piston_velocity_second_order(crank_angle, crank_radius, rod_length, speed))


def piston_acceleration_first_order(crank_angle, crank_radius, speed):
    """First-order series acceleration r·ω²·cosα [m/s²]."""
    return crank_radius * speed ** 2 * np.cos(crank_angle)


def piston_acceleration_second_order(crank_angle, crank_radius, rod_length, speed):
    """Second-order series acceleration r·ω²·λ·cos2α [m/s²]."""
    return crank_radius ** 2 / rod_length * speed ** 2 * np.cos(2 * np.asarray(crank_angle))


def piston_acceleration_series(crank_angle, crank_radius, rod_length, speed):
    """Series acceleration r·ω²·(cosα + λ·cos2α) [m/s²]."""
    return (piston_acceleration_first_order(crank_angle, crank_radius, speed)
            + piston_acceleration_second_order(crank_angle, crank_radius, rod_length, speed))


def choose(exact_kinematics, exact, series):
    """The exact value where ``exact_kinematics`` is 1, else the series value."""
    return np.where(np.asarray(exact_kinematics) == 1, exact, series)


def crank_rod_ratio(crank_radius, rod_length):
    """λ = r/l [-] (thesis §3.1.2: 1/3 for r = 50 mm, l = 150 mm)."""
    return np.asarray(crank_radius) / rod_length


def angular_velocity(speed):
    """Crankshaft angular velocity ω [rad/s]; ``speed`` is already ω in SI units."""
    return np.asarray(speed, dtype=float)


def mean_piston_speed(stroke, speed):
    """Mean piston speed 2·H·n = H·ω/π [m/s]."""
    return np.asarray(stroke) * speed / np.pi
