"""Input rules as functions: 1 where the inputs break the rule, else 0.

Each is the calc half of a ``[[rule]]`` of a template, whose formula is the same
condition in Excel (the workbook's input checks); a value that cannot be computed
(NaN) counts as broken there and here.
"""
import numpy as np


def _flag(condition):
    return np.where(np.asarray(condition, dtype=bool), 1.0, 0.0)


def rod_too_short(rod_length, crank_radius, offset):
    """1 where l ≤ r + |e|: the rod cannot reach the pin axis at every crank angle."""
    return _flag(np.asarray(rod_length) <= np.asarray(crank_radius) + np.abs(offset))


def series_needs_centric(exact_kinematics, offset):
    """1 where the thesis's series formulas are chosen for an offset mechanism."""
    return _flag((np.asarray(exact_kinematics) == 0) & (np.asarray(offset) != 0))


def rod_cg_off_rod(rod_cg_from_big_end, rod_length):
    """1 where the rod's centre of gravity lies beyond its small end."""
    return _flag(np.asarray(rod_cg_from_big_end) > rod_length)


def trace_missing(pressure_source, trace_crank_angle):
    """1 where the measured trace is chosen but has fewer than two points."""
    points = np.count_nonzero(np.isfinite(np.asarray(trace_crank_angle, dtype=float)))
    return _flag((np.asarray(pressure_source) == 1) & (points < 2))


def no_crank(stroke, offset, extreme_angle):
    """1 where H² − 2eH·tan(θ/2) ≤ 0: no crank gives this stroke, offset and K."""
    return _flag(stroke ** 2 - 2 * offset * stroke * np.tan(extreme_angle / 2) <= 0)


def not_positive(value):
    """1 where a quantity that must be positive is not."""
    return _flag(~(np.asarray(value, dtype=float) > 0))


def dimension_beyond_bore(bore, main_journal_diameter, main_journal_length, crankpin_diameter,
                          crankpin_length, web_thickness, web_width, fillet_radius):
    """1 where a crankshaft dimension exceeds three bores."""
    largest = np.max([main_journal_diameter, main_journal_length, crankpin_diameter,
                      crankpin_length, web_thickness, web_width, fillet_radius])
    return _flag(largest > 3 * bore)


def bore_not_inside(bore, diameter):
    """1 where a hollow journal's or pin's bore is not smaller than its diameter."""
    return _flag(bore >= diameter)


def throw_missing(check_throw, throw):
    """1 where no cylinder is on the throw to check."""
    return _flag(not np.any(np.asarray(throw, dtype=float) == check_throw))


def throw_without_cylinder(throw):
    """1 where the throws are not numbered 1…n without a gap (a throw with no cylinder)."""
    numbers = np.asarray(throw, dtype=float)
    return _flag(np.max(numbers) != np.unique(numbers).size)


def band_reversed(fatigue_band_min, fatigue_band_max):
    """1 where a band's lower end exceeds its upper end."""
    return _flag(fatigue_band_min > fatigue_band_max)


def base_not_outside_offset(base_radius, offset):
    """1 where a cam's base radius does not exceed |e| (no s0 = √(r0² − e²))."""
    return _flag(base_radius <= np.abs(offset))


def angles_beyond_a_turn(rise_angle, far_dwell, return_angle):
    """1 where rise, far dwell and return take more than a turn."""
    return _flag(rise_angle + far_dwell + return_angle > 2 * np.pi * (1 + 1e-12))


def zero_rotation(rotation):
    """1 where a sense of rotation is 0 (it must be 1 or −1)."""
    return _flag(np.asarray(rotation) == 0)


# ------------------------------------------------------------ plausibility
# Legal values an engineer rarely means: 1 flags a likely slip, the build goes on.

STEEL_DENSITY = 7850.0          # kg/m³
MEAN_PISTON_SPEED_LIMIT = 30.0  # m/s: above any production engine's (racing engines ~25)
FIRING_GRID = 15.0              # °: regular firing intervals are whole multiples of it
FIRING_SLIP = 2.0               # °: a firing angle this close to, not on, the grid is a slip


def heavier_than_solid_steel(mass, bore):
    """1 where ``mass`` [kg] exceeds a solid steel cylinder as wide and as long as the
    bore [m] (7850·π/4·D³): no piston or rod is, so grams were typed for kg."""
    return _flag(np.asarray(mass) > STEEL_DENSITY * np.pi / 4 * np.asarray(bore) ** 3)


def piston_speed_implausible(mean_piston_speed):
    """1 where the mean piston speed [m/s] exceeds 30 m/s (Heywood, ch. 2: 8–15 m/s for
    most engines, about 25 m/s for racing engines): a stroke or speed slip."""
    return _flag(np.asarray(mean_piston_speed) > MEAN_PISTON_SPEED_LIMIT)


def firing_angle_slip(firing_angle):
    """1 where a firing angle [rad] lies within 2° of a multiple of 15° without being on
    it (179° for 180°): every regular interval (720/n, a V's bank angle) is a multiple
    of 15°, so a degree off is a typing slip."""
    degrees = np.degrees(np.asarray(firing_angle, dtype=float))
    off = np.abs((degrees + FIRING_GRID / 2) % FIRING_GRID - FIRING_GRID / 2)
    return _flag(np.any((off > 1e-6) & (off <= FIRING_SLIP)))


MIN_INTAKE_PRESSURE = 0.5e6     # Pa: a four-stroke trace whose lowest point is above it is in bar


def trace_looks_like_bar(pressure_source, trace_pressure):
    """1 where the measured trace is chosen and its lowest pressure [Pa] is above
    0.5 MPa: an engine breathes near 0.1 MPa (boosted, up to about 0.4 MPa), so the
    numbers are bar typed as MPa."""
    pressures = np.asarray(trace_pressure, dtype=float)
    pressures = pressures[np.isfinite(pressures)]
    low = pressures.min() if pressures.size else 0.0
    return _flag((np.asarray(pressure_source) == 1) & (low > MIN_INTAKE_PRESSURE))


MAX_GAS_EXCHANGE_PRESSURE = 0.6e6   # Pa: 6 bar, above any intake, exhaust or crankcase


def gas_pressure_looks_like_bar(intake_pressure, exhaust_pressure, ambient_pressure):
    """1 where the intake, exhaust or crankcase pressure is above 0.6 MPa, beyond the
    boost and back pressure of any engine here: bar (0.95 at the intake, 1.1 at the
    exhaust, 1 in the crankcase) typed as MPa."""
    return _flag(max(intake_pressure, exhaust_pressure, ambient_pressure)
                 > MAX_GAS_EXCHANGE_PRESSURE)


def stroke_bore_implausible(stroke, bore):
    """1 where the stroke is below 0.3 or above 5 times the bore: engines run from
    about 0.5 (racing) to 4.2 (long-stroke two-stroke crossheads), so a crank radius
    or rod length in m typed into an mm cell."""
    return _flag((stroke < 0.3 * bore) | (stroke > 5 * bore))


MAX_PEAK_PRESSURE = 40e6        # Pa: above any engine's (heavy diesels reach about 25 MPa)


def peak_pressure_implausible(cylinder_pressure_max):
    """1 where the peak cylinder pressure is above 40 MPa: a length, the compression
    ratio or the heat typed wrong."""
    return _flag(cylinder_pressure_max > MAX_PEAK_PRESSURE)


def flywheel_implausible(station_inertia, bore):
    """1 where the flywheel station's inertia [kg·m²] (the last station) is below the
    crank throws' together — no flywheel is lighter than the crank it steadies — or
    above a solid steel disc four bores across and a bore thick
    (7850·π/4·(4D)²·D·(4D)²/8 = 7850·8π·D⁵): a flywheel sized at a low p_speed (it
    grows as 1/n²), or a slip in the typed value.  A truck diesel's flywheel station
    reaches 1.6 times the half as thick disc (Mendes et al. 2008: 2.075 kg·m² on a
    105 mm bore, tests/data/mendes_2008.toml), so a real engine passes."""
    inertia = np.asarray(station_inertia, dtype=float)
    flywheel, throws = inertia[-1], inertia[1:-1].sum()
    return _flag((flywheel < throws) | (flywheel > STEEL_DENSITY * 8 * np.pi * bore ** 5))


def sweep_reversed(sweep_speed_min, sweep_speed_max):
    """1 where both sweep bounds are typed and the lowest is not below the highest."""
    return _flag((np.asarray(sweep_speed_min) > 0) & (np.asarray(sweep_speed_max) > 0)
                 & (np.asarray(sweep_speed_min) >= sweep_speed_max))


# the least specified tensile strength of shaft forgings: Lloyd's Register, Rules for
# Ships, Pt 5 Ch 6 §2.1.1 (carbon and carbon-manganese steel 400–760 N/mm²), the rules
# that carry M68's permissible stresses
LEAST_SHAFT_STRENGTH = 400e6    # Pa


def shaft_strength_below_rule(shaft_tensile_strength):
    """1 where M68's σ_B is typed (not 0 = the crankshaft's) below 400 MPa, the least
    shaft steel the class rules take: a value in GPa typed into the MPa cell, most
    likely."""
    sigma = np.asarray(shaft_tensile_strength, dtype=float)
    return _flag((sigma > 0) & (sigma < LEAST_SHAFT_STRENGTH))


def damper_inertia_implausible(damper_kind, damper_inertia, station_inertia):
    """1 where a damper is fitted whose ring has more inertia [kg·m²] than the flywheel
    (the last station): a ring is a small fraction of it, so kg·cm² typed for kg·m²."""
    flywheel = np.asarray(station_inertia, dtype=float)[-1]
    return _flag((np.asarray(damper_kind) > 0) & (np.asarray(damper_inertia) > flywheel))


def damper_without_inertia(damper_kind, damper_inertia):
    """1 where a damper is chosen whose ring has no inertia."""
    return _flag((np.asarray(damper_kind) > 0) & (np.asarray(damper_inertia) == 0))


def tuned_without_stiffness(damper_kind, damper_stiffness):
    """1 where a tuned damper has no rubber stiffness to be tuned by."""
    return _flag((np.asarray(damper_kind) == 2) & (np.asarray(damper_stiffness) == 0))


def oil_bore_too_wide(oil_bore_diameter, crankpin_diameter):
    """1 where the crankpin's oil bore is not narrower than the pin."""
    return _flag(np.asarray(oil_bore_diameter) >= np.asarray(crankpin_diameter))


def pin_outside_span(m53_l2_typed, m53_l3_typed):
    """1 where typed M53 lengths put the crankpin outside the main journals (L2 ≥ L3)."""
    l2, l3 = np.asarray(m53_l2_typed), np.asarray(m53_l3_typed)
    return _flag((l2 > 0) & (l3 > 0) & (l2 >= l3))


def web_wider_than_flange(rod_section_standard, rod_web_thickness, rod_flange_width):
    """1 where a typed I-section's web is not thinner than its flange is wide."""
    return _flag((np.asarray(rod_section_standard) == 0)
                 & (np.asarray(rod_web_thickness) >= rod_flange_width))


def flanges_fill_section(rod_section_standard, rod_flange_thickness, rod_section_height):
    """1 where a typed I-section's two flanges are as thick as the section is high."""
    return _flag((np.asarray(rod_section_standard) == 0)
                 & (2 * np.asarray(rod_flange_thickness) >= rod_section_height))


def overspeed_below_speed(overspeed, speed):
    """1 where a typed over-speed is below the design speed."""
    return _flag((np.asarray(overspeed) > 0) & (np.asarray(overspeed) < speed))


def bolt_class_not_in_table(bolt_property_class):
    """1 where the bolt's property class is none of 8.8, 9.8, 10.9 and 12.9."""
    # to one decimal, as the formula's ROUND: a typed 8.8 may come back 8.800000000000001
    return _flag(~np.isin(np.round(np.asarray(bolt_property_class, dtype=float), 1),
                          (8.8, 9.8, 10.9, 12.9)))


def bearing_beyond_journals(check_bearing, throw):
    """1 where the main bearing asked for is beyond the last main journal (throws + 1)."""
    return _flag(np.asarray(check_bearing) > np.max(throw) + 1)


def groove_too_wide(oil_groove_width, crankpin_length, main_journal_length):
    """1 where the oil groove is as wide as a bearing is long: no film is left."""
    return _flag((oil_groove_width >= crankpin_length) | (oil_groove_width >= main_journal_length))


def clearance_too_large(bearing_clearance, crankpin_diameter, main_journal_diameter):
    """1 where the radial clearance exceeds 1 % of a journal's diameter, ten times the
    usual 0.05–0.1 %: no film forms in such a gap."""
    return _flag(bearing_clearance * 100 > np.minimum(crankpin_diameter, main_journal_diameter))


def clearance_implausible(bearing_clearance, crankpin_diameter, main_journal_diameter):
    """1 where the radial clearance is below 0.02 % of a journal's diameter, a fifth
    of the usual least: a clearance in mm typed into the µm cell."""
    return _flag(bearing_clearance < 0.0002 * np.minimum(crankpin_diameter, main_journal_diameter))


# a material constant a power of a thousand too small: GPa typed into an MPa cell, or a
# coefficient per kelvin into a µm/(m·K) one.  No structural metal has a modulus below
# 1 GPa (steel 210, bronze 115, its shear moduli 40–80), a strength below 20 MPa or an
# expansion below 0.1 µm/(m·K) (invar's is about 1).
LEAST_MODULUS = 1e9             # Pa
LEAST_STRENGTH = 20e6           # Pa
LEAST_EXPANSION = 0.1e-6        # 1/K


def shear_modulus_in_gpa(shear_modulus):
    """1 where the crankshaft's shear modulus G is below 1 GPa: GPa typed for MPa."""
    return _flag(np.asarray(shear_modulus) < LEAST_MODULUS)


def rod_moduli_in_gpa(rod_elastic_modulus, bush_elastic_modulus):
    """1 where the rod's or its bush's elastic modulus is below 1 GPa: GPa typed for MPa."""
    return _flag(np.minimum(rod_elastic_modulus, bush_elastic_modulus) < LEAST_MODULUS)


def rod_strengths_in_gpa(rod_crushing_stress, rod_fatigue_limit):
    """1 where the rod steel's crushing stress or fatigue limit is below 20 MPa: GPa
    typed for MPa."""
    return _flag(np.minimum(rod_crushing_stress, rod_fatigue_limit) < LEAST_STRENGTH)


def crank_strengths_in_gpa(allowable_stress, fatigue_limit, fatigue_limit_torsion):
    """1 where the crankshaft's allowable stress or a fatigue limit is below 20 MPa:
    GPa typed for MPa."""
    return _flag(min(allowable_stress, fatigue_limit, fatigue_limit_torsion) < LEAST_STRENGTH)


def expansions_per_kelvin(rod_expansion, bush_expansion):
    """1 where the rod's or the bush's expansion coefficient is typed (not 0) below
    0.1 µm/(m·K): a coefficient per kelvin (11e-6) typed for µm/(m·K) (11)."""
    a = np.array([rod_expansion, bush_expansion], dtype=float)
    return _flag(np.any((a > 0) & (a < LEAST_EXPANSION)))


LEAST_FILM_ALLOWABLE = 0.1e-6   # m: a tenth of the usual 1 µm floor


def film_allowable_implausible(min_film_allowable):
    """1 where the allowable minimum film is below 0.1 µm, a tenth of the usual floor
    and thinner than a ground journal's roughness: mm typed into the µm cell."""
    return _flag(np.asarray(min_film_allowable) < LEAST_FILM_ALLOWABLE)


def viscosity_implausible(oil_viscosity):
    """1 where the oil is thinner than 1 mPa·s (water at 20 °C): Pa·s typed for mPa·s."""
    return _flag(np.asarray(oil_viscosity) < 1e-3)
