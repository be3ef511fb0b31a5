"""Multi-cylinder engines: layout, engine torque, harmonics, free forces and moments.

Every cylinder has the geometry, masses and cylinder pressure of the single-cylinder
tables; cylinder i differs by its bank angle δ_i (its axis from the vertical,
positive in the sense of rotation), its firing angle φ_i (the crank angle α of its
firing TDC; cylinder 1's is 360°), its axial position z_i and its throw.  Its own
crank angle in the single-cylinder tables is α_i = α − φ_i + 360° (mod the cycle),
and the crank of its throw stands at θ_i = α − φ_i + δ_i from the vertical.

Engine frame (issue 11): y up, x horizontal in the direction the top of the crank
moves, z along the crankshaft from the front.  Free forces are the inertia forces the
moving masses put on the engine block (gas forces are internal and cancel).

Angles are in radians, lengths in metres, as everywhere in calc/.  A per-item
argument is an array of one value per cylinder (n,); a series per cylinder is (N, n).

References
----------
Thesis 000 §4.4.1 (cylinder pitch), §4.8.3; seed 004 (equivalent ring mass, compound
pendulum); any engine-dynamics text for the balance of multi-cylinder engines.
"""
from typing import NamedTuple

import numpy as np

SHAKING_ORDERS = (1.0, 2.0, 4.0, 6.0)
TORQUE_ORDERS = tuple(k / 2 for k in range(1, 25))          # 0.5, 1, …, 12
NEGLIGIBLE = 1e-6                 # × the first-order scale: an order counts as balanced
ORDER_NOISE = 1e-9                # × the series' peak |value|: a Fourier part below is 0
NONUNIFORMITY_FLOOR = 1e-6        # × the peak |torque|: a mean torque below it is zero


# ---------------------------------------------------------------- layout
def throw_count(throw):
    """Number of throws: the largest throw number."""
    return int(np.max(np.asarray(throw, dtype=float)))


def journal_count(throw):
    """Main journals: one more than the throws."""
    return throw_count(throw) + 1


def torque_order_count():
    """Orders 0.5, 1, …, 12 of the torque harmonics."""
    return len(TORQUE_ORDERS)


def shaking_order_count():
    """Orders 1, 2, 4 and 6 of the free forces and moments."""
    return len(SHAKING_ORDERS)


def cylinder_count(firing_angle):
    """Z, the number of cylinders (one firing angle each) [-]."""
    return float(np.size(firing_angle))


def engine_displacement(cylinder_count, bore, stroke):
    """V = Z·πD²/4·S [m³] (Heywood, Internal Combustion Engine Fundamentals, §2.2)."""
    return cylinder_count * np.pi / 4 * bore ** 2 * stroke


def engine_work(cylinder_count, indicated_work):
    """The engine's indicated work per cycle W = Z·∮p·dV [J]: every cylinder runs the
    same cycle, so one integration serves all (Heywood §2.4)."""
    return cylinder_count * indicated_work


def crank_angle_of_throw(firing_angle, bank_angle):
    """θ_i at α = 0: the crank of cylinder i from the vertical, in [0, 2π) [rad]."""
    return np.mod(np.asarray(bank_angle, dtype=float) - np.asarray(firing_angle, dtype=float),
                  2 * np.pi)


def firing_phase(firing_angle, cycle):
    """φ_i − φ_1 in [0, cycle): when cylinder i fires after cylinder 1 [rad]."""
    firing_angle = np.asarray(firing_angle, dtype=float)
    return np.mod(firing_angle - firing_angle[0], cycle)


def firing_order(firing_phase):
    """The cylinder (1-based) that fires k-th, for k = 1…n (ties: the first of them)."""
    phase = np.asarray(firing_phase, dtype=float)
    ordered = np.sort(phase)
    return np.array([float(np.flatnonzero(phase == value)[0] + 1) for value in ordered])


def firing_interval(firing_phase, cycle):
    """The crank angle from the k-th firing to the next [rad] (the last wraps round)."""
    ordered = np.sort(np.asarray(firing_phase, dtype=float))
    following = np.append(ordered[1:], cycle)
    return following - ordered


def cylinders_on_throw(throw):
    """For each cylinder, how many cylinders share its throw."""
    throw = np.asarray(throw, dtype=float)
    return np.array([float(np.sum(throw == t)) for t in throw])


def throw_crank_disagreement(throw, firing_angle, bank_angle):
    """1 for a cylinder whose throw carries a cylinder with another crank angle, else 0."""
    throw = np.asarray(throw, dtype=float)
    theta = np.asarray(bank_angle, dtype=float) - np.asarray(firing_angle, dtype=float)
    out = np.zeros(throw.size)
    for i in range(throw.size):
        same = throw == throw[i]
        difference = np.abs(np.mod(theta[same] - theta[i] + np.pi, 2 * np.pi) - np.pi)
        out[i] = float(np.any(difference > np.radians(1e-6)))
    return out


def firing_off_grid(firing_angle, crank_angle):
    """1 for a cylinder whose firing angle is not a whole number of grid steps, else 0."""
    grid = np.asarray(crank_angle, dtype=float).ravel()
    steps = np.asarray(firing_angle, dtype=float) / ((grid.max() - grid.min()) / (grid.size - 1))
    return np.where(np.abs(steps - np.round(steps)) > 1e-6, 1.0, 0.0)


def offset_with_several_cylinders(firing_angle, offset):
    """1 when a multi-cylinder layout has a pin offset (the layouts assume e = 0)."""
    return float(np.size(firing_angle) > 1 and offset != 0)


def axial_centre(axial_position):
    """z_c, midway between the outermost cylinders [m]."""
    z = np.asarray(axial_position, dtype=float)
    return (z.max() + z.min()) / 2


# ---------------------------------------------------------------- phase shift
def at_angle(series, crank_angle, angle, cycle):
    """``series`` of a periodic grid read at ``angle`` (any real angle): the nearest grid
    point of one period, as Excel's INDEX(…, MOD(INT((angle − start)/step + 0.5), N) + 1).

    Parameters
    ----------
    series : array_like, shape (N + 1,)
        Values on the grid ``crank_angle`` [rad], whose last point closes the cycle.
    angle : array_like
        Where to read [rad]; broadcasts (e.g. (N + 1, 1) − (n,) gives (N + 1, n)).
    cycle : float
        The period [rad].
    """
    grid = np.asarray(crank_angle, dtype=float).ravel()
    step = (grid[-1] - grid[0]) / (grid.size - 1)
    points = int(round(cycle / step))
    position = np.floor((np.asarray(angle, dtype=float) - grid[0]) / step + 0.5)
    index = np.mod(position, points).astype(int)
    return np.asarray(series, dtype=float).ravel()[index]


def cylinder_series(series, crank_angle, firing_angle, cycle):
    """A single-cylinder series at each cylinder's own crank angle α − φ_i + 360°
    (N + 1, n)."""
    alpha = np.asarray(crank_angle, dtype=float).reshape(-1, 1)
    return at_angle(series, crank_angle,
                    alpha - np.asarray(firing_angle, dtype=float) + 2 * np.pi, cycle)


def engine_sum(cylinder_values):
    """Σ over cylinders of a per-cylinder series (N + 1,)."""
    return np.asarray(cylinder_values, dtype=float).sum(axis=1)


def journal_torque(cylinder_torque, throw):
    """Torque carried by main journal j = 1…T+1: the throws ahead of it (j > throw)
    (N + 1, T + 1) [N·m]."""
    torque = np.asarray(cylinder_torque, dtype=float)
    throw = np.asarray(throw, dtype=float)
    journals = np.arange(1, journal_count(throw) + 1, dtype=float)
    ahead = (throw[None, :] < journals[:, None]).astype(float)          # (J, n)
    return torque @ ahead.T


def series_peak(values):
    """Largest |value| of each column [same unit]."""
    values = np.asarray(values, dtype=float)
    return np.abs(values).max(axis=0)


# ---------------------------------------------------------------- uniformity, flywheel
def nonuniformity(maximum, minimum, mean):
    """Torque non-uniformity (T_max − T_min)/T_mean [-]; NaN (a blank cell) where the mean
    torque is zero, i.e. |T_mean| ≤ NONUNIFORMITY_FLOOR·max(|T_max|, |T_min|): the ratio
    of a torque that averages to zero describes nothing."""
    if abs(mean) <= NONUNIFORMITY_FLOOR * max(abs(maximum), abs(minimum)):
        return float("nan")
    return (maximum - minimum) / mean


def energy_swing_series(torque, mean_torque, crank_angle):
    """ΔE(α) = ∫₀^α (T − T_mean) dα by the trapezoidal rule from 0 [J]."""
    torque = np.asarray(torque, dtype=float)
    alpha = np.asarray(crank_angle, dtype=float).ravel()
    steps = ((torque[1:] + torque[:-1]) / 2 - mean_torque) * np.diff(alpha)
    return np.concatenate([[0.0], np.cumsum(steps)])


def energy_swing(values):
    """ΔE_max = max ΔE − min ΔE [J]."""
    values = np.asarray(values, dtype=float)
    return values.max() - values.min()


def flywheel_inertia(energy_swing, speed_fluctuation, speed):
    """J = ΔE_max/(δ·ω²) [kg·m²]."""
    return energy_swing / (speed_fluctuation * speed ** 2)


# ---------------------------------------------------------------- Fourier orders
def torque_orders():
    """0.5, 1, …, 12 [-]."""
    return np.array(TORQUE_ORDERS)


def shaking_orders():
    """1, 2, 4, 6 [-]."""
    return np.array(SHAKING_ORDERS)


def order_amplitude(values, crank_angle, order, period):
    """Fourier amplitude √(a_k² + b_k²) of order k, a_k = (2/N)·Σ f_n·cos(k·α_n),
    b_k likewise with sin, over the N grid points with 0 ≤ α < ``period`` [unit of f].

    ``values`` is one series (N + 1,) or one per item (N + 1, n) (then one amplitude
    per item and order: (orders, n)).
    """
    alpha = np.asarray(crank_angle, dtype=float).ravel()
    inside = alpha < period - 1e-9
    f = np.asarray(values, dtype=float)[inside]
    k = np.asarray(order, dtype=float).reshape(-1, 1)
    phase = k * alpha[inside][None, :]                               # (orders, N)
    count = inside.sum()
    a = 2 / count * (np.cos(phase) @ f)
    b = 2 / count * (np.sin(phase) @ f)
    return np.sqrt(a ** 2 + b ** 2)


def _fourier_part(values, crank_angle, order, period, part):
    """(2/N)·Σ f_n·part(k·α_n) over the N grid points with 0 ≤ α < ``period``, set to 0
    where it is below the noise floor ORDER_NOISE·max|f| (one value per order)."""
    alpha = np.asarray(crank_angle, dtype=float).ravel()
    inside = alpha < period - 1e-9
    f = np.asarray(values, dtype=float).ravel()
    k = np.asarray(order, dtype=float).reshape(-1, 1)
    raw = 2 / inside.sum() * (part(k * alpha[inside][None, :]) @ f[inside])
    return np.where(np.abs(raw) <= ORDER_NOISE * np.max(np.abs(f)), 0.0, raw)


def order_cosine(values, crank_angle, order, period):
    """a_k = (2/N)·Σ f_n·cos(k·α_n) of each order k, so that f(α) ≈ f_mean + Σ a_k·cos(kα)
    + b_k·sin(kα); 0 below the noise floor ORDER_NOISE·max|f| [unit of f].

    Parameters
    ----------
    values : array_like, shape (N + 1,)
        One series on the periodic grid (its last point closes the cycle).
    crank_angle : array_like
        The grid [rad].
    order : array_like
        The orders k [-] (per revolution: k = 0.5 is once per four-stroke cycle).
    period : float
        The cycle [rad]; the grid points with α < period are summed.
    """
    return _fourier_part(values, crank_angle, order, period, np.cos)


def order_sine(values, crank_angle, order, period):
    """b_k = (2/N)·Σ f_n·sin(k·α_n) of each order k; 0 below the noise floor (see
    :func:`order_cosine`) [unit of f]."""
    return _fourier_part(values, crank_angle, order, period, np.sin)


def order_magnitude(cosine, sine):
    """A_k = √(a_k² + b_k²) [unit of a_k]."""
    return np.hypot(np.asarray(cosine, dtype=float), np.asarray(sine, dtype=float))


def order_phase(cosine, sine):
    """φ_k = atan2(b_k, a_k) in (−π, π], so that each term is A_k·cos(kα − φ_k); 0 for an
    order whose parts are both 0 [rad]."""
    return np.arctan2(np.asarray(sine, dtype=float) + 0.0, np.asarray(cosine, dtype=float))


# ---------------------------------------------------------------- free forces
def rotating_mass_share(rod_mass, small_end_mass, crank_unbalanced_mass, cylinders_on_throw):
    """Rotating mass assigned to cylinder i: its rod's big-end share m″ − m1 plus its
    part of the throw's unbalanced crank mass m_k/n_throw [kg]."""
    return rod_mass - small_end_mass + crank_unbalanced_mass / np.asarray(cylinders_on_throw)


def rotating_force_amplitude(rotating_mass_share, reciprocating_mass, counterweights,
                             balance_fraction, crank_radius, angular_velocity):
    """Net outward force along cylinder i's crank, rotating mass less its share of the
    counterweight: (m_r,i − c·(m_r,i + χ·m_j))·r·ω² [N] (c = 1 with counterweights)."""
    counter = counterweights * (np.asarray(rotating_mass_share) + balance_fraction
                                * reciprocating_mass)
    return (np.asarray(rotating_mass_share) - counter) * crank_radius * angular_velocity ** 2


def _cylinder_forces(reciprocating_mass, cylinder_acceleration, bank_angle,
                     rotating_force, crank_angle, firing_angle):
    """(F_x, F_y) of each cylinder on the block (N + 1, n) [N]."""
    alpha = np.asarray(crank_angle, dtype=float).reshape(-1, 1)
    delta = np.asarray(bank_angle, dtype=float)
    theta = alpha - np.asarray(firing_angle, dtype=float) + delta
    along = reciprocating_mass * np.asarray(cylinder_acceleration, dtype=float)
    rotating = np.asarray(rotating_force, dtype=float)
    fx = along * np.sin(delta) + rotating * np.sin(theta)
    fy = along * np.cos(delta) + rotating * np.cos(theta)
    return fx, fy


class Shaking(NamedTuple):
    """The engine's free forces [N] and moments about z_c [N·m] on the block."""
    force_x: np.ndarray
    force_y: np.ndarray
    moment_pitch: np.ndarray
    moment_yaw: np.ndarray


def shaking(reciprocating_mass, cylinder_acceleration, bank_angle, rotating_force,
            crank_angle, firing_angle, axial_position, axial_centre, scale):
    """Free forces and moments, a :class:`Shaking` of (N + 1,) series:

    F_x = Σ m_j·a_i·sinδ_i + F_rot,i·sinθ_i,  F_y = Σ m_j·a_i·cosδ_i + F_rot,i·cosθ_i,
    pitch = Σ (z_i − z_c)·F_y,i,  yaw = Σ (z_i − z_c)·F_x,i;

    each 0 where its size is at most 1e-9 of the first-order ``scale`` [N] (× 1 m for
    a moment): a balanced engine's sums cancel to rounding noise, which a chart would
    otherwise draw as a jagged line on an axis of 10⁻¹² N.
    """
    fx, fy = _cylinder_forces(reciprocating_mass, cylinder_acceleration, bank_angle,
                              rotating_force, crank_angle, firing_angle)
    arm = np.asarray(axial_position, dtype=float) - axial_centre

    def snapped(total):
        return np.where(np.abs(total) <= ORDER_NOISE * scale, 0.0, total)

    return Shaking(snapped(fx.sum(axis=1)), snapped(fy.sum(axis=1)),
                   snapped((fy * arm).sum(axis=1)), snapped((fx * arm).sum(axis=1)))


def classic_order_amplitude(order, reciprocating_mass, crank_radius, angular_velocity,
                            crank_rod_ratio, bank_angle, firing_angle, rotating_force,
                            axial_position, axial_centre, component, moment):
    """The textbook amplitude of a free force or moment of order 1 or 2 with the series
    kinematics a = rω²(cos α + λ·cos 2α): C = m_j·r·ω²,
    order 1: |Σ w_i·(C·e^{i(θ_i − δ_i)} + F_rot,i/… )|, order 2: λ·C·|Σ w_i·e^{2i(θ_i − δ_i)}|,
    with w_i = cos δ_i (y) or sin δ_i (x), times (z_i − z_c) for a moment; 0 for other
    orders (the series has none) [N or N·m].

    ``component`` is 0 for x and 1 for y; ``moment`` 1 for the moment about it.
    """
    order = np.asarray(order, dtype=float).reshape(-1, 1)
    delta = np.asarray(bank_angle, dtype=float)
    theta0 = -np.asarray(firing_angle, dtype=float) + delta                 # θ_i at α = 0
    scale = reciprocating_mass * crank_radius * angular_velocity ** 2
    weight = np.cos(delta) if component == 1 else np.sin(delta)
    arm = np.asarray(axial_position, dtype=float) - axial_centre if moment else 1.0
    coefficient = np.where(order == 1, scale, np.where(order == 2, crank_rod_ratio * scale, 0.0))
    recip = (coefficient * weight * arm * np.exp(1j * order * (theta0 - delta))).sum(axis=1)
    # the rotating force along the crank: its y part is cos θ, its x part sin θ = cos(θ − 90°)
    lag = 0.0 if component == 1 else np.pi / 2
    rotating = np.where(order[:, 0] == 1, (np.asarray(rotating_force) * arm
                                           * np.exp(1j * (theta0 - lag))).sum(), 0.0)
    return np.abs(recip + rotating)


def unbalanced(amplitude_x, amplitude_y, scale):
    """1 where an order leaves a free force or moment (|·| > 1e-6 of the first-order
    scale), else 0."""
    return np.where(np.hypot(amplitude_x, amplitude_y) > NEGLIGIBLE * scale, 1.0, 0.0)


def above_noise(value, scale, arm=1.0):
    """``value``, or 0 where it is at most the noise floor 1e-6·scale·arm: a balanced
    order shows as 0, not as rounding noise [unit of value].

    Parameters
    ----------
    value : array_like
        Amplitudes of one order each [N or N·m].
    scale : float
        One cylinder's first-order force (m_j + m_r)·r·ω² [N].
    arm : float
        A length that makes the floor a moment [m]: the crank radius (1 for forces).
    """
    value = np.asarray(value, dtype=float)
    return np.where(value <= NEGLIGIBLE * scale * arm, 0.0, value)


def first_order_scale(reciprocating_mass, rotating_mass, crank_radius, angular_velocity):
    """(m_j + m_r)·r·ω²: the size a free first-order force of one cylinder would have [N]."""
    return (reciprocating_mass + rotating_mass) * crank_radius * angular_velocity ** 2


# ---------------------------------------------------------------- ring mass (seed 004)
def big_end_mass(rod_mass, small_end_mass):
    """The rod's big-end share m2 = m″ − m1 [kg] (it rotates with the crank pin)."""
    return rod_mass - small_end_mass


def ring_mass_per_rod(reciprocating_mass, big_end_mass, crank_rod_ratio):
    """Bob weight for one rod on a balancing machine, M = m2 + m1·(1/2 + λ²/8) [kg]:
    the mass on the crank-pin radius whose kinetic energy equals the piston and rod's
    mean kinetic energy over a revolution (seed 004 §2, eqs. 1–4, series velocity)."""
    return big_end_mass + reciprocating_mass * (0.5 + crank_rod_ratio ** 2 / 8)


def throw_rods(throw):
    """Rods on each throw t = 1…T."""
    throw = np.asarray(throw, dtype=float)
    return np.array([float(np.sum(throw == t)) for t in range(1, throw_count(throw) + 1)])


def ring_mass(ring_mass_per_rod, throw_rods):
    """Bob weight per throw: the sum over its rods [kg]."""
    return ring_mass_per_rod * np.asarray(throw_rods, dtype=float)


def ring_mass_numeric(reciprocating_mass, big_end_mass, crank_rod_ratio, samples=36000):
    """The same bob weight from a numerical mean of the kinetic energy over a revolution
    with seed 004's series velocity v1 = Rω(sin α + λ/2·sin 2α): an independent check."""
    alpha = np.linspace(0, 2 * np.pi, samples, endpoint=False)
    v1 = np.sin(alpha) + crank_rod_ratio / 2 * np.sin(2 * alpha)          # per Rω
    return big_end_mass + reciprocating_mass * np.mean(v1 ** 2)


def rod_cg_from_small_end(rod_length, rate_small_end, rate_big_end, gravity):
    """Rod centre of gravity from the small-end centre by the compound pendulum [m].

    The rod swings about its small-end centre at the rate f1 and about its big-end
    centre at f2 (swings per second; the sheet takes them per minute).  With
    T = 1/f = 2π√(I/(m·g·h)) and I = I_c + m·h² about each pivot, h1 + h2 = l, the
    two equations give h1 = l·(G/f2² − l)/(G·(1/f1² + 1/f2²) − 2l), G = g/(4π²)
    (seed 004 eq. 5, derived again: the extracted text is garbled).

    Parameters
    ----------
    rod_length : float
        l, centre to centre [m].
    rate_small_end, rate_big_end : float
        f1, f2: small swings per second about each centre [1/s].
    gravity : float
        g [m/s²].
    """
    G = gravity / (4 * np.pi ** 2)
    return rod_length * (G / rate_big_end ** 2 - rod_length) / \
        (G * (1 / rate_small_end ** 2 + 1 / rate_big_end ** 2) - 2 * rod_length)


def pendulum_rate(pivot_to_cg, radius_of_gyration, gravity):
    """Small swings per second of a compound pendulum [1/s] (to build test rods)."""
    return np.sqrt(gravity * pivot_to_cg / (radius_of_gyration ** 2 + pivot_to_cg ** 2)) \
        / (2 * np.pi)
