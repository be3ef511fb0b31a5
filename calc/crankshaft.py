"""The crankshaft: crank-pin and main-bearing loads, the throw as a simply supported
beam (thesis 000 §4.6), the fatigue safety factor (seed 002 §3.3, eq. 3.3) and the
main dimensions by rules of the bore (thesis §4.4.1).

Crank-fixed frame: the tangential component is positive in the sense of rotation,
the radial one positive toward the crank centre (as the single-cylinder radial
force).  Engine frame: y up, x the way the top of the crank moves (issue 11).  SI
units throughout; per-cylinder series are (N + 1, n), per-throw ones (N + 1, T).

References
----------
Thesis 000 §4.4.1 (main dimensions), §4.6 (static strength), seed 002 §3.3 (eq. 3.3).
"""
from typing import NamedTuple

import numpy as np

from crankbook.calc import charge


# ---------------------------------------------------------------- loads
def per_throw(cylinder_values, throw):
    """Σ over the cylinders on each throw t = 1…T of a per-cylinder series (N + 1, T)."""
    values = np.asarray(cylinder_values, dtype=float)
    throw = np.asarray(throw, dtype=float)
    throws = np.arange(1, int(throw.max()) + 1, dtype=float)
    return values @ (throw[:, None] == throws[None, :]).astype(float)


def crankpin_load_radial(cylinder_radial_force, big_end_mass, crank_radius, angular_velocity,
                         throw):
    """Radial load on each crank pin, toward the crank centre: the rods' radial forces
    less the centrifugal force m2·r·ω² of each rod's big end (N + 1, T) [N]."""
    centrifugal = big_end_mass * crank_radius * angular_velocity ** 2
    return per_throw(np.asarray(cylinder_radial_force, dtype=float) - centrifugal, throw)


def magnitude(x, y):
    """√(x² + y²) [unit of x]."""
    return np.hypot(x, y)


def series_max(values):
    """Largest value of each column (or of a series) [same unit]."""
    return np.asarray(values, dtype=float).max(axis=0)


def series_mean(values):
    """Cycle mean of each column without the closing point [same unit]."""
    return np.asarray(values, dtype=float)[:-1].mean(axis=0)


def _throw_loads(cylinder_tangential_force, cylinder_radial_force, cylinder_rotating_force,
                 crank_angle, firing_angle, bank_angle):
    """Each cylinder's part of its throw's load on the main bearings, engine frame:
    its rod force on the pin plus its share of the crank's and counterweight's
    centrifugal forces (N + 1, n) twice [N]."""
    alpha = np.asarray(crank_angle, dtype=float).reshape(-1, 1)
    theta = alpha - np.asarray(firing_angle, dtype=float) + np.asarray(bank_angle, dtype=float)
    tangential = np.asarray(cylinder_tangential_force, dtype=float)
    outward = np.asarray(cylinder_rotating_force, dtype=float) \
        - np.asarray(cylinder_radial_force, dtype=float)
    x = tangential * np.cos(theta) + outward * np.sin(theta)
    y = -tangential * np.sin(theta) + outward * np.cos(theta)
    return x, y


def _journal_share(values, throw):
    """Half of each throw's load on the journal in front of it and half on the one
    behind: journal j carries throws j − 1 and j (N + 1, T + 1)."""
    throw = np.asarray(throw, dtype=float)
    journals = np.arange(1, int(throw.max()) + 2, dtype=float)
    share = 0.5 * ((throw[:, None] == journals[None, :] - 1)
                   | (throw[:, None] == journals[None, :])).astype(float)
    return np.asarray(values, dtype=float) @ share


class JournalLoads(NamedTuple):
    """The load each main journal puts on its bearing: horizontal and vertical
    (N + 1, T + 1) [N]."""
    x: np.ndarray
    y: np.ndarray


def journal_loads(cylinder_tangential_force, cylinder_radial_force, cylinder_rotating_force,
                  crank_angle, firing_angle, bank_angle, throw):
    """Each main journal's bearing load, a :class:`JournalLoads`: half of each throw's
    load on the journal in front of it and half on the one behind."""
    x, y = _throw_loads(cylinder_tangential_force, cylinder_radial_force,
                        cylinder_rotating_force, crank_angle, firing_angle, bank_angle)
    return JournalLoads(_journal_share(x, throw), _journal_share(y, throw))


# ---------------------------------------------------------------- dimensions
def ratio(value, bore):
    """A dimension over the bore [-]."""
    return value / bore


def within(value, low, high):
    """1 where low ≤ value ≤ high, else 0."""
    return np.where((value >= low) & (value <= high), 1.0, 0.0)


def band_verdict(value, low, high):
    """1 where low ≤ value ≤ high; 0 below the band (unsafe); 2 above it (safe, but
    heavier than the band asks: the part could be lighter)."""
    value = np.asarray(value, dtype=float)
    return np.where(value < low, 0.0, np.where(value > high, 2.0, 1.0))


def cylinder_pitch(web_thickness, main_journal_length, crankpin_length):
    """L = 2h + L1 + L2 [m] (thesis §4.4.1)."""
    return 2 * web_thickness + main_journal_length + crankpin_length


def throw_span(main_journal_length, web_thickness, crankpin_length):
    """a = L1/2 + h + L2/2, main-journal centre to crank-pin centre along the shaft [m]."""
    return main_journal_length / 2 + web_thickness + crankpin_length / 2


def journal_overlap(main_journal_diameter, crankpin_diameter, crank_radius):
    """Overlap of the main journal and crank pin, (D1 + D2)/2 − r [m]."""
    return (main_journal_diameter + crankpin_diameter) / 2 - crank_radius


# ---------------------------------------------------------------- static strength
def bending_modulus(diameter, bore):
    """Section modulus in bending of a (hollow) round section, π·D³/32·(1 − (d/D)⁴) [m³]."""
    return np.pi * diameter ** 3 / 32 * (1 - (bore / diameter) ** 4)


def torsion_modulus(diameter, bore):
    """Polar section modulus, π·D³/16·(1 − (d/D)⁴) [m³]."""
    return np.pi * diameter ** 3 / 16 * (1 - (bore / diameter) ** 4)


def pin_bending_stress_component(load, throw_span, bending_modulus):
    """Bending stress at the pin centre of the throw as a simply supported beam with the
    load at mid-span: M = P·a/2, σ = M/W [Pa]."""
    return np.asarray(load, dtype=float) * throw_span / 2 / bending_modulus


def pin_torque(journal_torque, tangential_load, crank_radius):
    """Torque in the crank pin: the front journal's torque plus half the pin's
    tangential load times r [N·m]."""
    return np.asarray(journal_torque, dtype=float) + np.asarray(tangential_load) * crank_radius / 2


def torsional_stress(torque, torsion_modulus):
    """τ = M_t/W_p [Pa]."""
    return np.asarray(torque, dtype=float) / torsion_modulus


def combined_stress(bending_stress, torsional_stress, strength_theory):
    """Equivalent stress: √(σ² + 4τ²) by the third strength theory, √(σ² + 3τ²) by the
    fourth [Pa]."""
    factor = np.where(np.asarray(strength_theory) == 3, 4.0, 3.0)
    return np.sqrt(np.asarray(bending_stress) ** 2 + factor * np.asarray(torsional_stress) ** 2)


def value_at(series, crank_angle, angle):
    """The series at a grid angle (an exact grid value) [unit of series]."""
    grid = np.asarray(crank_angle, dtype=float).ravel()
    return float(np.asarray(series, dtype=float)[int(np.argmin(np.abs(grid - angle)))])


def safety_factor(allowable, stress):
    """[σ]/σ [-]."""
    return allowable / stress


# ---------------------------------------------------------------- fatigue (seed 002)
def amplitude(values):
    """Stress amplitude, half the range over the cycle [unit of values]."""
    values = np.asarray(values, dtype=float)
    return (values.max() - values.min()) / 2


def mean_of_range(values):
    """Mean stress, the middle of the range over the cycle [unit of values]."""
    values = np.asarray(values, dtype=float)
    return (values.max() + values.min()) / 2


def choose(source, from_series, typed):
    """The series value where ``source`` is 0, the typed one where 1."""
    return np.where(np.asarray(source) == 1, typed, from_series)


def fatigue_safety_factor(fatigue_limit, stress_concentration, strengthening_factor,
                          size_factor, mean_stress_sensitivity, stress_amplitude, mean_stress):
    """n = σ₋₁/(kσ·σa/(β·εσ) + ψσ·σm) (seed 002 eq. 3.3; NaN where the stress is zero)
    [-]."""
    demand = stress_concentration * stress_amplitude / (strengthening_factor * size_factor) \
        + mean_stress_sensitivity * mean_stress
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(demand > 0, fatigue_limit / np.where(demand > 0, demand, 1.0), np.nan)


def combined_safety_factor(bending_factor, torsion_factor):
    """n = n_σ·n_τ/√(n_σ² + n_τ²), i.e. 1/n² = 1/n_σ² + 1/n_τ²; a missing (zero-stress)
    part counts as no demand [-]."""
    inverse = np.nan_to_num(1 / np.asarray(bending_factor, dtype=float), nan=0.0) ** 2 + \
        np.nan_to_num(1 / np.asarray(torsion_factor, dtype=float), nan=0.0) ** 2
    return 1 / np.sqrt(inverse)


# ---------------------------------------------------------------- stroke study
def swept_volume(bore, stroke):
    """V_h = πD²/4·S [m³]."""
    return np.pi * bore ** 2 / 4 * stroke




def mean_piston_speed(stroke, speed):
    """c_m = S·n/30 with n in rpm, i.e. S·ω/π [m/s]."""
    return stroke * speed / np.pi


def peak(values):
    """Largest |value| of a series [same unit]."""
    return float(np.abs(np.asarray(values, dtype=float)).max())



def half(value):
    """value/2 (a crank radius from a stroke)."""
    return value / 2


def value_of_item(values, item):
    """Column ``item`` (1-based) of a per-item series [unit of values]."""
    return np.asarray(values, dtype=float)[:, int(item) - 1]


def pin_torque_of(journal_torque, tangential_load, item, crank_radius):
    """Torque in the pin of throw ``item``: the journal in front of it (journal
    ``item``) plus half the pin's tangential load times r [N·m]."""
    return pin_torque(value_of_item(journal_torque, item), tangential_load, crank_radius)


def value_near(series, crank_angle, angle, cycle):
    """The series at the grid point nearest ``angle`` of a periodic grid."""
    from crankbook.calc.multicylinder import at_angle
    return float(at_angle(series, crank_angle, angle, cycle))


def choose_amplitude(source, maximum, minimum, typed):
    """σa: half the range between the series' largest and smallest value, or the typed
    value where ``source`` is 1."""
    return choose(source, (np.asarray(maximum) - minimum) / 2, typed)


def choose_mean(source, maximum, minimum, typed):
    """σm: the middle of the series' range, or the typed value where ``source`` is 1."""
    return choose(source, (np.asarray(maximum) + minimum) / 2, typed)


def percent_change(new, old):
    """(new − old)/old·100 [%]."""
    return (new - old) / old * 100


def study_change(alternative, current, direction):
    """The stroke study's change [%] in its direction: ``direction`` 1 (to the
    alternative) (S′ − S)/S·100; 2 (from the alternative, as the thesis went from
    96 to 100 mm) (S − S′)/S′·100."""
    if direction == 2:
        return percent_change(current, alternative)
    return percent_change(alternative, current)


def engine_volume(swept_volume, firing_angle):
    """V_h·Z, Z the number of cylinders [m³]."""
    return swept_volume * np.size(firing_angle)


def same(value):
    """The value itself (shown beside its alternative)."""
    return value


def chamber_volume(swept_volume, compression_ratio):
    """Combustion-chamber volume V_c = V_h/(ε − 1) [m³]."""
    return swept_volume / (compression_ratio - 1)


def alternative_chamber_volume(hold, swept_volume, alternative_volume, compression_ratio):
    """V_c′ with the alternative swept volume V_h′: V_h′/(ε − 1) where the compression
    ratio is held (``hold`` 1: the piston's top land makes up the difference, thesis
    §4.8.3), else the current V_c = V_h/(ε − 1) (``hold`` 2: the chamber held) [m³]."""
    held = alternative_volume if hold == 1 else swept_volume
    return held / (compression_ratio - 1)


def compression_ratio_of(swept_volume, chamber_volume):
    """ε = (V_h + V_c)/V_c = 1 + V_h/V_c [-]."""
    return 1 + swept_volume / chamber_volume


def mean_power(values, speed):
    """M_mean·ω of a torque series over the cycle (closing point left out) [W]."""
    return float(np.asarray(values, dtype=float)[:-1].mean()) * speed


def alternative_torque(alt_piston_force, alt_crank_angle_from_axis, alt_rod_angle,
                       alternative_crank_radius):
    """M′ = F′·sin(ψ′ + β′)/cos β′·r′ [N·m]."""
    return np.asarray(alt_piston_force) * np.sin(alt_crank_angle_from_axis + alt_rod_angle) \
        / np.cos(alt_rod_angle) * alternative_crank_radius


def alternative_pressure(pressure_source, stroke_study_pressure, cylinder_pressure,
                         alt_model_pressure):
    """The stroke study's cylinder pressure with the alternative stroke [Pa]: the
    pressure model redone for it (``stroke_study_pressure`` 1), else — and always for a
    measured trace (``pressure_source`` 1) — the same p(α)."""
    same = float(pressure_source) == 1 or float(stroke_study_pressure) == 2
    return np.asarray(cylinder_pressure if same else alt_model_pressure, dtype=float)


def alternative_heat(choice, heat_released, volumetric_efficiency, air_density,
                     displaced_volume, air_fuel_ratio, fuel_lhv, combustion_efficiency):
    """Q′ with the alternative swept volume [J]: as typed (``choice`` 1), else its
    charge's heat η_v·ρ_i·V_d′/AFR·Q_LHV·η_c (calc.charge)."""
    fuel = charge.fuel_mass(charge.trapped_air_mass(volumetric_efficiency, air_density,
                                                    displaced_volume), air_fuel_ratio)
    return charge.chosen(choice, heat_released,
                         charge.heat_from_charge(fuel, fuel_lhv, combustion_efficiency))
