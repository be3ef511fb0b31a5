"""Connecting-rod strength: the shank, the small end, the big end, its cap and its
preloaded bolts, from the crank train's own forces at the design speed and at an
over-speed.

* **Loads.**  The largest compression is the largest rod force over the cycle (gas
  plus inertia, F/cos β, the rod-force sheet's column); Khurmi & Gupta design the
  shank on the gas force alone, which is shown beside it.  The largest tension is the
  reciprocating inertia less the gas force at the gas-exchange top dead centre, taken
  at the over-speed (the inertia column scaled by (n_o/n)²).  The cap and its bolts
  carry that tension plus the rotating part of the rod above the cap,
  (m_rod − m_1 − m_cap)·r·ω_o².  The small-end eye carries the piston group's inertia
  only, m_p/m_j of the reciprocating inertia.
* **Shank.**  An I-section, flanges across the plane of motion: B the flange width, H
  the height in the plane of motion, t_f and t_w the flange and web thicknesses (the
  standard proportions B = 4t, H = 5t with t_f = t_w = t give A = 11t²,
  I_xx = 419t⁴/12, I_yy = 131t⁴/12).  Buckling by Rankine–Gordon,
  W_cr = σ_c·A/(1 + a·(L/k)²), in the plane of motion with both ends pinned (L = l,
  k_xx) and out of it with both ends fixed (L = l/2, k_yy).  The Chinese texts'
  amplified stress σ = P/A·(1 + C·L²/i²) is the same formula with C = a: its factor
  σ_c/σ equals W_cr/P.  Whipping, the bending of the rod by its own transverse inertia,
  peaks at M = m·ω²·r·l/(9√3) with m the rod's **total** mass (a published example
  prints 51.3 N·m where this formula gives 134.8 N·m with its data); its stress
  M/Z_xx is added to the direct compression P/A.
* **Small end.**  The bush is pressed in; the interference at running temperature is
  Δ + d·(α_bush − α_rod)·Δt, and the fit pressure is Lamé's for two thick cylinders,
  p = (δ/d)/[((D² + d²)/(D² − d²) + ν_rod)/E_rod + ((d² + d_i²)/(d² − d_i²) − ν_bush)/E_bush]
  (D the eye's outer diameter, d the bush's outer, d_i its bore = the pin).  The eye's
  hoop stress is p·(D² + d²)/(D² − d²) at its bore and 2p·d²/(D² − d²) outside.  Under
  the piston group's inertia tension P_j the eye's two side sections, (D − d)·b in all,
  carry σ_j = P_j/((D − d)·b) (a straight-bar estimate; the curved-beam moment of the
  Chinese texts is not included); with the outer fit stress as a standing mean, the
  fatigue factor is n = σ₋₁/(k_σ·σ_a/(ε·β) + ψ·σ_m), σ_a = σ_j/2, σ_m = σ_fit + σ_j/2.
* **Big end.**  Bearing pressure P/(d·l) on the crankpin; the cap a beam between the
  bolt centres, M = F·l_c/6 (Khurmi & Gupta), stress 6M/(b·t_c²) with b the crankpin's
  length, l_c = d_pin + 2·liner + d_bolt + clearance or typed.
* **Bolts** (Shigley ch. 8, per bolt, P = cap load / bolt count): joint constant
  C = k_b/(k_b + k_m) with k_b = A_t·E/l (the grip threaded, as a short cap screw) and
  k_m two frusta of 30° (eq. 8-20) with washer face 1.5d; preload F_i = f·A_t·S_p;
  yield factor n_p = S_p·A_t/(C·P + F_i), load factor n_L = (S_p·A_t − F_i)/(C·P),
  separation factor n_0 = F_i/(P·(1 − C)), fatigue by Goodman
  n_f = S_e·(S_ut − σ_i)/(σ_a·(S_ut + S_e)) and by Gerber, σ_a = C·P/(2A_t),
  σ_i = F_i/A_t.  Beside them Khurmi & Gupta's static method: the cap load on the bolts'
  core areas, against S_ut with their factor of safety 6.

Units SI at the interface (m, N, Pa, kg, rad/s).

References
----------
R. S. Khurmi, J. K. Gupta, *A Textbook of Machine Design*, ch. 32 (§32.14 forces on the
rod, whipping; §32.15 design of the rod: the I-section B = 4t, H = 5t, Rankine with
σ_c = 320 MPa and a = 1/7500 for mild steel, factor of safety 5 to 6, bolts with factor
6, the cap as a beam M = F·x/6; Example 32.3).
R. G. Budynas, J. K. Nisbett, *Shigley's Mechanical Engineering Design*, 9th ed.,
ch. 8: eq. (8-20) frustum stiffness, (8-31) preload, §8-9 the load factor, yield and
separation factors, §8-11 fatigue (Goodman eq. 8-45, Gerber eq. 8-46), Tables 8-11
(metric property classes), 8-16 (fatigue stress-concentration of threads) and 8-17
(endurance strengths of rolled threads); Example 8-5.
ISO 898-1 (the tensile stress area A_s = π/4·((d_2 + d_3)/2)²; proof and tensile
strengths of the property classes); ISO 261/724 (metric pitches).
W. C. Young, R. G. Budynas, *Roark's Formulas for Stress and Strain*, press fits of
thick cylinders (Lamé).
"""
from typing import NamedTuple

import numpy as np

OVERSPEED_FACTOR = 1.2          # the over-speed when none is typed: 1.2 × the design speed
BOLT_CLEARANCE = 3e-3           # m: Khurmi & Gupta's clearance beside the bolt in the span

# metric threads: (name, nominal diameter mm, pitch mm) — the sizes rod bolts are made
# in, ISO 261 coarse and fine
BOLT_SIZES = (("M6", 6, 1.0), ("M8", 8, 1.25), ("M8x1", 8, 1.0), ("M9x1", 9, 1.0),
              ("M10", 10, 1.5), ("M10x1", 10, 1.0), ("M10x1.25", 10, 1.25), ("M11x1", 11, 1.0),
              ("M12", 12, 1.75), ("M12x1.25", 12, 1.25), ("M14x1.5", 14, 1.5),
              ("M16x1.5", 16, 1.5), ("M18x1.5", 18, 1.5))
# property classes (ISO 898-1; Shigley Table 8-11): proof S_p and tensile S_ut in MPa
# (8.8 below and above M16), and the endurance strength of rolled threads S_e
# (Shigley Table 8-17), in MPa.  The class is typed as the number it is named by (a
# choice word "10.9" is read as a number by Gnumeric, and fails a word's match)
PROPERTY_CLASSES = ((8.8, (580, 800), (600, 830), 129), (9.8, (650, 900), (650, 900), 140),
                    (10.9, (830, 1040), (830, 1040), 162),
                    (12.9, (970, 1220), (970, 1220), 190))
# cut threads notch more than rolled ones (Shigley Table 8-16, classes 6.6–10.9: K_f 3.0
# rolled, 3.8 cut): S_e of a cut thread is the rolled one's × 3.0/3.8
CUT_THREAD_FACTOR = 3.0 / 3.8

# the checks, in the order the sheet lists them, and the fixed targets of those without
# an input for theirs (an allowable stress or pressure is met at a factor of 1)
CHECKS = ("buckling_in_plane", "buckling_out_of_plane", "shank_combined",
          "small_end_fit", "small_end_fatigue", "pin_bearing", "big_end_bearing",
          "cap_bending", "bolt_yield", "bolt_load", "bolt_separation", "bolt_fatigue")
BOLT_YIELD_TARGET = 1.0         # Shigley: n_p > 1, the bolt not loaded past its proof
BOLT_LOAD_TARGET = 2.0          # Shigley Example 8-4's load factor of 2
BOLT_SEPARATION_TARGET = 1.0    # n_0 > 1: the joint stays closed at the over-speed


# ---------------------------------------------------------------- loads
def overspeed_used(overspeed, speed):
    """The over-speed the cap and bolts are checked at: typed, or (0) 1.2 × the design
    speed [rad/s]."""
    return overspeed if overspeed > 0 else OVERSPEED_FACTOR * speed


def rod_force_at_overspeed(gas_force, inertia_force, rod_angle, rod_overspeed, speed):
    """The rod force with the inertia at the over-speed, (F_g + F_j·(n_o/n)²)/cos β [N],
    compression positive."""
    scale = (rod_overspeed / speed) ** 2
    return (np.asarray(gas_force, dtype=float) + np.asarray(inertia_force, dtype=float)
            * scale) / np.cos(rod_angle)


def largest(values):
    """The largest value over the cycle, never below 0 [unit of values]."""
    return max(0.0, float(np.nanmax(np.asarray(values, dtype=float))))


def largest_tension(values):
    """The largest tension, −min of a compression-positive force, never below 0 [N]."""
    return max(0.0, -float(np.nanmin(np.asarray(values, dtype=float))))


def cap_load(rod_tension_max, rod_mass, small_end_mass, rod_cap_mass, crank_radius,
             rod_overspeed):
    """The load on the cap and bolts at the over-speed: the rod's tension plus the
    rotating part of the rod above the cap, (m_rod − m_1 − m_cap)·r·ω_o² [N]."""
    above = max(0.0, rod_mass - small_end_mass - rod_cap_mass)
    return rod_tension_max + above * crank_radius * rod_overspeed ** 2


def small_end_tension(inertia_force, piston_mass, reciprocating_mass):
    """The piston group's largest inertia pull on the small-end eye at the design speed,
    m_p/m_j of the largest reciprocating inertia tension [N]."""
    return largest_tension(inertia_force) * piston_mass / reciprocating_mass


def whipping_moment(rod_mass, angular_velocity, crank_radius, rod_length):
    """The largest bending moment of the rod's transverse inertia,
    M = m·ω²·r·l/(9√3) with m the rod's total mass (Khurmi & Gupta §32.14) [N·m]."""
    return rod_mass * angular_velocity ** 2 * crank_radius * rod_length / (9 * np.sqrt(3))


# ---------------------------------------------------------------- the shank's section
class Section(NamedTuple):
    B: float      # flange width [m]
    H: float      # height in the plane of motion [m]
    t_f: float    # flange thickness [m]
    t_w: float    # web thickness [m]


def section(rod_section_standard, rod_flange_thickness, rod_flange_width,
            rod_section_height, rod_web_thickness):
    """The I-section used: the standard proportions from one thickness t (B = 4t,
    H = 5t, t_f = t_w = t) or the typed dimensions [m]."""
    t = rod_flange_thickness
    if rod_section_standard == 1:
        return Section(4 * t, 5 * t, t, t)
    return Section(rod_flange_width, rod_section_height, t, rod_web_thickness)


def section_area(B, H, t_f, t_w):
    """A = 2·B·t_f + (H − 2t_f)·t_w [m²]."""
    return 2 * B * t_f + (H - 2 * t_f) * t_w


def second_moment_in_plane(B, H, t_f, t_w):
    """I_xx = [B·H³ − (B − t_w)·(H − 2t_f)³]/12: bending in the plane of motion [m⁴]."""
    return (B * H ** 3 - (B - t_w) * (H - 2 * t_f) ** 3) / 12


def second_moment_out_of_plane(B, H, t_f, t_w):
    """I_yy = [2·t_f·B³ + (H − 2t_f)·t_w³]/12: bending out of the plane of motion [m⁴]."""
    return (2 * t_f * B ** 3 + (H - 2 * t_f) * t_w ** 3) / 12


def radius_of_gyration(second_moment, area):
    """k = √(I/A) [m]."""
    return np.sqrt(second_moment / area)


def half_length(rod_length):
    """The buckling length out of the plane of motion, both ends fixed: l/2 [m]."""
    return rod_length / 2


def rankine_load(crushing_stress, area, length, radius_of_gyration, rankine_denominator):
    """The Rankine–Gordon crippling load W_cr = σ_c·A/(1 + a·(L/k)²), a = 1/rankine_denominator
    [N]."""
    return crushing_stress * area / (1 + (length / radius_of_gyration) ** 2
                                     / rankine_denominator)


def amplified_stress(load, area, length, radius_of_gyration, rankine_denominator):
    """The Chinese texts' σ = P/A·(1 + C·L²/i²) with C = a [Pa]."""
    return load / area * (1 + (length / radius_of_gyration) ** 2 / rankine_denominator)


def factor(capacity, demand):
    """capacity/demand; NaN where the demand is not positive [-]."""
    return float(capacity / demand) if demand > 0 else np.nan


def direct_stress(load, area):
    """P/A [Pa]."""
    return load / area


def combined_stress(rod_direct_stress, rod_whipping_stress):
    """Direct compression plus whipping (Khurmi & Gupta §32.15) [Pa]."""
    return rod_direct_stress + rod_whipping_stress


def whipping_stress(rod_whipping_moment, H, second_moment):
    """σ_w = M/Z_xx, Z_xx = I_xx/(H/2) [Pa]."""
    return rod_whipping_moment * H / 2 / second_moment


# ---------------------------------------------------------------- the small end
def bearing_pressure(load, diameter, length):
    """The projected-area bearing pressure P/(d·l) [Pa]."""
    return load / (diameter * length)


def running_interference(bush_interference, bush_outer_diameter, bush_expansion,
                         rod_expansion, small_end_temperature_rise):
    """The diametral interference at running temperature, Δ + d·(α_bush − α_rod)·Δt [m]."""
    return bush_interference + bush_outer_diameter * (
        bush_expansion - rod_expansion) * small_end_temperature_rise


def fit_pressure(interference, small_end_outer_diameter, bush_outer_diameter,
                 piston_pin_diameter, rod_elastic_modulus, rod_poisson_ratio,
                 bush_elastic_modulus, bush_poisson_ratio):
    """Lamé's pressure between the eye (D, d) and the bush (d, d_i): the interference δ
    over d, divided by the two members' compliances; 0 when the fit is loose [Pa]."""
    D, d, di = small_end_outer_diameter, bush_outer_diameter, piston_pin_diameter
    eye = ((D ** 2 + d ** 2) / (D ** 2 - d ** 2) + rod_poisson_ratio) / rod_elastic_modulus
    bush = ((d ** 2 + di ** 2) / (d ** 2 - di ** 2) - bush_poisson_ratio) / bush_elastic_modulus
    return max(0.0, interference / d / (eye + bush))


def loose(small_end_interference):
    """1 where the bush has no interference left at running temperature."""
    return float(small_end_interference <= 0)


def eye_stress_inner(pressure, small_end_outer_diameter, bush_outer_diameter):
    """The eye's hoop stress at its bore, p·(D² + d²)/(D² − d²) [Pa]."""
    D, d = small_end_outer_diameter, bush_outer_diameter
    return pressure * (D ** 2 + d ** 2) / (D ** 2 - d ** 2)


def eye_stress_outer(pressure, small_end_outer_diameter, bush_outer_diameter):
    """The eye's hoop stress outside, 2p·d²/(D² − d²) [Pa]."""
    D, d = small_end_outer_diameter, bush_outer_diameter
    return pressure * 2 * d ** 2 / (D ** 2 - d ** 2)


def eye_tension_stress(small_end_tension, small_end_outer_diameter, bush_outer_diameter,
                       small_end_width):
    """The inertia pull on the eye's two side sections, P_j/((D − d)·b) [Pa]."""
    return small_end_tension / ((small_end_outer_diameter - bush_outer_diameter)
                                * small_end_width)


def small_end_fatigue_factor(rod_fatigue_limit, small_end_stress_concentration,
                             small_end_surface_factor, small_end_size_factor,
                             small_end_mean_sensitivity, small_end_stress_outer,
                             small_end_tension_stress):
    """n = σ₋₁/(k_σ·σ_a/(ε·β) + ψ·σ_m) with σ_a = σ_j/2 and σ_m = σ_fit + σ_j/2: the
    project's fatigue form (seed 002 eq. 3.3) [-]."""
    amplitude = small_end_tension_stress / 2
    mean = small_end_stress_outer + amplitude
    demand = small_end_stress_concentration * amplitude / (
        small_end_surface_factor * small_end_size_factor) + small_end_mean_sensitivity * mean
    return factor(rod_fatigue_limit, demand)


# ---------------------------------------------------------------- the big end and its cap
def bolt_span(bolt_span_typed, crankpin_diameter, bearing_liner_thickness, bolt_diameter):
    """The cap's span between the bolt centres: typed, or (0) d_pin + 2·liner + d_bolt +
    3 mm clearance (Khurmi & Gupta) [m]."""
    if bolt_span_typed > 0:
        return bolt_span_typed
    return crankpin_diameter + 2 * bearing_liner_thickness + bolt_diameter + BOLT_CLEARANCE


def cap_bending_stress(rod_cap_load, rod_bolt_span, crankpin_length, cap_thickness):
    """σ = M/Z with M = F·l_c/6 and Z = b·t_c²/6: σ = F·l_c/(b·t_c²) [Pa]."""
    return rod_cap_load * rod_bolt_span / (crankpin_length * cap_thickness ** 2)


# ---------------------------------------------------------------- the bolts
def _size(bolt_size):
    return BOLT_SIZES[int(round(bolt_size)) - 1]


def bolt_diameter(bolt_size):
    """The nominal diameter of the chosen thread [m]."""
    return _size(bolt_size)[1] * 1e-3


def bolt_pitch(bolt_size):
    """The pitch of the chosen thread [m]."""
    return _size(bolt_size)[2] * 1e-3


def tensile_stress_area(diameter, pitch):
    """ISO 898-1's A_s = π/4·((d_2 + d_3)/2)² = π/4·(d − 0.938194·P)² [m²]."""
    return np.pi / 4 * (diameter - 0.938194 * pitch) ** 2


def core_area(diameter, pitch):
    """The thread's core area π/4·d_3², d_3 = d − 1.226869·P [m²]."""
    return np.pi / 4 * (diameter - 1.226869 * pitch) ** 2


def _class(bolt_property_class):
    """The table's row of a property class (one of 8.8, 9.8, 10.9, 12.9: a rule says
    so; the nearest, so a value moved by rounding still finds its row)."""
    return min(PROPERTY_CLASSES, key=lambda row: abs(row[0] - bolt_property_class))


def proof_strength(bolt_property_class, bolt_diameter):
    """S_p of the property class (8.8: 580 MPa to M16, 600 above) [Pa]."""
    cls = _class(bolt_property_class)
    return 1e6 * (cls[1] if bolt_diameter <= 16e-3 else cls[2])[0]


def tensile_strength(bolt_property_class, bolt_diameter):
    """S_ut of the property class [Pa]."""
    cls = _class(bolt_property_class)
    return 1e6 * (cls[1] if bolt_diameter <= 16e-3 else cls[2])[1]


def endurance_strength(bolt_property_class, bolt_thread_rolled):
    """S_e of the class's rolled thread (Shigley Table 8-17), × 3.0/3.8 for a cut thread
    [Pa]."""
    rolled = 1e6 * _class(bolt_property_class)[3]
    return rolled if bolt_thread_rolled == 1 else rolled * CUT_THREAD_FACTOR


def grip(bolt_grip_typed, cap_thickness):
    """The grip: typed, or (0) twice the cap's thickness [m]."""
    return bolt_grip_typed if bolt_grip_typed > 0 else 2 * cap_thickness


def bolt_stiffness(area, elastic_modulus, length):
    """k_b = A·E/l: the grip threaded throughout [N/m]."""
    return area * elastic_modulus / length


def frustum_stiffness(elastic_modulus, diameter, thickness, face_diameter):
    """One 30° pressure-cone frustum (Shigley eq. 8-20):
    k = 0.5774·π·E·d / ln[(1.155t + D − d)(D + d)/((1.155t + D + d)(D − d))] [N/m]."""
    d, t, D = diameter, thickness, face_diameter
    return 0.5774 * np.pi * elastic_modulus * d / np.log(
        (1.155 * t + D - d) * (D + d) / ((1.155 * t + D + d) * (D - d)))


def series_stiffness(*stiffnesses):
    """Springs in series, 1/k = Σ 1/k_i [N/m]."""
    return 1 / sum(1 / k for k in stiffnesses)


def member_stiffness(elastic_modulus, bolt_diameter, bolt_grip):
    """Two equal frusta of half the grip each, washer face 1.5d, in series [N/m]."""
    half = frustum_stiffness(elastic_modulus, bolt_diameter, bolt_grip / 2, 1.5 * bolt_diameter)
    return series_stiffness(half, half)


def joint_constant(bolt_joint_constant_typed, bolt_stiffness, member_stiffness):
    """C = k_b/(k_b + k_m), or the typed C (0 = from the stiffnesses) [-]."""
    if bolt_joint_constant_typed > 0:
        return bolt_joint_constant_typed
    return bolt_stiffness / (bolt_stiffness + member_stiffness)


def preload(bolt_preload_fraction, tensile_stress_area, proof_strength):
    """F_i = f·A_t·S_p (Shigley eq. 8-31: 0.75 reused, 0.90 permanent) [N]."""
    return bolt_preload_fraction * tensile_stress_area * proof_strength


def bolt_load(rod_cap_load, rod_bolt_count):
    """The external load per bolt, P = F_cap/N [N]."""
    return rod_cap_load / rod_bolt_count


def yield_factor(proof_strength, tensile_stress_area, joint_constant, bolt_load, preload):
    """n_p = S_p·A_t/(C·P + F_i) [-]."""
    return proof_strength * tensile_stress_area / (joint_constant * bolt_load + preload)


def load_factor(proof_strength, tensile_stress_area, joint_constant, bolt_load, preload):
    """n_L = (S_p·A_t − F_i)/(C·P) [-]."""
    return factor(proof_strength * tensile_stress_area - preload, joint_constant * bolt_load)


def separation_factor(preload, bolt_load, joint_constant):
    """n_0 = F_i/(P·(1 − C)) [-]."""
    return factor(preload, bolt_load * (1 - joint_constant))


def alternating_bolt_stress(joint_constant, bolt_load, tensile_stress_area):
    """σ_a = C·P/(2A_t): the bolt's share swings between 0 and C·P [Pa]."""
    return joint_constant * bolt_load / (2 * tensile_stress_area)


def goodman_factor(endurance_strength, tensile_strength, preload_stress, stress_amplitude):
    """n_f = S_e·(S_ut − σ_i)/(σ_a·(S_ut + S_e)) (Shigley eq. 8-45) [-]."""
    return factor(endurance_strength * (tensile_strength - preload_stress),
                  stress_amplitude * (tensile_strength + endurance_strength))


def gerber_factor(endurance_strength, tensile_strength, preload_stress, stress_amplitude):
    """n_f = [S_ut·√(S_ut² + 4S_e(S_e + σ_i)) − S_ut² − 2σ_i·S_e]/(2σ_a·S_e)
    (Shigley eq. 8-46) [-]."""
    se, sut, si = endurance_strength, tensile_strength, preload_stress
    return factor(sut * np.sqrt(sut ** 2 + 4 * se * (se + si)) - sut ** 2 - 2 * si * se,
                  2 * stress_amplitude * se)


def core_stress(rod_cap_load, rod_bolt_count, core_area):
    """Khurmi & Gupta: the cap load over the bolts' core areas, F/(N·π/4·d_c²) [Pa]."""
    return rod_cap_load / (rod_bolt_count * core_area)


# ---------------------------------------------------------------- the verdict
def check_count(throw):
    """The twelve checks (an axis's size)."""
    return len(CHECKS)


def check_numbers(throw):
    """1 … 12, the checks in the sheet's order."""
    return np.arange(1.0, len(CHECKS) + 1)


def check_factors(rod_buckling_factor_in_plane, rod_buckling_factor_out_of_plane,
                  rod_combined_factor, small_end_fit_factor, small_end_fatigue_factor,
                  pin_bearing_factor, big_end_bearing_factor, cap_bending_factor,
                  bolt_yield_factor, bolt_load_factor, bolt_separation_factor,
                  bolt_fatigue_factor):
    """Each check's safety factor, in CHECKS's order [-]."""
    return np.array([rod_buckling_factor_in_plane, rod_buckling_factor_out_of_plane,
                     rod_combined_factor, small_end_fit_factor, small_end_fatigue_factor,
                     pin_bearing_factor, big_end_bearing_factor, cap_bending_factor,
                     bolt_yield_factor, bolt_load_factor, bolt_separation_factor,
                     bolt_fatigue_factor], dtype=float)


def check_targets(rod_buckling_target, rod_static_target, rod_fatigue_target):
    """Each check's target factor, in CHECKS's order [-]."""
    return np.array([rod_buckling_target, rod_buckling_target, rod_static_target, 1.0,
                     rod_fatigue_target, 1.0, 1.0, 1.0, BOLT_YIELD_TARGET, BOLT_LOAD_TARGET,
                     BOLT_SEPARATION_TARGET, rod_fatigue_target], dtype=float)


def margins(rod_check_factor, rod_check_target):
    """factor/target: below 1 the check fails; the smallest governs [-]."""
    return np.asarray(rod_check_factor, dtype=float) / np.asarray(rod_check_target, dtype=float)


def passes(rod_check_margin):
    """1 where the check holds (margin ≥ 1), 0 where it fails or cannot be made."""
    m = np.asarray(rod_check_margin, dtype=float)
    return np.where(np.isfinite(m) & (m >= 1), 1.0, 0.0)


def governing(rod_check_margin):
    """The number of the check with the smallest margin (the first of equals); NaN
    when no check could be made [-]."""
    m = np.asarray(rod_check_margin, dtype=float)
    return float(np.nanargmin(m) + 1) if np.isfinite(m).any() else np.nan


def governs(rod_governing_check):
    """1 at the governing check, 0 at the others."""
    return np.where(np.arange(1, len(CHECKS) + 1) == rod_governing_check, 1.0, 0.0)


def verdict(rod_check_pass):
    """1 when every check holds, else 0."""
    return float(np.all(np.asarray(rod_check_pass) == 1))
