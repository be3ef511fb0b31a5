"""The charge an engine breathes, the heat it releases, friction and brake figures.

The pressure model (``calc.pressure``) releases a heat Q per cycle.  Typed, Q is
whatever the user states (the thesis analysed its own traces); from the charge it
follows the engine, as every engine-design text starts (Heywood ch. 2, Pulkrabek
ch. 2, 内燃机原理 ch. 2):

* intake density ρ_i = p_i/(R·T_i), air R = 287 J/(kg·K);
* trapped air m_a = η_v(n)·ρ_i·V_d, η_v read from a table of (speed, η_v) points
  (linear between the points, the end values beyond them);
* fuel m_f = m_a/AFR, heat Q = m_f·Q_LHV·η_c.

Indicated work comes from the p–V loop (``calc.cycle.indicated_work``); friction by
the Chen–Flynn form FMEP = A + B·p_max + C·S_p + D·S_p² (or typed per speed);
brake figures by the definitions of Heywood §2.5–2.9 for a four-stroke engine
(n_R = 2 revolutions per cycle):

* BMEP = IMEP − FMEP, brake torque T_b = BMEP·V_D/(4π) (V_D all cylinders),
  brake power P_b = T_b·ω, mechanical efficiency η_m = BMEP/IMEP;
* fuel flow ṁ_f = Z·m_f·n/2 (n in rev/s), BSFC = ṁ_f/P_b,
  thermal efficiency η = W/(m_f·Q_LHV) (indicated or brake work).

SI units throughout (kg, J, Pa, K, rad/s).

References
----------
J. B. Heywood, *Internal Combustion Engine Fundamentals*, McGraw-Hill 1988:
§2.5 (torque and power), §2.7 (mean effective pressure), §2.9 (specific fuel
consumption, efficiencies), §2.10 (volumetric efficiency), §13.1 (friction), and
§5.3 (the ideal Otto cycle, η = 1 − r^(1−γ)).
S. K. Chen, P. F. Flynn, "Development of a single cylinder compression ignition
research engine", SAE 650733, 1965 (the friction correlation's form).
W. W. Pulkrabek, *Engineering Fundamentals of the Internal Combustion Engine*,
2nd ed., Pearson 2004, ch. 2.
"""
import numpy as np

AIR_GAS_CONSTANT = 287.0     # J/(kg·K), dry air (Heywood, App. D)
REVOLUTIONS_PER_CYCLE = 2.0  # a four-stroke engine


# ---------------------------------------------------------------- tables over speed
def table_segment(x, table_x):
    """1-based index k of the table segment [x_k, x_k+1] used at each ``x``: the first
    segment below the table, the last above it (the workbook's
    MIN(MAX(MATCH(x, X, 1), 1), n − 1), with MATCH's #N/A below the table read as 1).

    Parameters
    ----------
    x : array_like
        Where the table is read (any unit, the table's).
    table_x : array_like
        The table's ascending abscissae (at least two).
    """
    points = np.asarray(table_x, dtype=float)
    x = np.asarray(x, dtype=float)
    found = np.searchsorted(points, x, side="right")
    return np.clip(found, 1, points.size - 1).astype(float)


def table_value(x, table_x, table_y, segment):
    """The table read at ``x``: linear between its points, its first and last values
    beyond its ends (a curve is not extrapolated past what was measured)."""
    points = np.asarray(table_x, dtype=float)
    values = np.asarray(table_y, dtype=float)
    x = np.asarray(x, dtype=float)
    k = np.asarray(segment, dtype=int) - 1
    inside = values[k] + (x - points[k]) * (values[k + 1] - values[k]) \
        / (points[k + 1] - points[k])
    return np.where(x <= points[0], values[0], np.where(x >= points[-1], values[-1], inside))


def chosen(choice, typed, table):
    """``typed`` where ``choice`` is 1 (fixed or typed), else ``table`` (from the
    table or the charge)."""
    return np.where(np.asarray(choice) == 1, typed, table)


def not_ascending(table_x):
    """1 when the table's speeds do not strictly ascend (or fewer than two), else 0."""
    points = np.asarray(table_x, dtype=float)
    return float(points.size < 2 or bool(np.any(np.diff(points) <= 0)))


# ---------------------------------------------------------------- the charge
def intake_air_density(intake_pressure, intake_temperature, gas_constant=AIR_GAS_CONSTANT):
    """ρ_i = p_i/(R·T_i) [kg/m³] (ideal gas; Heywood eq. 2.27's ρ_a,i).

    Parameters
    ----------
    intake_pressure : float
        p_i, absolute [Pa].
    intake_temperature : float
        T_i [K].
    gas_constant : float
        R of the charge [J/(kg·K)].
    """
    return intake_pressure / (gas_constant * intake_temperature)


def trapped_air_mass(volumetric_efficiency, air_density, displaced_volume):
    """m_a = η_v·ρ_i·V_d, the air one cylinder takes in per cycle [kg] (Heywood §2.10)."""
    return volumetric_efficiency * air_density * displaced_volume


def fuel_mass(trapped_air_mass, air_fuel_ratio):
    """m_f = m_a/AFR [kg]."""
    return trapped_air_mass / air_fuel_ratio


def heat_from_charge(fuel_mass, fuel_lhv, combustion_efficiency):
    """Q = m_f·Q_LHV·η_c, the heat the cylinder's charge releases per cycle [J]
    (Heywood eq. 3.27's combustion efficiency)."""
    return fuel_mass * fuel_lhv * combustion_efficiency


def relative_air_fuel_ratio(air_fuel_ratio, stoichiometric_air_fuel_ratio):
    """λ = AFR/AFR_s [-] (Heywood eq. 3.10)."""
    return air_fuel_ratio / stoichiometric_air_fuel_ratio


# ---------------------------------------------------------------- friction and brake figures
def chen_flynn_fmep(peak_pressure, mean_piston_speed, constant, pressure_factor,
                    speed_factor, speed_squared_factor):
    """FMEP = A + B·p_max + C·S_p + D·S_p² [Pa] (Chen and Flynn, SAE 650733).

    Parameters
    ----------
    peak_pressure : array_like
        p_max, the cycle's peak cylinder pressure [Pa].
    mean_piston_speed : array_like
        S_p = 2·S·n [m/s].
    constant : float
        A [Pa].
    pressure_factor : float
        B [-].
    speed_factor : float
        C [Pa·s/m].
    speed_squared_factor : float
        D [Pa·s²/m²].
    """
    s = np.asarray(mean_piston_speed, dtype=float)
    return constant + pressure_factor * np.asarray(peak_pressure, dtype=float) \
        + speed_factor * s + speed_squared_factor * s ** 2


def brake_mean_effective_pressure(imep, fmep):
    """BMEP = IMEP − FMEP [Pa] (Heywood §2.7)."""
    return np.asarray(imep, dtype=float) - np.asarray(fmep, dtype=float)


def torque_of_mep(mean_effective_pressure, engine_displacement):
    """T = mep·V_D/(2π·n_R) = mep·V_D/(4π) for a four-stroke engine [N·m] (Heywood
    eq. 2.19)."""
    return np.asarray(mean_effective_pressure, dtype=float) * engine_displacement \
        / (2 * np.pi * REVOLUTIONS_PER_CYCLE)


def power_of_torque(torque, angular_velocity):
    """P = T·ω [W]."""
    return np.asarray(torque, dtype=float) * np.asarray(angular_velocity, dtype=float)


def ratio(numerator, denominator):
    """numerator/denominator (the mechanical efficiency BMEP/IMEP) [-]."""
    return np.asarray(numerator, dtype=float) / np.asarray(denominator, dtype=float)


def fuel_flow(fuel_mass, cylinder_count, angular_velocity):
    """ṁ_f = Z·m_f·n/n_R, n = ω/(2π) [kg/s]."""
    return cylinder_count * np.asarray(fuel_mass, dtype=float) \
        * np.asarray(angular_velocity, dtype=float) / (2 * np.pi * REVOLUTIONS_PER_CYCLE)


def specific_fuel_consumption(fuel_flow, power):
    """sfc = ṁ_f/P [kg/J] (Heywood eq. 2.21); NaN (a blank cell) where P ≤ 0."""
    power = np.asarray(power, dtype=float)
    return np.where(power > 0, np.asarray(fuel_flow, dtype=float) / np.where(power > 0, power, 1),
                    np.nan)


def thermal_efficiency(work, fuel_mass, fuel_lhv):
    """η = W/(m_f·Q_LHV) per cylinder and cycle [-] (Heywood eq. 2.23, the fuel
    conversion efficiency)."""
    return np.asarray(work, dtype=float) / (np.asarray(fuel_mass, dtype=float) * fuel_lhv)


def work_of_mep(mean_effective_pressure, displaced_volume):
    """W = mep·V_d, per cylinder and cycle [J]."""
    return np.asarray(mean_effective_pressure, dtype=float) * displaced_volume


def speed_of_peak(operating_speed, values):
    """The operating speed of the largest value (the first, where it recurs) [rad/s]."""
    values = np.asarray(values, dtype=float)
    if not np.isfinite(values).any():
        return float("nan")                  # no point has a value: a blank cell
    return float(np.asarray(operating_speed, dtype=float)[int(np.nanargmax(values))])


def otto_efficiency(compression_ratio, heat_capacity_ratio):
    """η = 1 − r^(1−γ), the ideal constant-volume cycle (Heywood eq. 5.31) [-]."""
    return 1 - compression_ratio ** (1 - heat_capacity_ratio)


# ---------------------------------------------------------------- choices the workbook offers
def chosen_from_table(choice, typed, x, table_x, table_y, segment):
    """``typed`` where ``choice`` is 1 (fixed), else the table read at ``x``."""
    return chosen(choice, typed, table_value(x, table_x, table_y, segment))


def fuel_mass_of(choice, heat_released, trapped_air_mass, air_fuel_ratio, fuel_lhv,
                 combustion_efficiency):
    """The fuel per cylinder and cycle behind the model's heat [kg]: Q/(Q_LHV·η_c) for a
    typed heat (``choice`` 1), else m_a/AFR."""
    return chosen(choice, heat_released / (fuel_lhv * combustion_efficiency),
                  fuel_mass(trapped_air_mass, air_fuel_ratio))


def heat_per_cycle(choice, heat_released, fuel_mass, fuel_lhv, combustion_efficiency):
    """The pressure model's heat per cycle [J]: typed (``choice`` 1), else m_f·Q_LHV·η_c."""
    return chosen(choice, heat_released, heat_from_charge(fuel_mass, fuel_lhv,
                                                          combustion_efficiency))


def friction_mep(choice, typed, peak_pressure, mean_piston_speed, fmep_constant,
                 fmep_pressure_factor, fmep_speed_factor, fmep_speed_squared_factor):
    """FMEP by Chen–Flynn (``choice`` 1), else as typed [Pa]."""
    return chosen(choice, chen_flynn_fmep(peak_pressure, mean_piston_speed, fmep_constant,
                                          fmep_pressure_factor, fmep_speed_factor,
                                          fmep_speed_squared_factor), typed)


def brake_thermal_efficiency(mean_effective_pressure, displaced_volume, fuel_mass, fuel_lhv):
    """η_b = BMEP·V_d/(m_f·Q_LHV) [-] (Heywood eq. 2.23 with the brake work)."""
    return thermal_efficiency(work_of_mep(mean_effective_pressure, displaced_volume),
                              fuel_mass, fuel_lhv)


def on_every_point(value, operating_speed):
    """A scalar repeated on every operating point (a vertical line on a chart over
    speed) (P,)."""
    return np.full(np.size(operating_speed), float(value))


def drop_line(values):
    """A vertical line's heights on a chart over speed: 0 at the first point, the
    largest value at the others (drawn at one speed, it runs from the axis to the
    peak) (P,)."""
    values = np.asarray(values, dtype=float)
    top = np.nanmax(values) if np.isfinite(values).any() else np.nan
    out = np.full(values.shape, top)
    out[0] = 0.0
    return out
