"""Forces in the crank train (thesis 000, §2.2.2 and §3.2).

Sign conventions (thesis §2.2): forces on the piston are positive toward the
crankshaft; the tangential force is positive in the sense of rotation, the radial
force positive toward the crank centre; torque = tangential force × r.
"""
import numpy as np


def piston_area(bore):
    """Piston crown projected area πD²/4 [m²]."""
    return np.pi * np.asarray(bore) ** 2 / 4


def gas_force(cylinder_pressure, ambient_pressure, bore):
    """Gas force on the piston, Fg = πD²/4·(p − p0) [N].

    Parameters
    ----------
    cylinder_pressure : array_like
        p, absolute cylinder pressure [Pa].
    ambient_pressure : float
        p0, crankcase back pressure [Pa].
    bore : float
        D [m].
    """
    return piston_area(bore) * (np.asarray(cylinder_pressure) - ambient_pressure)


def small_end_mass(rod_mass, rod_cg_from_big_end, rod_length):
    """Reciprocating (small-end) share of the rod mass, m1 = m_rod·l_cg/l [kg].

    The two-mass rod model of thesis §2.2.2 c: mass and centre of gravity kept,
    ``rod_cg_from_big_end`` is the distance of the rod's centre of gravity from the
    big-end centre [m].
    """
    return rod_mass * rod_cg_from_big_end / rod_length


def reciprocating_mass(piston_mass, rod_mass, rod_cg_from_big_end, rod_length):
    """Reciprocating mass m_j = m_piston + m1 [kg] (thesis §3.2.2: 515 g)."""
    return piston_mass + small_end_mass(rod_mass, rod_cg_from_big_end, rod_length)


def rotating_mass(crank_unbalanced_mass, rod_mass, rod_cg_from_big_end, rod_length):
    """Rotating mass at the crank-pin radius, m_r = m_k + m_rod − m1 [kg]."""
    return crank_unbalanced_mass + rod_mass - small_end_mass(rod_mass, rod_cg_from_big_end,
                                                              rod_length)


def inertia_force(reciprocating_mass, piston_acceleration):
    """Reciprocating inertia force Fj = −m_j·a [N]."""
    return -reciprocating_mass * np.asarray(piston_acceleration)


def inertia_force_first_order(reciprocating_mass, crank_angle, crank_radius, speed):
    """First-order reciprocating inertia force −m_j·r·ω²·cosα [N]."""
    return -reciprocating_mass * crank_radius * speed ** 2 * np.cos(crank_angle)


def inertia_force_second_order(reciprocating_mass, crank_angle, crank_radius, rod_length,
                               speed):
    """Second-order reciprocating inertia force −m_j·r·ω²·λ·cos2α [N]."""
    return (-reciprocating_mass * crank_radius ** 2 / rod_length * speed ** 2
            * np.cos(2 * np.asarray(crank_angle)))


def rotating_inertia_force(rotating_mass, crank_radius, speed):
    """Centrifugal force of the rotating mass, Fr = m_r·r·ω² [N], along the crank outward."""
    return rotating_mass * crank_radius * speed ** 2


def rotating_inertia_force_axial(rotating_inertia_force, crank_angle_from_axis):
    """Component of Fr along the cylinder axis, positive away from the crankshaft [N]."""
    return rotating_inertia_force * np.cos(crank_angle_from_axis)


def rotating_inertia_force_lateral(rotating_inertia_force, crank_angle_from_axis):
    """Component of Fr across the cylinder axis, positive on the side the pin swings to
    first (the side of positive offset) [N]."""
    return rotating_inertia_force * np.sin(crank_angle_from_axis)


def piston_force(gas_force, inertia_force):
    """Total force at the piston pin along the cylinder axis, F = Fg + Fj [N]."""
    return np.asarray(gas_force) + inertia_force


def side_force(piston_force, rod_angle):
    """Piston side (normal) force on the cylinder wall, F_N = F·tanβ [N]."""
    return np.asarray(piston_force) * np.tan(rod_angle)


def rod_force(piston_force, rod_angle):
    """Force along the connecting rod, F_l = F/cosβ [N], positive in compression."""
    return np.asarray(piston_force) / np.cos(rod_angle)


def tangential_force(piston_force, crank_angle_from_axis, rod_angle):
    """Tangential force at the crank pin, F·sin(ψ+β)/cosβ [N], positive with rotation."""
    return (np.asarray(piston_force) * np.sin(np.asarray(crank_angle_from_axis) + rod_angle)
            / np.cos(rod_angle))


def radial_force(piston_force, crank_angle_from_axis, rod_angle):
    """Radial force at the crank pin, F·cos(ψ+β)/cosβ [N], positive toward the centre."""
    return (np.asarray(piston_force) * np.cos(np.asarray(crank_angle_from_axis) + rod_angle)
            / np.cos(rod_angle))


def torque(tangential_force, crank_radius):
    """Single-cylinder torque M = F_t·r [N·m], positive in the sense of rotation."""
    return np.asarray(tangential_force) * crank_radius


def overturning_moment(torque):
    """Overturning (reaction) moment on the engine block, M' = −M [N·m] (thesis §2.2.2)."""
    return -np.asarray(torque)
