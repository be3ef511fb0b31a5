"""The course-design offset slider-crank (seed 001, "四冲程内燃机设计"; seed 003).

Frame: x horizontal, y vertical up; O the crank centre, cylinder vertical with
the piston above O on the line x = e.  The crank turns clockwise at ω; ψ is the
crank angle measured clockwise from +y, φ = ψ − ψ_top the crank angle from the
highest piston position, ψ_top = asin(e/(l + r)).  With e > 0 the downstroke
(highest to lowest position) takes π + θ of crank rotation.  The rod angle β to
the cylinder axis has sinβ = (r·sinψ − e)/l; A = r(sinψ, cosψ), B = (e, y_B).

Slider displacement, velocity and acceleration (positive away from the highest
position) are :mod:`calc.kinematics`'s exact formulas with α = φ.  Angular
quantities of the rod are positive counter-clockwise.
"""
import numpy as np

from crankbook.calc.kinematics import crank_angle_from_axis, piston_acceleration_exact, rod_angle


# --- synthesis from stroke, offset and time ratio ---------------------------------

def extreme_angle(time_ratio):
    """Crank angle between the two extreme positions θ = π(K − 1)/(K + 1) [rad]."""
    return np.pi * (np.asarray(time_ratio) - 1) / (np.asarray(time_ratio) + 1)


def crank_radius_from_design(stroke, offset, time_ratio):
    """Crank radius a = ½·√(H² − 2eH·tan(θ/2)) [m] (seed 003: law of cosines in
    △AC1C2 with e = (b² − a²)·sinθ/H)."""
    half = extreme_angle(time_ratio) / 2
    return 0.5 * np.sqrt(stroke ** 2 - 2 * offset * stroke * np.tan(half))


def rod_length_from_design(stroke, offset, time_ratio):
    """Rod length b = ½·√(H² + 2eH/tan(θ/2)) [m]."""
    half = extreme_angle(time_ratio) / 2
    return 0.5 * np.sqrt(stroke ** 2 + 2 * offset * stroke / np.tan(half))


def min_transmission_angle(crank_radius, rod_length, offset):
    """Minimum transmission angle γ_min = acos((r + |e|)/l) [rad]."""
    return np.arccos((crank_radius + np.abs(offset)) / rod_length)


def lowest_position_angle(crank_radius, rod_length, offset):
    """Crank angle φ of the lowest piston position, π + asin(e/(l−r)) − asin(e/(l+r)) [rad]."""
    return (np.pi + np.arcsin(offset / (rod_length - crank_radius))
            - np.arcsin(offset / (rod_length + crank_radius)))


# --- the 15 positions ------------------------------------------------------------

def max_speed_start_down(crank_radius, rod_length, offset):
    """Newton start for the maximum-speed position of the downstroke [rad]."""
    return max_speed_start(crank_radius, rod_length, offset, upstroke=False)


def max_speed_start_up(crank_radius, rod_length, offset):
    """Newton start for the maximum-speed position of the upstroke [rad]."""
    return max_speed_start(crank_radius, rod_length, offset, upstroke=True)


def max_speed_start(crank_radius, rod_length, offset, upstroke):
    """Newton start for a maximum-speed position: the centric root of a(ψ) = 0,
    cosψ = (√(1 + 8λ²) − 1)/(4λ), shifted by ψ_top [rad]."""
    lam = crank_radius / rod_length
    psi = np.arccos((np.sqrt(1 + 8 * lam ** 2) - 1) / (4 * lam))
    psi_top = np.arcsin(offset / (crank_radius + rod_length))
    return (2 * np.pi - psi if upstroke else psi) - psi_top


def acceleration_slope(crank_angle, crank_radius, rod_length, offset, speed):
    """d a/dφ, the slope of the slider acceleration over crank angle [m/s² per rad]."""
    psi = crank_angle_from_axis(crank_angle, crank_radius, rod_length, offset)
    beta = rod_angle(crank_angle, crank_radius, rod_length, offset)
    lam = crank_radius / rod_length
    dbeta = lam * np.cos(psi) / np.cos(beta)
    return speed ** 2 * crank_radius * (
        -np.sin(psi) - np.cos(psi) * np.tan(beta) - np.sin(psi) * dbeta / np.cos(beta) ** 2
        + lam * (-2 * np.cos(psi) * np.sin(psi) / np.cos(beta) ** 3
                 + 3 * np.cos(psi) ** 2 * np.sin(beta) * dbeta / np.cos(beta) ** 4))


def newton_iterates(step_index, start, crank_radius, rod_length, offset, speed):
    """Newton's iterates φ_k+1 = φ_k − a(φ_k)/a′(φ_k) for a root of the slider
    acceleration (a maximum of the slider speed), one per row of ``step_index`` [rad]."""
    out = np.empty(np.shape(step_index))
    angle = float(start)
    for k in range(out.size):
        out[k] = angle
        angle = angle - (piston_acceleration_exact(angle, crank_radius, rod_length, offset, speed)
                         / acceleration_slope(angle, crank_radius, rod_length, offset, speed))
    return out


def raw_position_angles(step_index, lowest_position_angle, max_speed_angle_down,
                        max_speed_angle_up):
    """The 15 positions of one revolution, unsorted: 12 divisions of 30° from the
    highest position, the lowest position and the two maximum-speed positions [rad]."""
    index = np.asarray(step_index, dtype=float)
    extra = {12: lowest_position_angle, 13: max_speed_angle_down, 14: max_speed_angle_up}
    return np.array([extra.get(int(i), np.pi / 6 * i) for i in index])


def position_angles(raw_position_angle):
    """The 30 positions of the cycle: the 15 sorted, then the same + 2π [rad]."""
    ordered = np.sort(np.asarray(raw_position_angle, dtype=float))
    return np.concatenate([ordered, ordered + 2 * np.pi])


# --- rod kinematics ----------------------------------------------------------------

def rod_angular_velocity(crank_angle, crank_radius, rod_length, offset, speed):
    """ω2 = r·ω·cosψ/(l·cosβ) [rad/s], counter-clockwise positive (crank clockwise)."""
    psi = crank_angle_from_axis(crank_angle, crank_radius, rod_length, offset)
    beta = rod_angle(crank_angle, crank_radius, rod_length, offset)
    return crank_radius * speed * np.cos(psi) / (rod_length * np.cos(beta))


def rod_angular_acceleration(crank_angle, crank_radius, rod_length, offset, speed):
    """α2 = (r·ω²/l)·[−sinψ/cosβ + r·cos²ψ·sinβ/(l·cos³β)] [rad/s²], counter-clockwise +."""
    psi = crank_angle_from_axis(crank_angle, crank_radius, rod_length, offset)
    beta = rod_angle(crank_angle, crank_radius, rod_length, offset)
    return crank_radius * speed ** 2 / rod_length * (
        -np.sin(psi) / np.cos(beta)
        + crank_radius * np.cos(psi) ** 2 * np.sin(beta) / (rod_length * np.cos(beta) ** 3))


def rod_relative_velocity(rod_angular_velocity, rod_length):
    """Relative velocity of B about A, v_BA = l·|ω2| [m/s]."""
    return rod_length * np.abs(rod_angular_velocity)


def rod_normal_acceleration(rod_angular_velocity, rod_length):
    """Normal relative acceleration of B about A, a^n_BA = l·ω2² [m/s²] (toward A)."""
    return rod_length * np.asarray(rod_angular_velocity) ** 2


def rod_tangential_acceleration(rod_angular_acceleration, rod_length):
    """Tangential relative acceleration of B about A, a^t_BA = l·α2 [m/s²], signed as α2."""
    return rod_length * np.asarray(rod_angular_acceleration)


def rod_cg_velocity_x(crank_angle_from_axis, crank_radius, speed, rod_cg_ratio):
    """x component of the rod centre-of-gravity velocity, (1 − k)·r·ω·cosψ [m/s]."""
    return (1 - rod_cg_ratio) * crank_radius * speed * np.cos(crank_angle_from_axis)


def rod_cg_velocity_y(crank_angle_from_axis, crank_radius, speed, rod_cg_ratio, slider_velocity):
    """y component (up +), −(1 − k)·r·ω·sinψ − k·v_B [m/s]."""
    return (-(1 - rod_cg_ratio) * crank_radius * speed * np.sin(crank_angle_from_axis)
            - rod_cg_ratio * np.asarray(slider_velocity))


def rod_cg_acceleration_x(crank_angle_from_axis, crank_radius, speed, rod_cg_ratio):
    """x component of the rod centre-of-gravity acceleration, −(1 − k)·r·ω²·sinψ [m/s²]."""
    return -(1 - rod_cg_ratio) * crank_radius * speed ** 2 * np.sin(crank_angle_from_axis)


def rod_cg_acceleration_y(crank_angle_from_axis, crank_radius, speed, rod_cg_ratio,
                          slider_acceleration):
    """y component (up +), −(1 − k)·r·ω²·cosψ − k·a_B [m/s²]."""
    return (-(1 - rod_cg_ratio) * crank_radius * speed ** 2 * np.cos(crank_angle_from_axis)
            - rod_cg_ratio * np.asarray(slider_acceleration))


def magnitude(x, y):
    """√(x² + y²)."""
    return np.hypot(x, y)


# --- kinetostatic analysis (动态静力分析) -----------------------------------------------

def piston_load(gas_force, piston_weight, piston_mass, slider_acceleration):
    """Vertical load on the piston, up +: −(F_g + Q3 − m3·a_B) [N] (gas, gravity, inertia)."""
    return -(np.asarray(gas_force) + piston_weight - piston_mass * np.asarray(slider_acceleration))


def rod_load_x(rod_mass, rod_cg_acceleration_x):
    """Horizontal load on the rod at C2: inertia −m2·a_C2x [N]."""
    return -rod_mass * np.asarray(rod_cg_acceleration_x)


def rod_load_y(rod_mass, rod_cg_acceleration_y, rod_weight):
    """Vertical load on the rod at C2, up +: −m2·a_C2y − Q2 [N]."""
    return -rod_mass * np.asarray(rod_cg_acceleration_y) - rod_weight


def rod_inertia_moment(rod_mass, rod_gyration_radius, rod_angular_acceleration):
    """Inertia moment of the rod −J_C2·α2, J_C2 = m2·ρ² [N·m], counter-clockwise +."""
    return -rod_mass * rod_gyration_radius ** 2 * np.asarray(rod_angular_acceleration)


def wall_reaction(rod_angle, rod_length, rod_cg_ratio, rod_load_x, rod_load_y, piston_load,
                  rod_inertia_moment):
    """Cylinder wall on the piston R03 (horizontal, +x) [N], from ΣM_B = 0 on the rod:
    R03 = −k·(F2x + F2y·tanβ) − F3y·tanβ + M2/(l·cosβ)."""
    tan = np.tan(rod_angle)
    return (-rod_cg_ratio * (np.asarray(rod_load_x) + np.asarray(rod_load_y) * tan)
            - np.asarray(piston_load) * tan + np.asarray(rod_inertia_moment)
            / (rod_length * np.cos(rod_angle)))


def crank_pin_force_x(rod_load_x, wall_reaction):
    """R12x, the crank on the rod at A [N]: −F2x − R03."""
    return -np.asarray(rod_load_x) - wall_reaction


def crank_pin_force_y(rod_load_y, piston_load):
    """R12y, the crank on the rod at A [N], up +: −F2y − F3y."""
    return -np.asarray(rod_load_y) - piston_load


def crank_pin_force_normal(crank_pin_force_x, crank_pin_force_y, rod_angle):
    """R12^n, along the rod from A toward B [N]."""
    return (-np.asarray(crank_pin_force_x) * np.sin(rod_angle)
            + np.asarray(crank_pin_force_y) * np.cos(rod_angle))


def crank_pin_force_tangential(crank_pin_force_x, crank_pin_force_y, rod_angle):
    """R12^t, perpendicular to the rod (the along-rod direction turned 90° CCW) [N]."""
    return (-np.asarray(crank_pin_force_x) * np.cos(rod_angle)
            - np.asarray(crank_pin_force_y) * np.sin(rod_angle))


def main_bearing_force_x(crank_pin_force_x, crank_mass, crank_cg_radius, speed,
                         crank_angle_from_axis):
    """R01x, the frame on the crank at O [N]: R12x − m1·ω²·l_OC·sinψ."""
    return (np.asarray(crank_pin_force_x)
            - crank_mass * speed ** 2 * crank_cg_radius * np.sin(crank_angle_from_axis))


def main_bearing_force_y(crank_pin_force_y, crank_weight, crank_mass, crank_cg_radius, speed,
                         crank_angle_from_axis):
    """R01y, up + [N]: R12y + Q1 − m1·ω²·l_OC·cosψ."""
    return (np.asarray(crank_pin_force_y) + crank_weight
            - crank_mass * speed ** 2 * crank_cg_radius * np.cos(crank_angle_from_axis))


def balancing_torque(crank_angle_from_axis, crank_radius, crank_pin_force_x, crank_pin_force_y,
                     crank_weight, crank_cg_radius):
    """Balancing torque M_b on the crank [N·m], positive in the (clockwise) sense of rotation:
    M_b = −[r·(sinψ·R12y − cosψ·R12x) + l_OC·Q1·sinψ]  (ΣM_O = 0 on the crank)."""
    psi = np.asarray(crank_angle_from_axis)
    return -(crank_radius * (np.sin(psi) * crank_pin_force_y - np.cos(psi) * crank_pin_force_x)
             + crank_cg_radius * crank_weight * np.sin(psi))


def driving_torque(balancing_torque):
    """Driving torque M_d = −M_b [N·m] (the seed's section 7 uses the M_b curve as M_d)."""
    return -np.asarray(balancing_torque)


# --- flywheel (seed 001 §7) ---------------------------------------------------------

def closed_cycle_mean(crank_angle, values, cycle=4 * np.pi):
    """Trapezoidal mean over the closed cycle 0…``cycle`` [rad]; the last point joins the
    first, one cycle on [-]."""
    x = np.asarray(crank_angle, dtype=float)
    y = np.asarray(values, dtype=float)
    area = np.sum((y[1:] + y[:-1]) / 2 * np.diff(x)) + (y[-1] + y[0]) / 2 * (cycle - x[-1])
    return area / cycle


def energy_fluctuation(crank_angle, driving_torque, resisting_torque):
    """Running work surplus ΔE(φ) = ∫₀^φ (M_d − M_r) dφ by trapezoids [J] (盈亏功)."""
    x = np.asarray(crank_angle, dtype=float)
    y = np.asarray(driving_torque, dtype=float)
    steps = ((y[1:] + y[:-1]) / 2 - resisting_torque) * np.diff(x)
    return np.concatenate([[0.0], np.cumsum(steps)])


def energy_swing(energy):
    """ΔW_max = max ΔE − min ΔE [J]."""
    return float(np.max(energy) - np.min(energy))


def flywheel_inertia(energy_swing, speed, speed_fluctuation):
    """Flywheel moment of inertia J_F = ΔW_max/(ω_m²·[δ]) [kg·m²] (link inertias neglected)."""
    return energy_swing / (speed ** 2 * speed_fluctuation)


def weight_to_mass(weight, gravity):
    """m = Q/g [kg]."""
    return weight / gravity


def scaled_length(ratio, length):
    """ratio × length [m]."""
    return ratio * length


def at_least(value, bound):
    """1 where value ≥ bound, else 0 (a design check)."""
    return np.where(np.asarray(value) >= bound, 1.0, 0.0)


def equivalent_ring_mass(reciprocating_mass, rotating_mass, crank_rod_ratio, samples=100000):
    """Mass at the crank pin with the mean kinetic energy of the piston–rod group over a
    revolution [kg] (seed 004 §2), by numerical averaging of ½m1v1² + ½m2v2² with the
    series piston velocity v1 = Rω(sinα + λ/2·sin2α) and v2 = Rω (R = ω = 1)."""
    alpha = np.linspace(0, 2 * np.pi, samples, endpoint=False)
    v1 = np.sin(alpha) + crank_rod_ratio / 2 * np.sin(2 * alpha)
    return float(np.mean(reciprocating_mass * v1 ** 2 + rotating_mass))
