"""A reciprocating air compressor (seed 002 §4.1–4.2): multi-stage gas forces with
re-expansion, suction, compression and discharge; column forces with friction;
torque; volumetric efficiency and delivery.

Each column (a crank throw with its piston) reaches its head-end dead centre at its
phase φ_c; its own crank angle is α_c = (α − φ_c) mod 360°, and its piston stands x
from the head-end dead centre (exact, centric): x = r(1 − cos α_c) + l − √(l² −
r²·sin²α_c).  Each stage works on the head end of its column's piston; with the
clearance as an equivalent length Sc, its pressure over a revolution is

* moving away from the head (α_c < 180°): re-expansion p = pd·(Sc/(x + Sc))^m down to
  the suction pressure, then suction at ps:  p = max(ps, pd·(Sc/(x + Sc))^m);
* moving toward the head: compression p = ps·((S + Sc)/(x + Sc))^n up to the
  discharge pressure, then discharge at pd:  p = min(pd, ps·((S + Sc)/(x + Sc))^n)

(seed 002 eqs. 4.13, 4.14).  Forces on the piston are positive toward the crankshaft,
as in the engine workbook.  SI units; per-column series (N + 1, c), per-stage (N + 1, s).
"""
import numpy as np


def column_angle(crank_angle, column_phase):
    """α_c = (α − φ_c) mod 2π of each column [rad] (N + 1, c)."""
    alpha = np.asarray(crank_angle, dtype=float).reshape(-1, 1)
    return np.mod(alpha - np.asarray(column_phase, dtype=float), 2 * np.pi)


def column_displacement(column_angle, crank_radius, rod_length):
    """x from the head-end dead centre [m]."""
    a = np.asarray(column_angle, dtype=float)
    return crank_radius * (1 - np.cos(a)) + rod_length \
        - np.sqrt(rod_length ** 2 - (crank_radius * np.sin(a)) ** 2)


def column_rod_angle(column_angle, crank_rod_ratio):
    """β = asin(λ·sin α_c) [rad]."""
    return np.arcsin(crank_rod_ratio * np.sin(np.asarray(column_angle, dtype=float)))


def column_acceleration(column_angle, column_rod_angle, crank_radius, crank_rod_ratio,
                        angular_velocity):
    """Piston acceleration toward the crankshaft, exact [m/s²]."""
    a, b = np.asarray(column_angle, dtype=float), np.asarray(column_rod_angle, dtype=float)
    return angular_velocity ** 2 * crank_radius * (np.cos(a) - np.sin(a) * np.tan(b)
                                                   + crank_rod_ratio * np.cos(a) ** 2
                                                   / np.cos(b) ** 3)


def _of_stage(column_values, stage_column):
    return np.asarray(column_values, dtype=float)[:, np.asarray(stage_column, int) - 1]


def stage_pressure(column_angle, column_displacement, stage_column, stroke,
                   stage_clearance_length, stage_suction_pressure, stage_discharge_pressure,
                   stage_expansion_exponent, stage_compression_exponent):
    """Cylinder pressure of each stage over the revolution [Pa] (N + 1, s)."""
    a = _of_stage(column_angle, stage_column)
    x = _of_stage(column_displacement, stage_column)
    sc, ps, pd = (np.asarray(v, dtype=float) for v in
                  (stage_clearance_length, stage_suction_pressure, stage_discharge_pressure))
    expansion = np.maximum(ps, pd * (sc / (x + sc)) ** np.asarray(stage_expansion_exponent))
    compression = np.minimum(pd, ps * ((stroke + sc) / (x + sc))
                             ** np.asarray(stage_compression_exponent))
    return np.where(a < np.pi, expansion, compression)


def stage_area(stage_bore):
    """Piston area of each stage πD²/4 [m²]."""
    return np.pi * np.asarray(stage_bore, dtype=float) ** 2 / 4


def stage_gas_force(stage_pressure, ambient_pressure, stage_area):
    """(p − p_back)·A of each stage [N]."""
    return (np.asarray(stage_pressure) - ambient_pressure) * np.asarray(stage_area)


def stage_volume(column_displacement, stage_column, stage_area, stage_clearance_length):
    """Cylinder volume of each stage A·(x + Sc) [m³]."""
    x = _of_stage(column_displacement, stage_column)
    return np.asarray(stage_area) * (x + np.asarray(stage_clearance_length))


def stage_indicated_power(stage_pressure, stage_volume, speed):
    """Power the gas takes from each stage, −∮p·dV per revolution × n [W] (speed ω in
    rad/s: revolutions per second ω/2π), trapezoidal rule over the closed loop."""
    p, v = np.asarray(stage_pressure, dtype=float), np.asarray(stage_volume, dtype=float)
    work = np.sum((p[1:] + p[:-1]) / 2 * np.diff(v, axis=0), axis=0)
    return -work * speed / (2 * np.pi)


def per_column(stage_values, stage_column, column_phase):
    """Σ over the stages on each column (N + 1, c)."""
    stage_column = np.asarray(stage_column, dtype=float)
    columns = np.arange(1, np.size(column_phase) + 1, dtype=float)
    return np.asarray(stage_values, dtype=float) @ (stage_column[:, None]
                                                     == columns[None, :]).astype(float)


def friction_magnitude(friction_coefficient, stage_indicated_power, mechanical_efficiency,
                       stroke, speed):
    """f = k·N_i·(1/η_m − 1)/(2·S·n) (seed 002 eq. 4.16; n in revolutions per second) [N]."""
    total = np.sum(np.asarray(stage_indicated_power, dtype=float))
    return friction_coefficient * total * (1 / mechanical_efficiency - 1) \
        / (2 * stroke * speed / (2 * np.pi))


def column_friction_force(column_angle, friction_magnitude):
    """Friction against the piston's motion: −f moving away from the head, +f toward
    it, 0 at the dead centres (decided by the crank angle) [N]."""
    a = np.asarray(column_angle, dtype=float)
    dead = np.isclose(np.mod(a, np.pi), 0.0, atol=1e-9) | np.isclose(np.mod(a, np.pi), np.pi,
                                                                      atol=1e-9)
    return np.where(dead, 0.0, np.where(a < np.pi, -friction_magnitude, friction_magnitude))


def column_mass(piston_mass, rod_mass, rod_small_end_share):
    """Reciprocating mass of each column m_p = m_s + share·m_d (seed 002 eq. 4.10) [kg]."""
    return np.asarray(piston_mass) + np.asarray(rod_small_end_share) * np.asarray(rod_mass)


def column_rotating_mass(rod_mass, rod_small_end_share):
    """The rod's big-end share that rotates with the pin, m2 = (1 − share)·m_d [kg]."""
    return (1 - np.asarray(rod_small_end_share, dtype=float)) * np.asarray(rod_mass, dtype=float)


def crankpin_load_tangential(column_tangential_force):
    """Tangential load on each column's crank pin: the rod's tangential force [N]."""
    return np.asarray(column_tangential_force, dtype=float)


def crankpin_load_radial(column_radial_force, column_rotating_mass, crank_radius,
                         angular_velocity):
    """Radial load on each column's crank pin, toward the crank centre: the rod's
    radial force less its big end's centrifugal force m2·r·ω² [N]."""
    return np.asarray(column_radial_force, dtype=float) \
        - np.asarray(column_rotating_mass, dtype=float) * crank_radius * angular_velocity ** 2


def journal_torque(column_torque):
    """Torque in the main journal ahead of each column: the torques of the columns
    before it along the shaft (column 1 at the free end) [N·m]."""
    torque = np.asarray(column_torque, dtype=float)
    return np.cumsum(torque, axis=1) - torque


def column_inertia_force(column_reciprocating_mass, column_acceleration):
    """−m_p·a [N]."""
    return -np.asarray(column_reciprocating_mass) * np.asarray(column_acceleration)


def column_sum3(column_gas_force, column_inertia_force, column_friction_force):
    """P_t = P + I + f (eq. 4.12) [N]."""
    return np.asarray(column_gas_force) + np.asarray(column_inertia_force) \
        + np.asarray(column_friction_force)


def column_tangential_force(column_piston_force, column_angle, column_rod_angle):
    """F·sin(α + β)/cos β [N]."""
    b = np.asarray(column_rod_angle)
    return np.asarray(column_piston_force) * np.sin(np.asarray(column_angle) + b) / np.cos(b)


def column_radial_force(column_piston_force, column_angle, column_rod_angle):
    """F·cos(α + β)/cos β, toward the crank centre [N] (eq. 4.17 is the same)."""
    b = np.asarray(column_rod_angle)
    return np.asarray(column_piston_force) * np.cos(np.asarray(column_angle) + b) / np.cos(b)


def column_side_force(column_piston_force, column_rod_angle):
    """F·tan β [N]."""
    return np.asarray(column_piston_force) * np.tan(np.asarray(column_rod_angle))


def column_rod_force(column_piston_force, column_rod_angle):
    """F/cos β [N]."""
    return np.asarray(column_piston_force) / np.cos(np.asarray(column_rod_angle))


def shaft_power(mean_torque, angular_velocity):
    """The power absorbed, −M_mean·ω [W]."""
    return -mean_torque * angular_velocity


def expansion_end_displacement(stage_clearance_length, stage_suction_pressure,
                               stage_discharge_pressure, stage_expansion_exponent):
    """x_e = Sc·((pd/ps)^(1/m) − 1) [m]."""
    return np.asarray(stage_clearance_length) * (
        (np.asarray(stage_discharge_pressure) / np.asarray(stage_suction_pressure))
        ** (1 / np.asarray(stage_expansion_exponent)) - 1)


def compression_end_displacement(stroke, stage_clearance_length, stage_suction_pressure,
                                 stage_discharge_pressure, stage_compression_exponent):
    """x_c = (S + Sc)·(ps/pd)^(1/n) − Sc [m]."""
    sc = np.asarray(stage_clearance_length)
    return (stroke + sc) * (np.asarray(stage_suction_pressure)
                            / np.asarray(stage_discharge_pressure)) \
        ** (1 / np.asarray(stage_compression_exponent)) - sc


def angle_of_displacement(displacement, crank_radius, rod_length):
    """The crank angle in [0, π] where the piston stands x from the head-end dead
    centre: cos α = (A² − l² + r²)/(2Ar), A = r + l − x [rad]."""
    a = crank_radius + rod_length - np.asarray(displacement, dtype=float)
    return np.arccos((a ** 2 - rod_length ** 2 + crank_radius ** 2) / (2 * a * crank_radius))


def stage_expansion_end_angle(stage_expansion_end_displacement, crank_radius, rod_length,
                              stage_column, column_phase):
    """Where re-expansion ends, in column 1's crank angle [rad]."""
    phase = np.asarray(column_phase, dtype=float)[np.asarray(stage_column, int) - 1]
    return np.mod(angle_of_displacement(stage_expansion_end_displacement, crank_radius,
                                        rod_length) + phase, 2 * np.pi)


def stage_compression_end_angle(stage_compression_end_displacement, crank_radius, rod_length,
                                stage_column, column_phase):
    """Where compression ends (discharge begins), in column 1's crank angle [rad]."""
    phase = np.asarray(column_phase, dtype=float)[np.asarray(stage_column, int) - 1]
    return np.mod(2 * np.pi - angle_of_displacement(stage_compression_end_displacement,
                                                    crank_radius, rod_length) + phase,
                  2 * np.pi)


def volumetric_efficiency(stage_expansion_end_displacement, stroke):
    """λv = 1 − x_e/S [-]."""
    return 1 - np.asarray(stage_expansion_end_displacement) / stroke


def free_air_delivery(stage_volumetric_efficiency, stage_area, stroke, speed):
    """λv1·A1·S·n of the first stage [m³/s] (speed ω in rad/s)."""
    return np.asarray(stage_volumetric_efficiency)[0] * np.asarray(stage_area)[0] * stroke \
        * speed / (2 * np.pi)


def stage_count_beyond(stage_column, column_phase):
    """1 for a stage on a column that does not exist."""
    return np.where(np.asarray(stage_column) > np.size(column_phase), 1.0, 0.0)


def suction_above_previous_discharge(stage_suction_pressure, stage_discharge_pressure):
    """1 for a stage (after the first) whose suction pressure is above the previous
    stage's discharge pressure: between stages the gas only loses pressure."""
    suction = np.asarray(stage_suction_pressure, dtype=float)
    discharge = np.asarray(stage_discharge_pressure, dtype=float)
    above = np.zeros(suction.shape)
    above[1:] = suction[1:] > discharge[:-1]
    return above


def suction_not_below_discharge(stage_suction_pressure, stage_discharge_pressure):
    """1 for a stage whose suction pressure is not below its discharge pressure."""
    return np.where(np.asarray(stage_suction_pressure) >= np.asarray(stage_discharge_pressure),
                    1.0, 0.0)
