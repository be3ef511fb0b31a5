"""Torsional vibration of a crankshaft: the equivalent mass–spring system, Holzer's
table, natural frequencies and mode shapes, critical speeds, and the vector sums of
relative amplitudes that tell which orders a firing order excites.

The system is a chain of stations, front to back — pulley (or damper), one station
per throw, flywheel — with a mass moment of inertia J_i at each and a torsional
stiffness k_i for the shaft between station i and i + 1.  Free vibration at circular
frequency ω: with amplitude θ_1 = 1 at the front, Holzer's recurrence

    T_i = T_(i−1) + J_i·ω²·θ_i    (the shaft torque behind station i, T_0 = 0)
    θ_(i+1) = θ_i − T_i / k_i

ends in a residual torque T_n that is zero exactly at a natural frequency.  A
spreadsheet finds those zeros on a grid of trial frequencies; :func:`holzer_frequencies`
does the same arithmetic (the same grid, the same linear interpolation of each sign
change), so the workbook's cells and numpy agree to rounding, and
:func:`natural_frequencies` (the generalised eigenvalues of K·v = ω²·J·v) is the
independent check.

Units: J in kg·m², k in N·m/rad, ω in rad/s, f in Hz, lengths in metres, angles in
radians, speeds in r/min.

References
----------
Den Hartog, J. P., *Mechanical Vibrations*, 4th ed., McGraw-Hill, 1956, §5.6
(Holzer's method) and §5.8 (engine orders).
Ker Wilson, W., *Practical Solution of Torsional Vibration Problems*, vol. 1, 3rd ed.,
Chapman & Hall, 1956 (Carter's formula for the stiffness of a crank throw).
Thesis 000 §1 (vibration among the high-speed engine's problems); seed 004 (the
reciprocating mass's mean equivalent m_j·r²·(1/2 + λ²/8)).
"""
from typing import NamedTuple

import numpy as np

ORDERS = tuple(k / 2 for k in range(1, 25))          # 0.5, 1, …, 12


# ---------------------------------------------------------------- the equivalent system
def polar_moment(diameter, bore=0.0):
    """Polar second moment of area of a (hollow) round section, π(D⁴ − d⁴)/32 [m⁴]."""
    return np.pi * (np.asarray(diameter, dtype=float) ** 4 -
                    np.asarray(bore, dtype=float) ** 4) / 32.0


def carter_equivalent_length(journal_diameter, journal_length, pin_diameter, pin_length,
                             web_thickness, web_width, crank_radius, journal_bore=0.0,
                             pin_bore=0.0):
    """Length of plain journal-diameter shaft as stiff in torsion as one crank throw
    (journal to journal), by Carter's formula (Ker Wilson, vol. 1):

        L_e = D_j⁴·[(l_j + 0.8·h)/(D_j⁴ − d_j⁴) + 0.75·l_p/(D_p⁴ − d_p⁴) + 1.5·r/(h·b³)]

    with D, d the journal's and pin's outer and bore diameters, l their lengths, h the
    web thickness (along the axis), b the web width and r the crank radius [m].
    """
    dj4 = np.asarray(journal_diameter, dtype=float) ** 4
    return dj4 * ((journal_length + 0.8 * web_thickness) /
                  (dj4 - np.asarray(journal_bore, dtype=float) ** 4) +
                  0.75 * pin_length / (np.asarray(pin_diameter, dtype=float) ** 4 -
                                       np.asarray(pin_bore, dtype=float) ** 4) +
                  1.5 * crank_radius / (web_thickness * web_width ** 3))


def shaft_stiffness(shear_modulus, diameter, length, bore=0.0):
    """Torsional stiffness G·I_p/L of a round shaft [N·m/rad] (G in Pa, D, d, L in m)."""
    return shear_modulus * polar_moment(diameter, bore) / np.asarray(length, dtype=float)


# ---------------------------------------------------------------- Holzer's table
class HolzerTable(NamedTuple):
    """Holzer's table: θ_i [rad per rad of the front station] and T_i [N·m/rad]."""
    amplitude: np.ndarray
    torque: np.ndarray


def holzer(omega, inertia, stiffness):
    """Holzer's table at circular frequencies ``omega``.

    Parameters
    ----------
    omega : float or array (m,)
        Trial circular frequencies [rad/s].
    inertia : array (n,)
        J of the stations, front to back [kg·m²].
    stiffness : array (n − 1,)
        k of the shaft between neighbouring stations [N·m/rad].

    Returns
    -------
    amplitude : array (m, n)
        θ_i for θ_1 = 1 [rad per rad of the front station].
    torque : array (m, n)
        T_i, the shaft torque behind station i per unit front amplitude [N·m/rad];
        the last column is the residual torque, zero at a natural frequency.
    """
    omega = np.atleast_1d(np.asarray(omega, dtype=float))
    inertia = np.asarray(inertia, dtype=float)
    stiffness = np.asarray(stiffness, dtype=float)
    n = inertia.size
    amplitude = np.empty((omega.size, n))
    torque = np.empty((omega.size, n))
    w2 = omega ** 2
    theta = np.ones_like(omega)
    total = np.zeros_like(omega)
    for i in range(n):
        if i:
            theta = theta - total / stiffness[i - 1]
        total = total + inertia[i] * w2 * theta
        amplitude[:, i], torque[:, i] = theta, total
    return HolzerTable(amplitude, torque)


def holzer_frequencies(inertia, stiffness, step, max_frequency):
    """Natural frequencies from Holzer's residual on a grid, as the workbook finds them.

    The residual torque is evaluated at f = step, 2·step, … ≤ max_frequency [Hz]; each
    sign change between neighbouring points gives a natural frequency by linear
    interpolation, f_a − R_a·(f_b − f_a)/(R_b − R_a), b = a + 1; a residual exactly 0
    at a grid point b is that point (the formula gives f_b), counted once.  The
    rigid-body mode (f = 0) is not counted.

    Returns
    -------
    frequencies : array [Hz]
        Lowest first; at most n − 1 (n stations); empty if the grid finds none.
    """
    grid = step * np.arange(1, int(np.floor(max_frequency / step + 1e-9)) + 1)
    residual = holzer(2 * np.pi * grid, inertia, stiffness).torque[:, -1]
    found = _crossings(grid, residual, sign_changes(residual), np.asarray(inertia).size - 1)
    return found[~np.isnan(found)]


def natural_frequencies(inertia, stiffness):
    """Natural frequencies [Hz] of the chain from the generalised eigenvalue problem
    K·v = ω²·J·v (the independent check of Holzer's table), rigid-body mode left out."""
    inertia = np.asarray(inertia, dtype=float)
    stiffness = np.asarray(stiffness, dtype=float)
    n = inertia.size
    K = np.zeros((n, n))
    for i, k in enumerate(stiffness):
        K[i, i] += k
        K[i + 1, i + 1] += k
        K[i, i + 1] -= k
        K[i + 1, i] -= k
    scale = 1.0 / np.sqrt(inertia)            # symmetric form: J^-½ K J^-½
    eigen = np.linalg.eigvalsh(scale[:, None] * K * scale[None, :])
    omega2 = np.sort(np.clip(eigen, 0.0, None))[1:]
    return np.sqrt(omega2) / (2 * np.pi)


def mode_shapes(frequencies, inertia, stiffness):
    """(stations, modes) relative amplitudes at each natural frequency, front = 1."""
    return mode_table(frequencies, inertia, stiffness).amplitude


# ---------------------------------------------------------------- orders and speeds
def critical_speeds(frequencies, orders=ORDERS):
    """(orders, modes) crankshaft speeds [r/min] at which order k meets mode f:
    n = 60·f/k."""
    return 60.0 * np.asarray(frequencies, dtype=float)[None, :] / \
        np.asarray(orders, dtype=float)[:, None]


def relative_amplitude_sum(throw_amplitudes, firing_angle, orders=ORDERS):
    """|Σ β_i·e^(j·k·φ_i)| per order and mode: how strongly order k of the cylinders'
    torques drives each mode (Den Hartog §5.8's vector sums).

    Parameters
    ----------
    throw_amplitudes : array (cylinders, modes)
        The mode shape at each cylinder's throw (β_i).
    firing_angle : array (cylinders,)
        Crank angle of each cylinder's firing [rad].
    orders : sequence of k

    Returns
    -------
    array (orders, modes) [-]
    """
    beta = np.asarray(throw_amplitudes, dtype=float)
    phase = np.asarray(firing_angle, dtype=float)
    k = np.asarray(orders, dtype=float)
    rotor = np.exp(1j * k[:, None] * phase[None, :])          # (orders, cylinders)
    return np.abs(rotor @ beta)


# ---------------------------------------------------------------- the workbook's columns
# The torsion sheets hold Holzer's table on a live grid of HOLZER_ROWS trial
# frequencies, f = step, 2·step, …; each function below is one column or table.
HOLZER_ROWS = 400


def station_count(throw):
    """Stations of the equivalent system: pulley, one per throw, flywheel."""
    return int(np.max(np.asarray(throw, dtype=float))) + 2


def section_count(throw):
    """Shaft sections between neighbouring stations (= modes that can be found)."""
    return station_count(throw) - 1


def frequency_grid(holzer_step, holzer_max_frequency):
    """The trial frequencies f = step·(1 … HOLZER_ROWS) up to the highest [Hz]; NaN
    (a blank row) beyond it."""
    f = holzer_step * np.arange(1, HOLZER_ROWS + 1, dtype=float)
    return np.where(f <= holzer_max_frequency, f, np.nan)


def station_inertias(pulley_inertia, ring_mass, crank_radius, web_inertia, flywheel_inertia,
                     station_inertia_typed=0.0):
    """J of every station [kg·m²]: the pulley, each throw (its rods' ring mass — the
    big ends and the reciprocating masses by their mean — at the crank radius, plus
    both webs), the flywheel; a typed value > 0 replaces the station's."""
    throws = np.asarray(ring_mass, dtype=float) * crank_radius ** 2 + web_inertia
    computed = np.concatenate([[pulley_inertia], throws, [flywheel_inertia]])
    typed = np.broadcast_to(np.asarray(station_inertia_typed, dtype=float), computed.shape)
    return np.where(typed > 0, typed, computed)


def flywheel_station_inertia(flywheel_inertia_typed, engine_flywheel_inertia):
    """The typed flywheel inertia, or (0 typed) the flywheel sheet's [kg·m²]."""
    return flywheel_inertia_typed if flywheel_inertia_typed > 0 else engine_flywheel_inertia


def section_stiffnesses(shear_modulus, main_journal_diameter, main_journal_bore,
                        throw_equivalent_length, throw, section_stiffness_typed=0.0):
    """k of every section [N·m/rad]: one throw's equivalent length of journal each; a
    typed value > 0 replaces the section's."""
    k = shaft_stiffness(shear_modulus, main_journal_diameter, throw_equivalent_length,
                        main_journal_bore)
    computed = np.full(section_count(throw), float(k))
    typed = np.broadcast_to(np.asarray(section_stiffness_typed, dtype=float), computed.shape)
    return np.where(typed > 0, typed, computed)


def holzer_table(holzer_frequency, station_inertia, section_stiffness):
    """Holzer's table at each trial frequency [Hz], θ_1 = 1: a :class:`HolzerTable` of
    (rows, stations) arrays; a blank (NaN) trial frequency is a blank row."""
    f = np.ravel(holzer_frequency).astype(float)
    amplitude, torque = holzer(2 * np.pi * f, station_inertia, section_stiffness)
    amplitude[np.isnan(f)] = np.nan
    return HolzerTable(amplitude, torque)


def holzer_residual(holzer_torque):
    """The last station's T: zero at a natural frequency."""
    return np.asarray(holzer_torque, dtype=float)[:, -1]


def sign_changes(holzer_residual):
    """Running count of sign changes down the residual column: row b counts one when
    R_(b−1) ≠ 0 and R_(b−1)·R_b ≤ 0 (a zero at b is b's); the first row 0."""
    r = np.asarray(holzer_residual, dtype=float)
    step = np.concatenate([[0.0], ((r[:-1] != 0) & (r[:-1] * r[1:] <= 0)).astype(float)])
    return np.cumsum(step)


def natural_frequency(holzer_frequency, holzer_residual, holzer_sign_changes, throw):
    """Natural frequency of each mode [Hz] (NaN where the grid finds none)."""
    return _crossings(holzer_frequency, holzer_residual, holzer_sign_changes,
                      section_count(throw))


def _crossings(frequency, residual, count, modes):
    """Mode m is the row b where the running count of sign changes first reaches m,
    interpolated linearly with b − 1: f_a − R_a·(f_b − f_a)/(R_b − R_a) [Hz]; NaN for a
    mode the grid does not reach."""
    f = np.asarray(frequency, dtype=float)
    r = np.asarray(residual, dtype=float)
    count = np.asarray(count, dtype=float)
    out = np.full(modes, np.nan)
    for m in range(1, modes + 1):
        rows = np.flatnonzero(count == m)
        if rows.size:
            b = rows[0]
            a = b - 1
            out[m - 1] = f[a] - r[a] * (f[b] - f[a]) / (r[b] - r[a])
    return out


def torsion_orders():
    """The orders k = 0.5, 1, …, 12 of the critical-speed table."""
    return np.asarray(ORDERS, dtype=float)


def critical_speed_table(natural_frequency, torsion_order):
    """(orders, modes) critical speeds as angular velocities [rad/s] (the sheet's r/min
    in SI); NaN where a mode was not found."""
    return critical_speeds(natural_frequency, np.ravel(torsion_order)) * np.pi / 30.0


def critical_in_range(critical_speed, operating_speed):
    """1 where a critical speed lies within the operating points' speeds (inclusive)."""
    c = np.asarray(critical_speed, dtype=float)
    low, high = np.min(operating_speed), np.max(operating_speed)
    with np.errstate(invalid="ignore"):
        return ((c >= low) & (c <= high)).astype(float)


def found_none(natural_frequency):
    """1 when the Holzer grid found no natural frequency at all, else 0 (modes above
    the grid are expected: only the lowest matter to an engine's orders)."""
    return float(np.all(np.isnan(np.asarray(natural_frequency, dtype=float))))


# ---------------------------------------------------------------- mode shapes
def station_numbers(throw):
    """The stations 1 … n of the mode-shape table (1 = pulley, n = flywheel)."""
    return np.arange(1, station_count(throw) + 1, dtype=float)


def mode_table(natural_frequency, station_inertia, section_stiffness):
    """Holzer's table redone at each natural frequency [Hz]: a :class:`HolzerTable` of
    (stations, modes) arrays — the mode shapes (θ_1 = 1) and the shaft torques behind
    each station [N·m/rad]; a mode the grid did not find is a column of NaN."""
    f = np.asarray(natural_frequency, dtype=float)
    shape = (np.asarray(station_inertia).size, f.size)
    amplitude, torque = np.full(shape, np.nan), np.full(shape, np.nan)
    found = ~np.isnan(f)
    table = holzer(2 * np.pi * f[found], station_inertia, section_stiffness)
    amplitude[:, found], torque[:, found] = table.amplitude.T, table.torque.T
    return HolzerTable(amplitude, torque)


def modal_inertia(station_inertia, mode_shape):
    """J_m = Σ J_i·θ_i² of each mode, front amplitude 1 [kg·m²] (NaN: a mode not found,
    whose shape is NaN)."""
    return np.asarray(station_inertia, dtype=float) @ np.asarray(mode_shape, dtype=float) ** 2


def relative_amplitude_sums(mode_shape, throw, firing_angle, torsion_order):
    """(orders, modes) |Σ θ_(throw+1)·e^(j·k·φ)| over the cylinders: each cylinder
    drives the station of its throw with its firing angle φ [rad]."""
    theta = np.asarray(mode_shape, dtype=float)
    stations = np.asarray(throw, dtype=int)            # throw t is station t + 1
    return relative_amplitude_sum(theta[stations, :], np.ravel(firing_angle),
                                  np.ravel(torsion_order))


def resonant_torque_amplitude(cylinder_torque_cosine, cylinder_torque_sine,
                              cylinder_inertia_torque_cosine, cylinder_inertia_torque_sine,
                              torque_order, torsion_order, critical_speed, speed):
    """One cylinder's order-k torque amplitude at the critical speed n_c of order k and
    mode n [N·m]: the gas part as at the design speed (the same pressure), the inertia
    part scaled with the speed squared,

        A_k(n_c) = |(a_k − a_k,j) + (n_c/n)²·a_k,j, (b_k − b_k,j) + (n_c/n)²·b_k,j|

    Parameters
    ----------
    cylinder_torque_cosine, cylinder_torque_sine : array (orders,) [N·m]
        a_k, b_k of one cylinder's torque at the design speed.
    cylinder_inertia_torque_cosine, cylinder_inertia_torque_sine : array (orders,) [N·m]
        a_k,j, b_k,j of its inertia part at the design speed.
    torque_order : array (orders,), the orders of those harmonics [-]
    torsion_order : array (N,) or (N, 1), the orders of this table [-]
    critical_speed : array (N, modes) [rad/s]; NaN where the mode was not found
    speed : float, the design speed [rad/s]

    Returns
    -------
    array (N, modes) [N·m]; 0 where the torque has no harmonic of that order, NaN
    where there is no critical speed.

    References
    ----------
    Den Hartog, *Mechanical Vibrations*, §5.8: the exciting torque at resonance is the
    harmonic at the critical speed; the inertia torque grows with ω².
    """
    k = np.ravel(torsion_order).astype(float)
    orders = np.asarray(torque_order, dtype=float)
    # the sheet's MATCH(k, orders, 0) is exact on these halves; a tolerance keeps the
    # comparison's rounding perturbations from reading a jump to 0 as a derivative
    same = np.abs(k[:, None] - orders[None, :]) <= 1e-9
    found, at = same.any(axis=1), np.argmax(same, axis=1)

    def part(values):
        return np.where(found, np.asarray(values, dtype=float)[at], 0.0)[:, None]
    scale = (np.asarray(critical_speed, dtype=float) / speed) ** 2 - 1.0
    a = part(cylinder_torque_cosine) + scale * part(cylinder_inertia_torque_cosine)
    b = part(cylinder_torque_sine) + scale * part(cylinder_inertia_torque_sine)
    return np.hypot(a, b)


def resonant_amplitude(resonant_torque_amplitude, relative_amplitude_sum,
                       torsion_damping_ratio, natural_frequency, modal_inertia):
    """Amplitude of the front station at resonance of order k with mode n [rad], by
    the energy balance: the work of one cylinder's order-k torque A_k (at the critical
    speed) over a cycle, π·A_k·Σ·θ_1 (Σ the vector sum), equals the modal damping's
    2π·ζ·ω_n²·J_m·θ_1², so

        θ_1 = A_k·Σ / (2·ζ·ω_n²·J_m)

    Parameters
    ----------
    resonant_torque_amplitude : array (N, modes) [N·m]
    relative_amplitude_sum : array (N, modes) [-]
    torsion_damping_ratio : float ζ [-]; 0 leaves the amplitude blank (NaN)
    natural_frequency : array (modes,) [Hz]
    modal_inertia : array (modes,) [kg·m²]

    Returns
    -------
    array (N, modes) [rad]

    References
    ----------
    Den Hartog, *Mechanical Vibrations*, §5.8 (the energy method at resonance).
    """
    omega2 = (2 * np.pi * np.asarray(natural_frequency, dtype=float)) ** 2
    if torsion_damping_ratio <= 0:          # no modal damping: the balance has no answer
        return np.full(np.shape(resonant_torque_amplitude), np.nan)
    return np.asarray(resonant_torque_amplitude, dtype=float) * np.asarray(
        relative_amplitude_sum, dtype=float) / (
        2 * torsion_damping_ratio * omega2[None, :] * np.asarray(modal_inertia, dtype=float))


# ---------------------------------------------------------------- Campbell diagram
CAMPBELL_ROWS = 101        # speeds 0 … 1.25·n_max: the operating range's box ends within 1.25 %
CAMPBELL_MODES = 3
MAJOR, MINOR, HALF = 2.0, 1.0, 0.0


def campbell_mode_count(throw):
    """Natural-frequency lines: the lowest three modes (or fewer, if fewer exist)."""
    return min(CAMPBELL_MODES, section_count(throw))


def campbell_speeds(operating_speed):
    """Speeds 0 … 1.25 × the highest operating speed in 100 steps [rad/s]."""
    return np.arange(CAMPBELL_ROWS) * 1.25 * np.max(operating_speed) / (CAMPBELL_ROWS - 1)


def order_lines(campbell_speed):
    """(speeds, orders) f = k·ω/2π [Hz] (= k·n/60 with n in r/min) for the orders
    k = 0.5, 1, …, 12 of a four-stroke engine; ``campbell_speed`` ω [rad/s]."""
    omega = np.ravel(campbell_speed).astype(float)
    return omega[:, None] * np.asarray(ORDERS)[None, :] / (2 * np.pi)


def major_orders(firing_angle, torque_order):
    """Per order k: 2 where every cylinder's order-k torque is in phase — |Σ e^(j·k·φ_i)|
    equals the number of cylinders (the major orders, k = n/2, n, … of an evenly firing
    four-stroke inline engine; Den Hartog §5.8) — 1 for another whole order, 0 for a
    half order.  ``firing_angle`` φ_i [rad], ``torque_order`` k [-]."""
    phi = np.asarray(firing_angle, dtype=float)
    k = np.ravel(torque_order).astype(float)
    total = np.abs(np.exp(1j * k[:, None] * phi[None, :]).sum(axis=1))
    whole = np.where(np.abs(k - np.round(k)) < 1e-9, MINOR, HALF)
    return np.where(np.abs(total - phi.size) < 1e-6, MAJOR, whole)


def operating_box_speed(campbell_speed, operating_speed):
    """The x of the operating range's box on the Campbell diagram [rad/s]: n_min, n_min,
    n_max, n_max, n_min, then n_min on every further row (the box drawn once)."""
    low, high = np.min(operating_speed), np.max(operating_speed)
    rows = np.ravel(campbell_speed).size
    corners = np.array([low, low, high, high, low])
    return np.concatenate([corners, np.full(max(rows - 5, 0), low)])[:rows]


def operating_box_frequency(campbell_speed):
    """The y of the box [Hz]: 0, the top order line's highest frequency (12·ω_max/2π),
    the same, 0, 0, then 0."""
    speeds = np.ravel(campbell_speed).astype(float)
    top = ORDERS[-1] * np.max(speeds) / (2 * np.pi)
    corners = np.array([0.0, top, top, 0.0, 0.0])
    return np.concatenate([corners, np.zeros(max(speeds.size - 5, 0))])[:speeds.size]


def natural_lines(natural_frequency, campbell_speed):
    """(speeds, lines) the lowest natural frequencies, constant over speed [Hz]."""
    f = np.asarray(natural_frequency, dtype=float)[:CAMPBELL_MODES]
    return np.repeat(f[None, :], np.ravel(campbell_speed).size, axis=0)
