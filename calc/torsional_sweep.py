"""The forced torsional response over a speed sweep, laid out as the workbook lays it out.

:mod:`crankbook.calc.forced_torsion` holds the physics of one frequency; this module
runs it over every speed of a sweep and every torque order k = 0.5 … 12, one row per
(speed, order) pair — speed s, order k at row 24·(s − 1) + 2k — so that each workbook
formula has one calc function here, cell for cell:

* the sweep: ``p_sweep_speed_count`` even speeds from the lowest to the highest, and
  before them the critical speeds of the lowest three modes that fall strictly inside
  the range (24 reserved rows per mode, blank where a critical speed lies outside),
  sorted, so that no resonance peak falls between grid points;
* the excitation of each station: its cylinders' order-k torque harmonics with their
  firing phase.  One cylinder's torque is M(α) = M_mean + Σ a_k·cos kα + b_k·sin kα
  (the torque-harmonics sheet) and cylinder c's is M(α − φ_c + 360°) (the engine-torque
  sheet's: its firing angle φ_c counts from cylinder 1's firing TDC, at 360° of M's
  cycle), so its order-k part is Re[(a_k − i·b_k)·e^(−ik(φ_c − 360°))·e^(ikα)]: the
  complex amplitude F = (a − ib)·e^(−ik(φ_c − 360°)),
  the phase convention of every formula here (tested by rebuilding the engine's
  torque from it).  The gas part is the design speed's; the inertia part scales with
  (n/n_design)², as the critical-speed table's resonant torque does;
* an absolute damper to ground at every throw (c_cyl), the shafts' loss factor
  η = 2ζ + η_shaft on every stiffness (a modal damping ratio ζ is a loss factor 2ζ at
  resonance; a hysteretic η gives C = η·k/ω at the order's own frequency ω), and a
  damper at the front: its ring J_d on a coupling k_d + iωc_d is a station of its own,
  condensed exactly onto the hub — a leaf station's dynamic stiffness,
  ω²J_d·z/(z − ω²J_d), z = k_d + iωc_d, adds to the hub's ω²J_1;
* the two passes of the complex Holzer recurrence (θ_1 = 1 without excitation,
  θ_1 = 0 with it), the front amplitude θ_1 = −R_forced/R_free, each section's
  elastic torque k·Δθ = T/(1 + iη) and its running sum over the orders (the
  synthesis, the rules' conservative sum of order amplitudes).

Units SI: speeds rad/s, torques N·m, angles rad, stresses Pa.  Blank cells are NaN.

References
----------
Den Hartog, J. P., *Mechanical Vibrations*, 4th ed., McGraw-Hill, 1956, §5.6–5.9.
Wilson, W. K., *Practical Solution of Torsional Vibration Problems*, vol. 2, 3rd ed.,
Chapman & Hall, 1963 (forced response of a multi-mass system by Holzer's tabulation).
IACS UR M68 Rev. 2 (2005), §3: the synthesis and the permissible stresses.
"""
from typing import NamedTuple

import numpy as np

from crankbook.calc import forced_torsion
from crankbook.calc.torsional import CAMPBELL_MODES, ORDERS

ORDER_COUNT = len(ORDERS)                # 24: k = 0.5, 1, …, 12


# ---------------------------------------------------------------- the sweep
def sweep_bound(typed, operating_speed, highest=False):
    """The sweep's lowest (or highest) speed: the typed one, or 0 = the operating
    points' lowest (highest) [rad/s]."""
    if typed > 0:
        return float(typed)
    speeds = np.asarray(operating_speed, dtype=float)
    return float(np.max(speeds) if highest else np.min(speeds))


def sweep_low(sweep_speed_min, operating_speed):
    """n_low [rad/s] (module docstring)."""
    return sweep_bound(sweep_speed_min, operating_speed)


def sweep_high(sweep_speed_max, operating_speed):
    """n_high [rad/s] (module docstring)."""
    return sweep_bound(sweep_speed_max, operating_speed, highest=True)


def reserved_rows(critical_speed):
    """Rows kept for critical speeds: 24 per mode found, of the lowest three (a mode
    above the Holzer table's frequencies has no critical speeds to keep)."""
    critical = np.asarray(critical_speed, dtype=float).reshape(ORDER_COUNT, -1)
    found = int(np.sum(np.isfinite(critical).any(axis=0)))
    return ORDER_COUNT * min(CAMPBELL_MODES, found)


def sweep_candidates(sweep_low, sweep_high, sweep_speed_count, critical_speed, rows=None):
    """The unsorted sweep: the reserved critical-speed rows (mode-major, order within),
    a critical speed strictly inside (n_low, n_high) or NaN, then the even speeds
    n_low + j·(n_high − n_low)/(count − 1) [rad/s].  ``rows``: the rows a workbook was
    built with (its reserved rows are those beyond the count); None: 24 per mode found."""
    critical = np.asarray(critical_speed, dtype=float).reshape(ORDER_COUNT, -1)
    count = int(round(sweep_speed_count))
    reserved = reserved_rows(critical) if rows is None else max(0, int(rows) - count)
    modes = min(reserved // ORDER_COUNT, critical.shape[1])
    kept = critical[:, :modes].T.ravel()                 # mode 1's orders, then mode 2's …
    with np.errstate(invalid="ignore"):
        kept = np.where((kept > sweep_low) & (kept < sweep_high), kept, np.nan)
    kept = np.concatenate([kept, np.full(reserved - kept.size, np.nan)])
    even = sweep_low + np.arange(count) * (sweep_high - sweep_low) / (count - 1)
    return np.concatenate([kept, even])


def sweep_speeds(sweep_candidate):
    """The candidates sorted, the blank ones last [rad/s]."""
    c = np.asarray(sweep_candidate, dtype=float)
    found = np.sort(c[np.isfinite(c)])
    return np.concatenate([found, np.full(c.size - found.size, np.nan)])


def sweep_stale(sweep_speed_count, sweep_candidate):
    """1 when the count was typed after the sweep's rows were laid out: more speeds
    than rows, or rows beyond the count that are not whole blocks of 24."""
    rows = np.size(sweep_candidate)
    count = int(round(sweep_speed_count))
    return float(count > rows or (rows - count) % ORDER_COUNT != 0)


# ---------------------------------------------------------------- rows: speed × order
def response_orders(sweep_speed, rows=None):
    """The order k of each (speed, order) row: 24 rows for each speed the sweep holds
    (the blank ones, last in the sorted sweep, get none); ``rows``, of a workbook read
    back: the rows it was built with, blank for a speed that has none [-]."""
    speeds = np.ravel(sweep_speed).astype(float)
    held = int(np.sum(np.isfinite(speeds))) if rows is None else int(rows) // ORDER_COUNT
    orders = np.tile(np.asarray(ORDERS), held)
    return np.where(np.repeat(np.isfinite(np.concatenate(
        [speeds, np.full(max(0, held - speeds.size), np.nan)])[:held]), ORDER_COUNT), orders, np.nan)


def response_speeds(response_order, sweep_speed):
    """The speed of each row [rad/s]."""
    order = np.ravel(response_order).astype(float)
    rows = order.size // ORDER_COUNT
    speeds = np.concatenate([np.ravel(sweep_speed).astype(float), np.full(rows, np.nan)])
    return np.where(np.isfinite(order), np.repeat(speeds[:rows], ORDER_COUNT), np.nan)


def speeds_without_rows(sweep_speed, response_order):
    """The sweep's speeds beyond the forced-response rows laid out (a critical speed an
    edit brought into the sweep after the workbook was built)."""
    held = int(np.sum(np.isfinite(np.ravel(sweep_speed).astype(float))))
    return float(max(0, held - np.size(response_order) // ORDER_COUNT))


def response_sweep_rows(response_order):
    """The sweep row s (1-based) each row belongs to."""
    return np.arange(np.size(response_order)) // ORDER_COUNT + 1.0


def response_omega(response_order, response_speed):
    """ω = k·Ω of each row [rad/s]."""
    return np.ravel(response_order).astype(float) * np.ravel(response_speed).astype(float)


def response_harmonic(response_order, response_speed, speed, harmonic, inertia_harmonic):
    """One cylinder's order-k harmonic (cosine a or sine b) at the row's speed: the
    design speed's value with its inertia part scaled by (n/n_design)² [N·m]."""
    k = np.ravel(response_order).astype(float)
    n = np.ravel(response_speed).astype(float)
    index = np.where(np.isfinite(k), np.round(2 * np.nan_to_num(k)) - 1, 0).astype(int)
    total = np.asarray(harmonic, dtype=float)[index]
    inertia = np.asarray(inertia_harmonic, dtype=float)[index]
    return np.where(np.isfinite(k), total + ((n / speed) ** 2 - 1) * inertia, np.nan)


class Complex(NamedTuple):
    re: np.ndarray
    im: np.ndarray


def station_excitation(response_order, response_cosine, response_sine, firing_angle, throw,
                       station_count):
    """(rows, stations) complex order-k torque on each station: Σ over the cylinders on
    its throw of (a − ib)·e^(−ik(φ_c − 360°)) [N·m]; the pulley and the flywheel carry
    none.  ``firing_angle`` φ_c [rad]."""
    k = np.ravel(response_order).astype(float)[:, None]
    a = np.ravel(response_cosine).astype(float)[:, None]
    b = np.ravel(response_sine).astype(float)[:, None]
    phi = np.asarray(firing_angle, dtype=float) - 2 * np.pi
    throws = np.asarray(throw, dtype=float)
    stations = int(round(station_count))
    cos_sum = np.zeros((k.shape[0], stations))
    sin_sum = np.zeros((k.shape[0], stations))
    for c in range(phi.size):
        column = int(throws[c])                           # station of throw t is t + 1
        cos_sum[:, column] += np.cos(k[:, 0] * phi[c])
        sin_sum[:, column] += np.sin(k[:, 0] * phi[c])
    return Complex(a * cos_sum - b * sin_sum, -(a * sin_sum + b * cos_sum))


def damper_dynamic_term(response_order, response_speed, damper_kind, damper_inertia,
                        damper_stiffness, damper_damping):
    """What the damper's ring adds to the hub's ω²·J_1: ω²J_d·z/(z − ω²J_d) with
    z = k_d + iωc_d (k_d = 0 for an untuned viscous damper; nothing without a damper)
    [N·m/rad]."""
    omega = np.ravel(response_order).astype(float) * np.ravel(response_speed).astype(float)
    kind = int(round(damper_kind))
    if kind == 0:
        zero = np.where(np.isfinite(omega), 0.0, np.nan)
        return Complex(zero, zero.copy())
    a = omega ** 2 * damper_inertia
    kd = damper_stiffness if kind == 2 else 0.0
    wc = omega * damper_damping
    den = (kd - a) ** 2 + wc ** 2
    with np.errstate(invalid="ignore", divide="ignore"):
        re = np.where(den == 0, 0.0, a * (kd * (kd - a) + wc ** 2) / den)
        im = np.where(den == 0, 0.0, -a ** 2 * wc / den)
    return Complex(re, im)


class Passes(NamedTuple):
    free_theta_re: np.ndarray
    free_theta_im: np.ndarray
    free_torque_re: np.ndarray
    free_torque_im: np.ndarray
    forced_theta_re: np.ndarray
    forced_theta_im: np.ndarray
    forced_torque_re: np.ndarray
    forced_torque_im: np.ndarray


def holzer_passes(response_order, response_speed, station_inertia, section_stiffness,
                  torsion_loss_factor, cylinder_damping, damper_re, damper_im,
                  response_cosine, response_sine, firing_angle, throw):
    """Both passes of the forced recurrence on every row, station by station as the
    sheet's columns run (:mod:`crankbook.calc.forced_torsion`): D_i = ω²J_i − iωc_i
    (+ the damper's term at the hub), T_i = T_(i−1) + D_i·θ_i (+ F_i),
    θ_(i+1) = θ_i − T_i/(k_i·(1 + iη))."""
    omega, d = _dynamic_stiffness(response_order, response_speed, station_inertia,
                                  cylinder_damping)
    stiffness = np.asarray(section_stiffness, dtype=float)
    n = d.shape[1]
    eta = torsion_loss_factor
    d[:, 0] += np.ravel(damper_re) + 1j * np.ravel(damper_im)
    excitation = station_excitation(response_order, response_cosine, response_sine,
                                    firing_angle, throw, n)
    force = excitation.re + 1j * excitation.im
    out = []
    for start, f in ((1.0, np.zeros_like(force)), (0.0, force)):
        out += _recurrence(d, stiffness, eta, start, f, omega)
    return Passes(*out)


def _dynamic_stiffness(response_order, response_speed, station_inertia, cylinder_damping):
    """ω as a (rows, 1) column and D_i = ω²J_i − iωc_i (rows, stations) without the
    damper."""
    omega = (np.ravel(response_order).astype(float)
             * np.ravel(response_speed).astype(float))[:, None]
    inertia = np.asarray(station_inertia, dtype=float)
    n = inertia.size
    ground = np.array([0.0] + [cylinder_damping] * (n - 2) + [0.0])
    return omega, omega ** 2 * inertia[None, :] - 1j * omega * ground[None, :]


def _recurrence(d, stiffness, eta, start, force, omega):
    """One pass: θ_1 = ``start``, T_i = T_(i−1) + D_i·θ_i + F_i,
    θ_(i+1) = θ_i − T_i/(k_i·(1 + iη)); [θ re, θ im, T re, T im], blank rows NaN."""
    n = d.shape[1]
    theta = np.zeros(d.shape, dtype=complex)
    torque = np.zeros(d.shape, dtype=complex)
    theta[:, 0] = start
    running = np.zeros(d.shape[0], dtype=complex)
    for i in range(n):
        running = running + d[:, i] * theta[:, i] + force[:, i]
        torque[:, i] = running
        if i < n - 1:
            theta[:, i + 1] = theta[:, i] - running / (stiffness[i] * (1 + 1j * eta))
    out = [theta.real, theta.imag, torque.real, torque.imag]
    blank = ~np.isfinite(omega[:, 0])
    for part in out:
        part[blank] = np.nan
    return out


class HubPass(NamedTuple):
    theta_re: np.ndarray
    theta_im: np.ndarray
    torque_re: np.ndarray
    torque_im: np.ndarray


def hub_pass(response_order, response_speed, station_inertia, section_stiffness,
             torsion_loss_factor, cylinder_damping, damper_kind):
    """Pass 3, only when there is a damper (blank without one): the hub held, θ_1 = 0,
    under a unit torque T_1 = 1 and no excitation.  The damper enters pass 1 only, as
    δ·θ_1 at the hub, so pass 1 without it is pass 1 − δ·pass 3: the same rows give
    the response without the damper beside the one with it."""
    omega, d = _dynamic_stiffness(response_order, response_speed, station_inertia,
                                  cylinder_damping)
    if int(round(damper_kind)) == 0:
        omega = np.full_like(omega, np.nan)
    unit = np.zeros_like(d)
    unit[:, 0] = 1.0
    return HubPass(*_recurrence(d, np.asarray(section_stiffness, dtype=float),
                                torsion_loss_factor, 0.0, unit, omega))


def _without_damper(free_re, free_im, hub_re, hub_im, damper_re, damper_im, damper_kind):
    """Pass 1's torques without the damper, T_free − δ·T_hub (complex)."""
    free = np.asarray(free_re) + 1j * np.asarray(free_im)
    if int(round(damper_kind)) == 0:
        return free
    delta = (np.ravel(damper_re) + 1j * np.ravel(damper_im))
    delta = delta.reshape((-1,) + (1,) * (free.ndim - 1))
    return free - delta * (np.asarray(hub_re) + 1j * np.asarray(hub_im))


def bare_residual(free_torque_re, free_torque_im, hub_torque_re, hub_torque_im, damper_re,
                  damper_im, damper_kind):
    """R_1 without the damper: the last station's torque of pass 1 − δ·pass 3 [N·m]."""
    r = _without_damper(np.asarray(free_torque_re)[:, -1], np.asarray(free_torque_im)[:, -1],
                        np.asarray(hub_torque_re)[:, -1], np.asarray(hub_torque_im)[:, -1],
                        damper_re, damper_im, damper_kind)
    return Complex(r.real, r.imag)


def bare_front(bare_residual_re, bare_residual_im, forced_torque_re, forced_torque_im,
               front_re, front_im, damper_kind):
    """θ_1 without the damper, −R_forced/R_1,bare (θ_1 itself when there is none) [rad]."""
    if int(round(damper_kind)) == 0:
        return Complex(np.ravel(front_re).astype(float), np.ravel(front_im).astype(float))
    free = np.ravel(bare_residual_re) + 1j * np.ravel(bare_residual_im)
    forced = np.asarray(forced_torque_re)[:, -1] + 1j * np.asarray(forced_torque_im)[:, -1]
    with np.errstate(invalid="ignore", divide="ignore"):
        theta = np.where(np.abs(free) == 0, np.nan, -forced / np.where(free == 0, 1, free))
    return Complex(theta.real, theta.imag)


def bare_section_torque(bare_front_re, bare_front_im, free_torque_re, free_torque_im,
                        hub_torque_re, hub_torque_im, damper_re, damper_im,
                        forced_torque_re, forced_torque_im, torsion_loss_factor,
                        damper_kind):
    """(rows, sections) each section's elastic torque amplitude without the damper,
    |θ_1,bare·(T_free − δ·T_hub) + T_forced|/√(1 + η²) [N·m]."""
    free = _without_damper(free_torque_re, free_torque_im, hub_torque_re, hub_torque_im,
                           damper_re, damper_im, damper_kind)
    theta = (np.ravel(bare_front_re) + 1j * np.ravel(bare_front_im))[:, None]
    torque = theta * free + np.asarray(forced_torque_re) + 1j * np.asarray(forced_torque_im)
    return np.abs(torque[:, :-1]) / np.sqrt(1 + torsion_loss_factor ** 2)


def front_response(free_torque_re, free_torque_im, forced_torque_re, forced_torque_im):
    """θ_1 = −R_forced/R_free, R the last station's torque of each pass [rad]."""
    free = np.asarray(free_torque_re)[:, -1] + 1j * np.asarray(free_torque_im)[:, -1]
    forced = np.asarray(forced_torque_re)[:, -1] + 1j * np.asarray(forced_torque_im)[:, -1]
    with np.errstate(invalid="ignore", divide="ignore"):
        theta = -forced / free
    return Complex(theta.real, theta.imag)


def front_amplitude_of(front_re, front_im):
    """|θ_1| [rad] (the sheet shows degrees)."""
    return np.hypot(np.ravel(front_re), np.ravel(front_im))


def response_section_torque(front_re, front_im, free_torque_re, free_torque_im,
                            forced_torque_re, forced_torque_im, torsion_loss_factor):
    """(rows, sections) elastic vibratory torque amplitude |k·Δθ| = |T|/√(1 + η²) of
    each section, T = θ_1·T_free + T_forced [N·m]."""
    theta = (np.ravel(front_re) + 1j * np.ravel(front_im))[:, None]
    torque = theta * (np.asarray(free_torque_re) + 1j * np.asarray(free_torque_im)) \
        + np.asarray(forced_torque_re) + 1j * np.asarray(forced_torque_im)
    return np.abs(torque[:, :-1]) / np.sqrt(1 + torsion_loss_factor ** 2)


def order_sum(values, sweep_speed):
    """(speeds, sections) the sum of each column over the 24 orders of each speed: the
    synthesis (blank where the speed is) [same unit]."""
    v = np.asarray(values, dtype=float)
    blocks = v.reshape(v.shape[0] // ORDER_COUNT, ORDER_COUNT, -1)
    sums = np.where(np.isfinite(blocks).any(axis=1), np.nansum(blocks, axis=1), np.nan)
    return _padded(sums, sweep_speed)


def order_sum_column(values, sweep_speed):
    """(speeds,) the sum of a per-row column over the 24 orders of each speed [same
    unit]."""
    return order_sum(np.ravel(values).astype(float)[:, None], sweep_speed)[:, 0]


def modes_without_rows(natural_frequency, sweep_candidate, sweep_speed_count):
    """Modes found (of the lowest three) beyond the critical-speed rows laid out."""
    found = min(CAMPBELL_MODES, int(np.sum(np.isfinite(np.asarray(natural_frequency, float)))))
    reserved = (np.size(sweep_candidate) - int(round(sweep_speed_count))) / ORDER_COUNT
    return float(max(0.0, found - reserved))


# ---------------------------------------------------------------- per speed
def _padded(block, sweep_speed):
    """(speeds, …): ``block``'s rows, then blank rows for the sweep's blank speeds."""
    speeds = np.size(sweep_speed)
    pad = np.full((speeds - block.shape[0],) + block.shape[1:], np.nan)
    return np.concatenate([block, pad])


def by_speed_and_order(values, sweep_speed):
    """A (rows,) column as (speeds, 24) [same unit]."""
    return _padded(np.asarray(values, dtype=float).reshape(-1, ORDER_COUNT), sweep_speed)


def front_amplitude_synthesis(front_amplitude):
    """Σ over the orders of the front amplitudes at each speed, blank where it has
    none [rad]."""
    a = np.asarray(front_amplitude, dtype=float)
    return np.where(np.isfinite(a).any(axis=1), np.nansum(a, axis=1), np.nan)


def section_stress(section_torque, main_journal_diameter, main_journal_bore):
    """τ = 16·T·d_o/(π·(d_o⁴ − d_b⁴)) of every section (the main journal) [Pa]."""
    return forced_torsion.section_shear_stress(section_torque, main_journal_diameter,
                                               main_journal_bore)


def rated_speed_used(rated_speed, operating_speed):
    """n_0: the typed rated speed, or 0 = the highest operating speed [rad/s]."""
    return sweep_bound(rated_speed, operating_speed, highest=True)


def m68_tensile_strength(shaft_tensile_strength, tensile_strength):
    """σ_B of M68's limit: typed, or 0 = the crankshaft material's, the one M53 reads
    (one material, one strength) [Pa]."""
    return shaft_tensile_strength if shaft_tensile_strength > 0 else tensile_strength


def stress_limit(sweep_speed, rated_speed_used, m68_tensile_strength, m68_ck,
                 main_journal_diameter):
    """IACS UR M68's τ_C at each sweep speed, λ = n/n_0 held at 1.05 above [Pa]."""
    speed = np.ravel(sweep_speed).astype(float)
    ratio = np.minimum(speed / rated_speed_used, 1.05)
    limit = forced_torsion.m68_continuous_limit(m68_tensile_strength, m68_ck,
                                                main_journal_diameter, ratio)
    return np.where(np.isfinite(speed), limit, np.nan)        # a blank row stays blank


def transient_limit(sweep_stress_limit, m68_ck):
    """τ_T = 1.7·τ_C/√C_K [Pa]."""
    return forced_torsion.m68_transient_limit(sweep_stress_limit, m68_ck)


def section_pass(section_stress, sweep_stress_limit):
    """1 where a section's stress is within τ_C at that speed, 0 where not, NaN blank."""
    s = np.asarray(section_stress, dtype=float)
    limit = np.ravel(sweep_stress_limit)[:, None]
    with np.errstate(invalid="ignore"):
        return np.where(np.isfinite(s), (s <= limit).astype(float), np.nan)


def failed_speed(sweep_speed, section_pass):
    """The speed of a row where some section fails, NaN where none does [rad/s]."""
    p = np.asarray(section_pass, dtype=float)
    fails = np.any(p == 0, axis=1)
    return np.where(fails, np.ravel(sweep_speed), np.nan)


def worst_section_order_torque(response_section_torque, worst_section, sweep_speed):
    """(speeds, 24) each order's elastic torque at the worst section [N·m]."""
    t = np.asarray(response_section_torque, dtype=float)
    if not np.isfinite(worst_section):
        return _padded(np.full((t.shape[0] // ORDER_COUNT, ORDER_COUNT), np.nan), sweep_speed)
    column = t[:, int(round(worst_section)) - 1]
    return _padded(column.reshape(-1, ORDER_COUNT), sweep_speed)


def row_max(values):
    """The largest value of each row, NaN where it holds none [same unit]."""
    v = np.asarray(values, dtype=float)
    filled = np.isfinite(v).any(axis=1)
    return np.where(filled, np.max(np.where(np.isfinite(v), v, -np.inf), axis=1), np.nan)


def peak_section_stress(values, main_journal_diameter, main_journal_bore):
    """The largest section's shear stress at each speed, from the section torques [Pa]."""
    return section_stress(row_max(values), main_journal_diameter, main_journal_bore)


# ---------------------------------------------------------------- per section
def _argmax_columns(v):
    """Each column's first largest row, or −1 where a column holds no number."""
    filled = np.where(np.isfinite(v), v, -np.inf)
    index = np.argmax(filled, axis=0)
    return np.where(np.isfinite(v).any(axis=0), index, -1)


def column_max(values):
    """The largest value of each column, NaN where it holds none [same unit]."""
    v = np.asarray(values, dtype=float)
    index = _argmax_columns(v)
    return np.array([v[i, c] if i >= 0 else np.nan for c, i in enumerate(index)])


def speed_of_column_max(values, sweep_speed):
    """The sweep speed of each column's largest value (the first, on a tie) [rad/s]."""
    index = _argmax_columns(np.asarray(values, dtype=float))
    return np.where(index >= 0, np.ravel(sweep_speed)[np.maximum(index, 0)], np.nan)


def nanmax_all(values):
    """The largest value of a block [same unit]."""
    v = np.asarray(values, dtype=float)
    return float(np.nanmax(v)) if np.isfinite(v).any() else np.nan


def first_max_item(values):
    """The 1-based item of the largest value (the first, on a tie)."""
    v = np.asarray(values, dtype=float)
    return float(np.nanargmax(v) + 1) if np.isfinite(v).any() else np.nan


def item_value(values, item):
    """Item ``item`` (1-based) of a per-item array [same unit]."""
    if not np.isfinite(item):
        return np.nan
    return float(np.asarray(values, dtype=float)[int(round(item)) - 1])


def all_pass(section_pass):
    """1 when no section fails at any sweep speed, else 0."""
    return float(not np.any(np.asarray(section_pass, dtype=float) == 0))


def barred_low(sweep_failed_speed):
    """The lowest failing speed, NaN when none fails [rad/s]."""
    s = np.asarray(sweep_failed_speed, dtype=float)
    return float(np.nanmin(s)) if np.isfinite(s).any() else np.nan


def barred_high(sweep_failed_speed):
    """The highest failing speed, NaN when none fails [rad/s]."""
    s = np.asarray(sweep_failed_speed, dtype=float)
    return float(np.nanmax(s)) if np.isfinite(s).any() else np.nan


# ---------------------------------------------------------------- Den Hartog's optima
def damper_optimum_damping(damper_kind, damper_inertia, natural_frequency, modal_inertia):
    """Den Hartog's optimum damping for mode 1 [N·m·s/rad]: c = 2·J_d·ω_n·ζ_opt with
    μ = J_d/J_m (J_m mode 1's inertia at the front, front amplitude 1), ζ_opt of the
    untuned viscous damper (kind 0 or 1) or of the tuned absorber (kind 2)."""
    wn = 2 * np.pi * float(np.ravel(natural_frequency)[0])
    mu = damper_inertia / float(np.ravel(modal_inertia)[0])
    ratio = forced_torsion.tuned_absorber_damping_ratio(mu) if round(damper_kind) == 2 \
        else forced_torsion.untuned_damper_optimum_ratio(mu)
    return 2 * damper_inertia * wn * float(ratio)


def damper_optimum_stiffness(damper_kind, damper_inertia, natural_frequency, modal_inertia):
    """The tuned absorber's optimum k_d = J_d·(ω_n/(1 + μ))² [N·m/rad]; 0 for a viscous
    damper (kind 0 or 1)."""
    if round(damper_kind) != 2:
        return 0.0
    wn = 2 * np.pi * float(np.ravel(natural_frequency)[0])
    mu = damper_inertia / float(np.ravel(modal_inertia)[0])
    return damper_inertia * (wn * float(forced_torsion.tuned_absorber_frequency_ratio(mu))) ** 2


def loss_factor(torsion_damping_ratio, shaft_loss_factor):
    """η = 2ζ + η_shaft on every shaft stiffness [-]."""
    return 2 * torsion_damping_ratio + shaft_loss_factor


def candidate_is_critical(sweep_candidate, sweep_speed_count):
    """1 on a candidate row that holds a critical speed, 0 on an even speed, NaN blank
    (the rows before the even speeds are the critical speeds')."""
    c = np.ravel(sweep_candidate).astype(float)
    flags = (np.arange(c.size) < c.size - int(round(sweep_speed_count))).astype(float)
    return np.where(np.isfinite(c), flags, np.nan)


def limit_at_column_max(values, limit):
    """Each column's τ_C at the speed of its largest value [Pa]."""
    index = _argmax_columns(np.asarray(values, dtype=float))
    return np.where(index >= 0, np.ravel(limit)[np.maximum(index, 0)], np.nan)
