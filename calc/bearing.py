"""The oil film of the big-end and main bearings: steady design numbers and the
dynamically loaded journal's orbit by the mobility method.

* **Steady numbers.**  Specific load p = F/(L·D) (the mean and the largest load of the
  cycle), PV with the journal's sliding speed ω·D/2, the Sommerfeld number
  S = (R/c)²·μ·N/p at the mean load (N in rev/s), and Petroff's friction coefficient
  f = 2π²·(R/c)·μ·N/p.  The steady eccentricity at the mean load is the short
  (Ocvirk) bearing's, S·(L/D)² = (1 − ε²)²/(π·ε·√(π²·(1 − ε²) + 16·ε²)), solved for ε
  by bisection; h₀ = c·(1 − ε).  The short-bearing theory carries more load than a
  finite bearing of the same L/D, so h₀ is optimistic above L/D ≈ ½.  The finite
  bearing's h₀/c and friction variable (R/c)·f at the mean load come from Raimondi and
  Boyd's tables for L/D = ∞, 1, ½, ¼, each read linearly in log₁₀ S (the charts'
  scale) and held at the tables' ends, blended for the bearing's L/D by their cubic
  interpolation formula.
* **The orbit.**  Booker's mobility method: the film's reaction to the load F is the
  journal's squeeze velocity relative to a frame turning at the mean angular velocity
  ω̄ = (ω_journal + ω_bush)/2,

      dε⃗/dt = F·(c/R)²/(μ·L·D) · M⃗(ε⃗, F̂) + ω̄ × ε⃗,

  with M⃗ = M_ζ·F̂ + M_κ·F̂⊥ (F̂⊥ = F̂ turned 90° in the sense of rotation), ζ and κ the
  eccentricity ratio's components along F̂ and F̂⊥.  M is Goenka's fit of the short
  bearing's mobility, M_ζ = (1 − ζ)^2.5/(π·(L/D)²), M_κ = −4κ·(1 − ζ)^1.5/(π²·(L/D)²):
  a short-bearing result, optimistic at high eccentricity.  The big end is solved in
  the rod's frame, where the bush is still: ω̄ = (ω − ω_rod)/2 with ω_rod the rod's
  own angular velocity in the crank's sense of rotation (= −dβ/dt), that is
  (ω + dβ/dt)/2 — not ω/2, which puts the film some 40 % off.  A main bearing's bush
  is the engine's: ω̄ = ω/2.  The eccentricity is carried from one 1° row to the next
  by Heun's step (one predictor and one corrector evaluation of the mobility), over
  two cycles from the centre; the first cycle is the start transient and the results
  are read from the second.  A step that would reach ε ≥ 0.995 is scaled back to it
  and the row is flagged: the film has broken down there.
* **Friction.**  The Couette shear of a full film at the eccentricity ε,
  P = 2π·μ·R³·L·Δω²/(c·√(1 − ε²)), Δω the journal's speed relative to the bush
  (Petroff's torque for ε = 0); the load's own moment is not added.
* **The film's peak pressure.**  The short bearing's mid-plane pressure (Reynolds'
  equation without the circumferential flow, half-Sommerfeld: none below zero),
  p = 3μL²/(2c²)·(A cos ψ + B sin ψ)/(1 − ε cos ψ)³, ψ from the thinnest film, with
  the squeeze A = dε/dt and the whirl B = ε(dφ/dt − ω̄); its largest value over ψ by
  a start on the pressure lobe's side and five Newton steps, row by row.

Units SI at the interface (m, N, Pa·s, rad/s, s); ε⃗ as fractions of c.

References
----------
J. F. Booker, "Dynamically loaded journal bearings: mobility method of solution",
*Trans. ASME, J. Basic Eng.* 87 (1965) 537–546.
P. K. Goenka, "Analytical curve fits for solution parameters of dynamically loaded
journal bearings", *Trans. ASME, J. Tribology* 106 (1984) 421–428 (the short-bearing
mobility M_ζ, M_κ above).
F. W. Ocvirk, "Short-bearing approximation for full journal bearings", NACA TN 2808
(1952); B. J. Hamrock, S. R. Schmid, B. O. Jacobson, *Fundamentals of Fluid Film
Lubrication*, 2nd ed. (2004), ch. 12 (the short bearing's load and attitude).
B. Yu, J. T. Sawicki, "Comparison of mobility method and mass conservation method in
a study of dynamically loaded journal bearings", *Int. J. Rotating Machinery* 8 (2002)
71–79 (the mobility method overestimates the minimum film: optimistic).
A. A. Raimondi, J. Boyd, "A solution for the finite journal bearing and its
application to analysis and design", parts I–III, *ASLE Trans.* 1 (1958) 159–209 (the
full bearing's design tables).
R. G. Budynas, J. K. Nisbett, *Shigley's Mechanical Engineering Design*, 9th ed.,
ch. 12: eq. (12-6) Petroff's friction, (12-7) the Sommerfeld number, (12-16) Raimondi
and Boyd's interpolation for any L/D, Examples 12-1 and 12-2, Table 12-5 the
unit loads in use (automotive engines: main 4–5 MPa, crankpin 10–15 MPa; diesel
engines: main 6–12 MPa, crankpin 8–15 MPa).
"""
from typing import NamedTuple

import numpy as np

ECCENTRICITY_LIMIT = 0.995      # the clamp; the template's constant holds the same


# ---------------------------------------------------------------- the bearings
def bearing_count(throw):
    """Two bearings are checked: the big end and one main bearing."""
    return 2


def bearing_diameter(crankpin_diameter, main_journal_diameter):
    """D of each bearing (big end, main) [m]."""
    return np.array([crankpin_diameter, main_journal_diameter], dtype=float)


def bearing_length(crankpin_length, main_journal_length, oil_groove_width):
    """Bearing length L less a circumferential groove's width (big end, main) [m]."""
    return np.array([crankpin_length, main_journal_length], dtype=float) - oil_groove_width


def length_ratio(bearing_length, bearing_diameter):
    """L/D [-]."""
    return bearing_length / bearing_diameter


def checked_journal(check_bearing, journal_load_mean):
    """The main bearing analysed: the one typed, else (0) the most loaded by mean
    load, the first within 1e-9 of the largest (a single throw's two journals carry
    the same load up to rounding, which differs between engines) [-]."""
    if check_bearing > 0:
        return float(check_bearing)
    means = np.asarray(journal_load_mean, dtype=float)
    return float(np.argmax(means >= means.max() * (1 - 1e-9)) + 1)


# ---------------------------------------------------------------- loads
def big_end_load(tangential_force, radial_force, big_end_mass, crank_radius,
                 angular_velocity, crank_angle_from_axis, rod_angle):
    """The crank pin's load on the big-end bush in the rod's frame: u along the rod
    toward the piston, v a quarter-turn on in the crank's sense of rotation (N,) twice
    [N].  The pin load (tangential P_t in the sense of rotation, radial P_r toward the
    crank centre, the big end's centrifugal force included) acts on the pin; the bush
    feels it reversed: F_u = P_t·sin(ψ + β) + P_r·cos(ψ + β),
    F_v = −P_t·cos(ψ + β) + P_r·sin(ψ + β) — the rod force itself on the u axis."""
    pt = np.asarray(tangential_force, dtype=float)
    pr = np.asarray(radial_force, dtype=float) - big_end_mass * crank_radius * angular_velocity ** 2
    a = np.asarray(crank_angle_from_axis, dtype=float) + np.asarray(rod_angle, dtype=float)
    return pt * np.sin(a) + pr * np.cos(a), -pt * np.cos(a) + pr * np.sin(a)


class BearingLoad(NamedTuple):
    """Each bearing's load in its bush's frame, u and v (N + 1, 2) [N]."""
    u: np.ndarray
    v: np.ndarray


def bearing_loads(tangential_force, radial_force, big_end_mass, crank_radius,
                  angular_velocity, crank_angle_from_axis, rod_angle, journal_load_x,
                  journal_load_y, checked_journal):
    """The big end's load in the rod's frame and the checked main bearing's in the
    engine's, turned so that the crank's rotation is positive: u = the vertical
    component, v = the horizontal one (the crank turns from +y to +x) [N]."""
    bu, bv = big_end_load(tangential_force, radial_force, big_end_mass, crank_radius,
                          angular_velocity, crank_angle_from_axis, rod_angle)
    j = int(checked_journal) - 1
    mu = np.asarray(journal_load_y, dtype=float)[:, j]
    mv = np.asarray(journal_load_x, dtype=float)[:, j]
    return BearingLoad(np.column_stack([np.ravel(bu), mu]), np.column_stack([np.ravel(bv), mv]))


def mean_angular_velocity(angular_velocity, rod_angular_velocity):
    """ω̄ in each bush's frame: (ω + dβ/dt)/2 for the big end, ω/2 for a main bearing
    (N + 1, 2) [rad/s]."""
    rod = np.ravel(np.asarray(rod_angular_velocity, dtype=float))
    return np.column_stack([(angular_velocity + rod) / 2, np.full_like(rod, angular_velocity / 2)])


# ---------------------------------------------------------------- steady numbers
def specific_load(load, bearing_length, bearing_diameter):
    """p = F/(L·D) [Pa]."""
    return load / (bearing_length * bearing_diameter)


def sliding_velocity(angular_velocity, bearing_diameter):
    """The journal's surface speed relative to its bush, ω·D/2 [m/s] (a big end's
    bush swings with the rod, which averages out over the cycle)."""
    return angular_velocity * bearing_diameter / 2


def pv(bearing_specific_load_mean, bearing_sliding_velocity):
    """PV at the mean load [Pa·m/s]."""
    return bearing_specific_load_mean * bearing_sliding_velocity


def sommerfeld(bearing_diameter, bearing_clearance, film_viscosity, angular_velocity,
               bearing_specific_load_mean):
    """S = (R/c)²·μ·N/p, N in rev/s (Shigley eq. 12-7) [-]."""
    radius_ratio = bearing_diameter / 2 / bearing_clearance
    return radius_ratio ** 2 * film_viscosity * angular_velocity / (2 * np.pi) \
        / bearing_specific_load_mean


def petroff_friction(bearing_diameter, bearing_clearance, film_viscosity, angular_velocity,
                     bearing_specific_load_mean):
    """Petroff's friction coefficient f = 2π²·(R/c)·μ·N/p (Shigley eq. 12-6) [-]."""
    return 2 * np.pi ** 2 * (bearing_diameter / 2 / bearing_clearance) * film_viscosity \
        * angular_velocity / (2 * np.pi) / bearing_specific_load_mean


def short_bearing_sommerfeld(eccentricity_ratio, length_ratio):
    """The short (Ocvirk) bearing's Sommerfeld number at the eccentricity ratio ε:
    S = (1 − ε²)²/(π·ε·√(π²·(1 − ε²) + 16·ε²)·(L/D)²) [-]."""
    e = np.asarray(eccentricity_ratio, dtype=float)
    return (1 - e ** 2) ** 2 / (np.pi * e * np.sqrt(np.pi ** 2 * (1 - e ** 2) + 16 * e ** 2)
                                * length_ratio ** 2)


class Bisection(NamedTuple):
    """The steady solve's rows: bracket, midpoint and the short bearing's S there
    (steps + 1, 2)."""
    low: np.ndarray
    high: np.ndarray
    mid: np.ndarray
    value: np.ndarray


def steady_bisection(steady_step, sommerfeld, bearing_length_ratio):
    """Bisection of S_short(ε) = S on 0 < ε < 1, one row per halving: row 0 is the
    bracket (0, 1); row k keeps the half of row k − 1's bracket that holds the root
    (S_short falls as ε grows)."""
    rows = len(np.ravel(steady_step))
    s = np.broadcast_to(np.asarray(sommerfeld, dtype=float), (2,)).astype(float)
    low = np.zeros((rows, 2))
    high = np.ones((rows, 2))
    mid = np.empty((rows, 2))
    value = np.empty((rows, 2))
    for k in range(rows):
        if k:
            above = value[k - 1] > s
            low[k] = np.where(above, mid[k - 1], low[k - 1])
            high[k] = np.where(above, high[k - 1], mid[k - 1])
        mid[k] = (low[k] + high[k]) / 2
        value[k] = short_bearing_sommerfeld(mid[k], bearing_length_ratio)
    return Bisection(low, high, mid, value)


def steady_eccentricity(steady_step, sommerfeld, bearing_length_ratio):
    """ε at the mean load: the last row's midpoint [-]."""
    return steady_bisection(steady_step, sommerfeld, bearing_length_ratio).mid[-1]


# Raimondi and Boyd's finite journal bearing, full (360°) bush, Reynolds' film rupture:
# (h₀/c, S, (R/c)·f) for L/D = ∞, 1, ½, ¼, each in the order of rising S.  The L/D = ∞
# table has no h₀/c = 0.03 row.  Raimondi & Boyd (1958), Part III, the design tables.
RAIMONDI_BOYD = (
    ("∞", ((0.1, 0.0115, 0.756), (0.2, 0.021, 0.961), (0.4, 0.0389, 1.20),
           (0.6, 0.0626, 1.52), (0.8, 0.123, 2.57), (0.9, 0.240, 4.80))),
    ("1", ((0.03, 0.00474, 0.514), (0.1, 0.0188, 1.05), (0.2, 0.0446, 1.70),
           (0.4, 0.121, 3.22), (0.6, 0.264, 5.79), (0.8, 0.631, 12.8), (0.9, 1.33, 26.4))),
    ("1/2", ((0.03, 0.00609, 0.610), (0.1, 0.0313, 1.60), (0.2, 0.0923, 3.26),
             (0.4, 0.319, 8.10), (0.6, 0.779, 17.0), (0.8, 2.03, 40.9), (0.9, 4.31, 85.6))),
    ("1/4", ((0.03, 0.0101, 0.922), (0.1, 0.0736, 3.50), (0.2, 0.261, 8.80),
             (0.4, 1.07, 26.7), (0.6, 2.83, 61.1), (0.8, 7.57, 153.0), (0.9, 16.2, 322.0))),
)
_RB_ROWS = np.array([(t + 1, *row) for t, (_, rows) in enumerate(RAIMONDI_BOYD)
                     for row in rows])          # table number, h₀/c, S, (R/c)·f


def raimondi_boyd_rows():
    """The number of rows of the stacked tables [-]."""
    return len(_RB_ROWS)


def _rb_column(rb_row, column):
    return _RB_ROWS[np.asarray(rb_row, dtype=int) - 1, column]


def rb_table(rb_row):
    """The table a row belongs to: 1 = L/D ∞, 2 = 1, 3 = ½, 4 = ¼ [-]."""
    return _rb_column(rb_row, 0)


def rb_film_ratio(rb_row):
    """h₀/c of a row [-]."""
    return _rb_column(rb_row, 1)


def rb_sommerfeld(rb_row):
    """S of a row [-]."""
    return _rb_column(rb_row, 2)


def rb_log_sommerfeld(rb_row):
    """log₁₀ S of a row, the charts' abscissa [-]."""
    return np.log10(_rb_column(rb_row, 2))


def rb_friction_variable(rb_row):
    """(R/c)·f of a row [-]."""
    return _rb_column(rb_row, 3)


def rb_row(sommerfeld, table):
    """The row (of the stacked tables, from 1) below S in a table: the lower end of
    the interval that holds log₁₀ S, the first or the last interval beyond the
    table's ends [-]."""
    x = np.log10(np.asarray(sommerfeld, dtype=float))
    rows = _RB_ROWS[_RB_ROWS[:, 0] == table]
    start = np.count_nonzero(_RB_ROWS[:, 0] < table)
    below = np.sum(np.log10(rows[:, 2])[None, :] <= np.ravel(x)[:, None], axis=1)
    return (start + np.clip(below, 1, len(rows) - 1)).reshape(np.shape(x)).astype(float)


def rb_fraction(sommerfeld, table):
    """Where log₁₀ S lies between its row and the next, 0 … 1 (held at the table's
    ends: the charts stop there) [-]."""
    x = np.log10(np.asarray(sommerfeld, dtype=float))
    i = rb_row(sommerfeld, table).astype(int) - 1
    low, high = np.log10(_RB_ROWS[i, 2]), np.log10(_RB_ROWS[i + 1, 2])
    return np.clip((x - low) / (high - low), 0.0, 1.0)


def rb_film_in_table(row, fraction):
    """h₀/c interpolated linearly in log₁₀ S in one table [-]."""
    i = np.asarray(row, dtype=int) - 1
    return _RB_ROWS[i, 1] + fraction * (_RB_ROWS[i + 1, 1] - _RB_ROWS[i, 1])


def rb_friction_in_table(row, fraction):
    """(R/c)·f interpolated linearly in log₁₀ S in one table [-]."""
    i = np.asarray(row, dtype=int) - 1
    return _RB_ROWS[i, 3] + fraction * (_RB_ROWS[i + 1, 3] - _RB_ROWS[i, 3])


def raimondi_boyd_blend(bearing_length_ratio, long, one, half, quarter):
    """Raimondi and Boyd's interpolation between the tables for any L/D (Shigley
    eq. 12-16): y = (1/(L/D)³)·[−⅛(1 − L/D)(1 − 2L/D)(1 − 4L/D)·y∞
    + ⅓(1 − 2L/D)(1 − 4L/D)·y₁ − ¼(1 − L/D)(1 − 4L/D)·y½ + 1/24·(1 − L/D)(1 − 2L/D)·y¼];
    each table itself at its own L/D [-]."""
    r = np.asarray(bearing_length_ratio, dtype=float)
    return (-(1 - r) * (1 - 2 * r) * (1 - 4 * r) * long / 8
            + (1 - 2 * r) * (1 - 4 * r) * one / 3
            - (1 - r) * (1 - 4 * r) * half / 4
            + (1 - r) * (1 - 2 * r) * quarter / 24) / r ** 3


def rb_friction_coefficient(rb_friction_ratio, bearing_diameter, bearing_clearance):
    """f = ((R/c)·f)/(R/c) [-]."""
    return rb_friction_ratio * bearing_clearance / (bearing_diameter / 2)


def rb_beyond(sommerfeld, bearing_length_ratio):
    """1 where the blend reads beyond the charts: L/D below ¼, or S outside the long
    bearing's table (0.0115 … 0.240), the narrowest, which the blend reads for every
    L/D but 1, ½ and ¼ [-]."""
    long = _RB_ROWS[_RB_ROWS[:, 0] == 1, 2]
    s = np.asarray(sommerfeld, dtype=float)
    return np.where((np.asarray(bearing_length_ratio) < 0.25) | (s < long[0]) | (s > long[-1]),
                    1.0, 0.0)


def film_from_ratio(film_ratio, bearing_clearance):
    """h₀ = c·(h₀/c) [m]."""
    return bearing_clearance * film_ratio


def film_from_eccentricity(eccentricity_ratio, bearing_clearance):
    """h = c·(1 − ε) [m]."""
    return bearing_clearance * (1 - eccentricity_ratio)


# ---------------------------------------------------------------- the orbit
def mobility_scale(bearing_diameter, bearing_length, bearing_clearance, film_viscosity):
    """(c/R)²/(μ·L·D): the squeeze rate per newton [1/(N·s)]."""
    return (2 * bearing_clearance / bearing_diameter) ** 2 \
        / (film_viscosity * bearing_length * bearing_diameter)


def time_step(orbit_step, angular_velocity):
    """The time one orbit row spans, Δα/ω [s]."""
    return orbit_step / angular_velocity


def short_bearing_mobility(zeta, kappa, length_ratio):
    """Goenka's short-bearing mobility (M_ζ, M_κ) [-]."""
    return ((1 - zeta) ** 2.5 / (np.pi * length_ratio ** 2),
            -4 * kappa * (1 - zeta) ** 1.5 / (np.pi ** 2 * length_ratio ** 2))


def load_components(x, y, load_u, load_v):
    """ζ and κ: the eccentricity ratio along the load and a quarter-turn on [-]."""
    load = np.maximum(np.hypot(load_u, load_v), 1e-9)
    return (x * load_u + y * load_v) / load, (y * load_u - x * load_v) / load


def eccentricity_rate(x, y, load_u, load_v, mean_velocity, scale, length_ratio):
    """dε⃗/dt (d(e_x/c)/dt, d(e_y/c)/dt) [1/s]."""
    zeta, kappa = load_components(x, y, load_u, load_v)
    m_zeta, m_kappa = short_bearing_mobility(zeta, kappa, length_ratio)
    return (scale * (m_zeta * load_u - m_kappa * load_v) - mean_velocity * y,
            scale * (m_zeta * load_v + m_kappa * load_u) + mean_velocity * x)


def clamp_scale(x, y, limit=ECCENTRICITY_LIMIT):
    """1, or the factor that brings |ε⃗| back to the limit [-]."""
    return np.minimum(1.0, limit / np.maximum(np.hypot(x, y), 1e-12))


class Orbit(NamedTuple):
    """The orbit's columns, one row per orbit angle, one column per bearing."""
    predictor_scale: np.ndarray
    predictor_x: np.ndarray
    predictor_y: np.ndarray
    predictor_zeta: np.ndarray
    predictor_kappa: np.ndarray
    predictor_rate_x: np.ndarray
    predictor_rate_y: np.ndarray
    scale: np.ndarray
    x: np.ndarray
    y: np.ndarray
    zeta: np.ndarray
    kappa: np.ndarray
    rate_x: np.ndarray
    rate_y: np.ndarray


def journal_orbit(orbit_load_u, orbit_load_v, orbit_mean_velocity, orbit_time_step,
                  bearing_mobility_scale, bearing_length_ratio,
                  limit=ECCENTRICITY_LIMIT):
    """Heun's step row by row from the centre: predictor ε⃗* = ε⃗ₖ₋₁ + h·ṙₖ₋₁ (scaled
    back to the limit), corrector ε⃗ₖ = ε⃗ₖ₋₁ + h/2·(ṙₖ₋₁ + ṙ(ε⃗*, Fₖ)) (likewise), and
    ṙₖ = ṙ(ε⃗ₖ, Fₖ) for the next row."""
    fu = np.asarray(orbit_load_u, dtype=float)
    fv = np.asarray(orbit_load_v, dtype=float)
    w = np.broadcast_to(np.asarray(orbit_mean_velocity, dtype=float), fu.shape)
    h = np.asarray(orbit_time_step, dtype=float)
    s = np.asarray(bearing_mobility_scale, dtype=float)
    ld = np.asarray(bearing_length_ratio, dtype=float)
    cols = {name: np.zeros(fu.shape) for name in Orbit._fields}
    cols["predictor_scale"][0] = cols["scale"][0] = 1.0
    for k in range(fu.shape[0]):
        c = {name: col[k] for name, col in cols.items()}
        if k:
            px = cols["x"][k - 1] + h * cols["rate_x"][k - 1]
            py = cols["y"][k - 1] + h * cols["rate_y"][k - 1]
            c["predictor_scale"][:] = clamp_scale(px, py, limit)
            c["predictor_x"][:] = px * c["predictor_scale"]
            c["predictor_y"][:] = py * c["predictor_scale"]
        zeta, kappa = load_components(c["predictor_x"], c["predictor_y"], fu[k], fv[k])
        c["predictor_zeta"][:], c["predictor_kappa"][:] = zeta, kappa
        c["predictor_rate_x"][:], c["predictor_rate_y"][:] = eccentricity_rate(
            c["predictor_x"], c["predictor_y"], fu[k], fv[k], w[k], s, ld)
        if k:
            x = cols["x"][k - 1] + h / 2 * (cols["rate_x"][k - 1] + c["predictor_rate_x"])
            y = cols["y"][k - 1] + h / 2 * (cols["rate_y"][k - 1] + c["predictor_rate_y"])
            c["scale"][:] = clamp_scale(x, y, limit)
            c["x"][:] = x * c["scale"]
            c["y"][:] = y * c["scale"]
        zeta, kappa = load_components(c["x"], c["y"], fu[k], fv[k])
        c["zeta"][:], c["kappa"][:] = zeta, kappa
        c["rate_x"][:], c["rate_y"][:] = eccentricity_rate(
            c["x"], c["y"], fu[k], fv[k], w[k], s, ld)
    return Orbit(**cols)


def clamped(orbit_predictor_scale, orbit_scale):
    """1 on a row whose step was scaled back to the eccentricity limit [-]."""
    return np.where((orbit_predictor_scale < 1) | (orbit_scale < 1), 1.0, 0.0)


def film_thickness(orbit_eccentricity_x, orbit_eccentricity_y, bearing_clearance):
    """h_min = c·(1 − |ε⃗|) on each row [m]."""
    return bearing_clearance * (1 - np.hypot(orbit_eccentricity_x, orbit_eccentricity_y))


def friction_power(orbit_eccentricity_x, orbit_eccentricity_y, orbit_mean_velocity,
                   bearing_diameter, bearing_length, bearing_clearance, film_viscosity):
    """The full film's Couette shear loss 2π·μ·R³·L·Δω²/(c·√(1 − ε²)), Δω = 2ω̄ the
    journal's speed relative to its bush [W]."""
    e2 = np.asarray(orbit_eccentricity_x) ** 2 + np.asarray(orbit_eccentricity_y) ** 2
    relative = 2 * np.asarray(orbit_mean_velocity, dtype=float)
    return 2 * np.pi * film_viscosity * (bearing_diameter / 2) ** 3 * bearing_length \
        * relative ** 2 / (bearing_clearance * np.sqrt(1 - e2))


# ---------------------------------------------------------------- the film's pressure
def squeeze_components(orbit_eccentricity_x, orbit_eccentricity_y, orbit_rate_x,
                       orbit_rate_y, orbit_mean_velocity):
    """The journal centre's velocity relative to the frame turning at ω̄,
    V⃗ = dε⃗/dt − ω̄ × ε⃗, resolved along ε⃗ (dε/dt, the squeeze) and a quarter-turn on
    (ε·(dφ/dt − ω̄), the whirl against the film's mean speed) [1/s].  At the centre,
    where ε⃗ has no direction, along V⃗ itself: (|V⃗|, 0) — every engine then starts the
    peak's search at ψ = 0, where the peak is, with no sign of a rounding zero to tell
    +180° from −180°."""
    x = np.asarray(orbit_eccentricity_x, dtype=float)
    y = np.asarray(orbit_eccentricity_y, dtype=float)
    w = np.asarray(orbit_mean_velocity, dtype=float)
    vx = np.asarray(orbit_rate_x, dtype=float) + w * y
    vy = np.asarray(orbit_rate_y, dtype=float) - w * x
    e = np.hypot(x, y)
    centre = e == 0
    e = np.where(centre, 1.0, e)
    return (np.where(centre, np.hypot(vx, vy), (vx * x + vy * y) / e),
            np.where(centre, 0.0, (vy * x - vx * y) / e))


def squeeze_rate(orbit_eccentricity_x, orbit_eccentricity_y, orbit_rate_x, orbit_rate_y,
                 orbit_mean_velocity):
    """dε/dt: V⃗ along ε⃗ [1/s]."""
    return squeeze_components(orbit_eccentricity_x, orbit_eccentricity_y, orbit_rate_x,
                              orbit_rate_y, orbit_mean_velocity)[0]


def whirl_rate(orbit_eccentricity_x, orbit_eccentricity_y, orbit_rate_x, orbit_rate_y,
               orbit_mean_velocity):
    """ε·(dφ/dt − ω̄): V⃗ a quarter-turn on from ε⃗ [1/s]."""
    return squeeze_components(orbit_eccentricity_x, orbit_eccentricity_y, orbit_rate_x,
                              orbit_rate_y, orbit_mean_velocity)[1]


def peak_pressure_start(orbit_squeeze_rate, orbit_whirl_rate, orbit_eccentricity_x,
                        orbit_eccentricity_y):
    """Where the search for the film's peak pressure starts, ψ from the thinnest film
    toward the rotation [rad]: on the side of the pressure lobe (centred on V⃗, at λ),
    the short bearing's steady peak ψ_s, cos ψ_s = (√(1 + 24ε²) − 1)/(4ε) (Ocvirk), held
    between |λ| − 85° (inside the lobe) and |λ|/2 (toward the thin film).  A start
    nearer the film than the lobe's middle is what lets five steps reach the peak."""
    a = np.asarray(orbit_squeeze_rate, dtype=float)
    b = np.asarray(orbit_whirl_rate, dtype=float)
    e = np.hypot(orbit_eccentricity_x, orbit_eccentricity_y)
    lobe = np.where((a == 0) & (b == 0), 0.0, np.arctan2(b + 0.0, a))   # +0.0: no −0
    steady = np.arccos(np.clip((np.sqrt(1 + 24 * e ** 2) - 1) / (4 * np.maximum(e, 1e-12)),
                               -1, 1))
    return np.sign(lobe) * np.minimum(np.maximum(steady, np.abs(lobe) - np.radians(85)),
                                      np.abs(lobe) / 2)


def peak_pressure_step(psi, orbit_squeeze_rate, orbit_whirl_rate, orbit_eccentricity_x,
                       orbit_eccentricity_y):
    """One Newton step toward the film's peak pressure, ψ − g/g′ held within ±1 rad,
    g = dln p/dψ·(1 − ε cos ψ)·(A cos ψ + B sin ψ) [rad].  The mid-plane pressure of the
    short bearing (half-Sommerfeld) is p ∝ (A cos ψ + B sin ψ)/(1 − ε cos ψ)³, A = dε/dt,
    B = ε(dφ/dt − ω̄); g = −A sin ψ + B cos ψ − A·ε·sin 2ψ − B·ε·(2 − cos 2ψ)."""
    a = np.asarray(orbit_squeeze_rate, dtype=float)
    b = np.asarray(orbit_whirl_rate, dtype=float)
    e = np.hypot(orbit_eccentricity_x, orbit_eccentricity_y)
    s, c = np.sin(psi), np.cos(psi)
    g = -a * s + b * c - a * e * np.sin(2 * psi) - b * e * (2 - np.cos(2 * psi))
    slope = -a * c - b * s - 2 * a * e * np.cos(2 * psi) - 2 * b * e * np.sin(2 * psi)
    with np.errstate(divide="ignore", invalid="ignore"):
        step = np.where(slope == 0, 0.0, np.clip(g / np.where(slope == 0, 1.0, slope), -1, 1))
    return psi - step


PEAK_PRESSURE_STEPS = 5     # the template's Newton columns: as many


class PeakSearch(NamedTuple):
    """The start and the Newton steps' angles ψ [rad], one row per orbit angle."""
    start: np.ndarray
    step_1: np.ndarray
    step_2: np.ndarray
    step_3: np.ndarray
    step_4: np.ndarray
    step_5: np.ndarray


def peak_pressure_search(orbit_squeeze_rate, orbit_whirl_rate, orbit_eccentricity_x,
                         orbit_eccentricity_y):
    """ψ of the film's peak pressure: the start and five Newton steps."""
    args = (orbit_squeeze_rate, orbit_whirl_rate, orbit_eccentricity_x, orbit_eccentricity_y)
    angles = [peak_pressure_start(*args)]
    for _ in range(PEAK_PRESSURE_STEPS):
        angles.append(peak_pressure_step(angles[-1], *args))
    return PeakSearch(*angles)


def film_pressure(psi, orbit_squeeze_rate, orbit_whirl_rate, orbit_eccentricity_x,
                  orbit_eccentricity_y, film_viscosity, bearing_length, bearing_clearance):
    """The short bearing's mid-plane film pressure at ψ from the thinnest film,
    p = 3μL²/(2c²)·(A cos ψ + B sin ψ)/(1 − ε cos ψ)³, none below zero (half-Sommerfeld:
    the film cavitates) [Pa].  From Reynolds' equation without the circumferential
    flow, ∂/∂z(h³ ∂p/∂z) = 12μ(ω̄ ∂h/∂θ + ∂h/∂t); for a still journal (A = 0,
    B = −ω/2·ε) Ocvirk's p = 3μωL²·ε sin θ/(4c²(1 + ε cos θ)³) with θ = π − ψ."""
    a = np.asarray(orbit_squeeze_rate, dtype=float)
    b = np.asarray(orbit_whirl_rate, dtype=float)
    e = np.hypot(orbit_eccentricity_x, orbit_eccentricity_y)
    p = 3 * film_viscosity * bearing_length ** 2 / (2 * bearing_clearance ** 2) \
        * (a * np.cos(psi) + b * np.sin(psi)) / (1 - e * np.cos(psi)) ** 3
    return np.maximum(p, 0.0)


# ---------------------------------------------------------------- results
def _second_cycle(orbit_angle):
    return np.ravel(np.asarray(orbit_angle, dtype=float)) >= 0


def second_cycle_min(values, orbit_angle):
    """The smallest value of each column over the second cycle [unit of values]."""
    return np.asarray(values, dtype=float)[_second_cycle(orbit_angle)].min(axis=0)


def second_cycle_max(values, orbit_angle):
    """The largest value of each column over the second cycle [unit of values]."""
    return np.asarray(values, dtype=float)[_second_cycle(orbit_angle)].max(axis=0)


def second_cycle_mean(values, orbit_angle, cycle):
    """The mean of each column over the second cycle, its closing row left out."""
    angle = np.ravel(np.asarray(orbit_angle, dtype=float))     # rad, as cycle
    rows = (angle >= 0) & (angle < cycle - 1e-9)
    return np.asarray(values, dtype=float)[rows].mean(axis=0)


def angle_of_min(values, orbit_angle, tolerance):
    """The first angle of the second cycle where a column comes within ``tolerance``
    of its smallest value [unit of orbit_angle]."""
    angle = np.ravel(np.asarray(orbit_angle, dtype=float))
    v = np.asarray(values, dtype=float)
    second = angle >= 0
    low = v[second].min(axis=0)
    hit = second[:, None] & (v <= low + tolerance)
    return angle[np.argmax(hit, axis=0)]


def angle_of_max(values, orbit_angle, tolerance):
    """The first angle of the second cycle where a column comes within ``tolerance``
    of its largest value [unit of orbit_angle]."""
    return angle_of_min(-np.asarray(values, dtype=float), orbit_angle, tolerance)


def count_clamped(orbit_clamped, orbit_angle):
    """Rows of the second cycle whose film broke down (ε held at the limit) [-]."""
    return np.asarray(orbit_clamped, dtype=float)[_second_cycle(orbit_angle)].sum(axis=0)


def film_ok(bearing_min_film, min_film_allowable, orbit_clamped_rows):
    """1 when every bearing's smallest film reaches the allowable and none broke down."""
    ok = np.all(np.asarray(bearing_min_film) >= min_film_allowable) \
        and np.all(np.asarray(orbit_clamped_rows) == 0)
    return 1.0 if ok else 0.0


def crank_step(crank_angle):
    """The crank-angle grid's step [rad]."""
    grid = np.ravel(np.asarray(crank_angle, dtype=float))
    return (grid[-1] - grid[0]) / (grid.size - 1)


def orbit_series(series, crank_angle, orbit_angle, cycle):
    """A per-bearing series of the crank-angle grid read at each orbit angle, linear
    between the grid's points (a 4° grid feeds the 1° orbit smoothly, and no angle
    halfway between two points depends on how an engine rounds the tie)
    (rows of orbit_angle, 2).  NaN where the crank-angle grid is not one regular
    cycle (the grader's sample angles)."""
    values = np.asarray(series, dtype=float)
    values = values.reshape(values.shape[0], -1)
    grid = np.round(np.degrees(np.ravel(np.asarray(crank_angle, dtype=float))), 9)
    angle = np.round(np.degrees(np.ravel(np.asarray(orbit_angle, dtype=float))), 9)
    period = np.degrees(cycle)
    step = (grid[-1] - grid[0]) / (grid.size - 1) if grid.size > 1 else 0.0
    if step <= 0 or not np.allclose(np.diff(grid), step) or grid[0] != 0 or \
            abs(grid[-1] - period) > 1e-6:
        return np.full((angle.size, values.shape[1]), np.nan)
    points = int(round(period / step))
    ratio = angle / step                    # as the sheet: φ/Δ, INT, and the fraction
    lower = np.floor(ratio)
    fraction = ratio - lower
    low = np.mod(lower, points).astype(int)
    high = np.mod(lower + 1, points).astype(int)
    return values[low] * (1 - fraction[:, None]) + values[high] * fraction[:, None]


def eccentricity_from_film(film, bearing_clearance):
    """ε = 1 − h/c [-]."""
    return 1 - film / bearing_clearance


def least(values):
    """The smallest of the values [their unit]."""
    return float(np.min(values))


def total(values):
    """The sum of the values [their unit]."""
    return float(np.sum(values))


def circle_x(orbit_angle):
    """The clearance circle drawn over the second cycle, cos(φ/2) [-]."""
    return np.cos(np.asarray(orbit_angle, dtype=float) / 2)


def circle_y(orbit_angle):
    """sin(φ/2) [-]."""
    return np.sin(np.asarray(orbit_angle, dtype=float) / 2)
