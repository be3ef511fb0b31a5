"""The bearings' oil film (issue 45): the mobility method against the short bearing's
published closed forms (Ocvirk's load and attitude), Petroff, the identities the
orbit rests on (the rod force on the rod's axis, a frame-free film, a free journal
turning at ω̄), Heun's step against a fine reference and against Euler, and the
workbook's numpy path on the thesis engine."""
import math

import numpy as np
import pytest

import crankbook
from crankbook.calc import bearing
from tests.conftest import (assert_build_refused_in_one_line, assert_slip_warned, edit_cells,
                            legend_names, named, text_formulas)

D, L, C, MU = 0.050, 0.025, 30e-6, 0.010          # m, m, m, Pa·s
OMEGA = 3000 * math.pi / 30


def run_orbit(load_u, load_v, mean_velocity, step_deg, omega=OMEGA, d=D, length=L):
    """The orbit of one bearing (two identical columns, as the sheet's two bearings)."""
    u = np.column_stack([load_u, load_u])
    v = np.column_stack([load_v, load_v])
    w = np.column_stack([mean_velocity, mean_velocity])
    return bearing.journal_orbit(u, v, w, math.radians(step_deg) / omega,
                                 bearing.mobility_scale(d, length, C, MU), length / d)


def ocvirk_attitude(eps):
    """Ocvirk's attitude angle: tan φ = π·√(1 − ε²)/(4ε) (Hamrock et al., ch. 12)."""
    return math.degrees(math.atan(math.pi * math.sqrt(1 - eps ** 2) / (4 * eps)))


def dense_peak(vx, vy, x, y, points=7201):
    """The largest of (V⃗·n̂)/(1 − ε⃗·n̂)³ over ``points`` directions n̂: the search's
    quantity by brute force, in the bush's own frame (no ψ, no lobe)."""
    best = np.zeros(np.shape(x))
    for t in np.linspace(-np.pi, np.pi, points):
        best = np.maximum(best, (vx * np.cos(t) + vy * np.sin(t))
                          / (1 - x * np.cos(t) - y * np.sin(t)) ** 3)
    return best


# ---------------------------------------------------------------- Raimondi and Boyd
def rb_at(sommerfeld, length_ratio):
    """h₀/c and (R/c)·f by the workbook's path: each table, then the blend."""
    films, frictions = [], []
    for table in (1, 2, 3, 4):
        row = bearing.rb_row(sommerfeld, table)
        fraction = bearing.rb_fraction(sommerfeld, table)
        films.append(bearing.rb_film_in_table(row, fraction))
        frictions.append(bearing.rb_friction_in_table(row, fraction))
    return (bearing.raimondi_boyd_blend(length_ratio, *films),
            bearing.raimondi_boyd_blend(length_ratio, *frictions))


def test_raimondi_boyd_reads_shigleys_worked_example():
    """Shigley (9th ed.) Examples 12-1 and 12-2: a full bearing, L/D = 1, μ = 4 µreyn,
    N = 30 r/s, W = 500 lbf, r = 0.75 in, c = 0.0015 in, l = 1.5 in: S = 0.135, and
    from the charts h₀/c = 0.42 and (r/c)·f = 3.50 — read off a chart, so to its
    reading (±0.01 and ±3 %)."""
    inch, reyn = 0.0254, 6894.757
    load, length, diameter = 500 * 4.448222, 1.5 * inch, 1.5 * inch
    s = bearing.sommerfeld(diameter, 0.0015 * inch, 4e-6 * reyn, 30 * 2 * math.pi,
                           bearing.specific_load(load, length, diameter))
    assert s == pytest.approx(0.135, abs=5e-4)
    film, friction = rb_at(s, 1.0)
    assert film == pytest.approx(0.42, abs=0.01)
    assert friction == pytest.approx(3.50, rel=0.03)


def test_raimondi_boyds_tables_meet_petroff_and_the_short_bearing():
    """Independent checks of the tables as typed: at ε = 0.1 every table's friction
    variable is Petroff's 2π²S within 2 %; h₀/c rises with S in each; the short
    (Ocvirk) bearing's film is never thinner than the finite one's, comes within 3 %
    of it at L/D = ¼ from h₀/c = 0.4 up, and is nearer it the shorter the bearing."""
    rows = bearing._RB_ROWS
    for table in (1, 2, 3, 4):
        block = rows[rows[:, 0] == table]
        assert np.all(np.diff(block[:, 1]) > 0) and np.all(np.diff(block[:, 2]) > 0)
        film, s, friction = block[-1, 1:]
        assert film == 0.9 and friction == pytest.approx(2 * math.pi ** 2 * s, rel=0.02)
    ratios = {}
    for table, length_ratio in ((2, 1.0), (3, 0.5), (4, 0.25)):
        block = rows[rows[:, 0] == table]
        eps = np.array([bearing.steady_eccentricity(np.arange(51), s, length_ratio)[0]
                        for s in block[:, 2]])
        ratios[length_ratio] = (1 - eps) / block[:, 1]
    assert all(np.all(r >= 1) for r in ratios.values())
    assert np.all(ratios[0.25][3:] < 1.03)
    assert np.all(ratios[0.25] < ratios[0.5]) and np.all(ratios[0.5] < ratios[1.0])


def test_the_blend_is_each_table_at_its_own_length_ratio():
    """Raimondi and Boyd's formula returns the L/D = 1, ½ and ¼ tables at those L/D,
    and the film between them lies between the two tables' films."""
    for s in (0.01, 0.05, 0.135, 0.2):
        films = []
        for table, length_ratio in ((2, 1.0), (3, 0.5), (4, 0.25)):
            row, fraction = bearing.rb_row(s, table), bearing.rb_fraction(s, table)
            alone = bearing.rb_film_in_table(row, fraction)
            assert rb_at(s, length_ratio)[0] == pytest.approx(alone, abs=1e-12)
            films.append(alone)
        assert films[2] < rb_at(s, 0.375)[0] < films[1] < rb_at(s, 0.75)[0] < films[0]


def test_the_thesis_steady_films():
    """The finite bearing's steady film is thinner than the short bearing's (the
    short bearing is optimistic); both engines of the thesis stay on the charts."""
    r = crankbook.compute("thesis")
    finite = np.asarray(r["bearing_min_film_steady"], dtype=float)
    short = np.asarray(r["bearing_min_film_short"], dtype=float)
    assert np.all(finite < short) and np.all(finite > 0)
    assert not np.any(np.asarray(r["rb_beyond"]))
    assert np.ravel(r["rb_row"]).size == bearing.raimondi_boyd_rows()   # every row laid out
    film, _ = rb_at(np.asarray(r["sommerfeld"], dtype=float),
                    np.asarray(r["bearing_length_ratio"], dtype=float))
    assert np.allclose(finite, film * float(r["bearing_clearance"]))


# ---------------------------------------------------------------- the film's pressure
def test_the_peak_search_finds_the_largest_pressure_of_any_state():
    """Five Newton steps from the sheet's start reach the largest mid-plane pressure
    of 20,000 random states (ε up to 0.995, the journal moving any way) within 10⁻⁶ of
    a 0.05° brute-force search over the film — the backward lobes, whose two equal
    peaks a plain start from the lobe's middle misses, included."""
    rng = np.random.default_rng(45)
    n = 20000
    eps = np.concatenate([rng.uniform(0, 0.995, n // 2), 1 - 10 ** rng.uniform(-2.3, -0.3, n // 2)])
    turn = rng.uniform(-np.pi, np.pi, n)
    x, y = eps * np.cos(turn), eps * np.sin(turn)
    vx, vy = rng.normal(size=n), rng.normal(size=n)
    w = rng.uniform(0, 300, n)
    rate_x, rate_y = vx - w * y, vy + w * x             # dε⃗/dt = V⃗ + ω̄ × ε⃗
    a = bearing.squeeze_rate(x, y, rate_x, rate_y, w)
    b = bearing.whirl_rate(x, y, rate_x, rate_y, w)
    psi = bearing.peak_pressure_search(a, b, x, y).step_5
    found = bearing.film_pressure(psi, a, b, x, y, 1.0, 1.0, 1.0) / 1.5
    assert np.all(found >= dense_peak(vx, vy, x, y) * (1 - 1e-6))


def test_a_still_journal_has_ocvirks_peak_pressure():
    """A steady load on a fixed bush: at rest the film's peak is Ocvirk's,
    p_max = 3μωL²·ε·sin θ_m/(4c²(1 + ε cos θ_m)³), cos θ_m = (1 − √(1 + 24ε²))/(4ε)
    (Ocvirk, NACA TN 2808; Hamrock et al., ch. 12), at the orbit's own ε."""
    rows = 3000
    orbit = run_orbit(np.full(rows, 8000.0), np.zeros(rows), np.full(rows, OMEGA / 2), 1.0)
    x, y = orbit.x[-1, :1], orbit.y[-1, :1]
    rate_x, rate_y = orbit.rate_x[-1, :1], orbit.rate_y[-1, :1]
    a = bearing.squeeze_rate(x, y, rate_x, rate_y, OMEGA / 2)
    b = bearing.whirl_rate(x, y, rate_x, rate_y, OMEGA / 2)
    assert abs(a[0]) < 1e-6 * abs(b[0])                # settled
    psi = bearing.peak_pressure_search(a, b, x, y).step_5
    peak = bearing.film_pressure(psi, a, b, x, y, MU, L, C)[0]
    eps = math.hypot(x[0], y[0])
    theta = math.acos((1 - math.sqrt(1 + 24 * eps ** 2)) / (4 * eps))
    ocvirk = 3 * MU * OMEGA * L ** 2 * eps * math.sin(theta) \
        / (4 * C ** 2 * (1 + eps * math.cos(theta)) ** 3)
    assert peak == pytest.approx(ocvirk, rel=1e-9)
    assert math.pi - abs(psi[0]) == pytest.approx(theta, abs=1e-9)
    assert psi[0] < 0                       # ahead of the thinnest film, against rotation


def test_the_films_pressure_carries_the_load():
    """The mid-plane pressure, parabolic across the length (2/3 of it on average) and
    integrated round the journal, is a force equal and opposite to the load the
    mobility was evaluated for: within 6 % (Goenka's fit of the short bearing's
    mobility), at random loads, eccentricities and speeds."""
    rng = np.random.default_rng(7)
    scale = bearing.mobility_scale(D, L, C, MU)
    t = np.linspace(-np.pi, np.pi, 20001)[:-1]
    for _ in range(12):
        eps, turn = rng.uniform(0.1, 0.9), rng.uniform(-np.pi, np.pi)
        x, y = np.array([eps * math.cos(turn)]), np.array([eps * math.sin(turn)])
        fu, fv = rng.normal(size=2) * 5000
        w = rng.uniform(50, 300)
        rate_x, rate_y = bearing.eccentricity_rate(x, y, fu, fv, w, scale, L / D)
        a = bearing.squeeze_rate(x, y, rate_x, rate_y, w)
        b = bearing.whirl_rate(x, y, rate_x, rate_y, w)
        rel = np.arctan2(y, x)
        p = bearing.film_pressure(t - rel, a, b, x, y, MU, L, C)   # ψ from the thin film
        force = -(2 / 3) * L * (D / 2) * np.array([np.sum(p * np.cos(t)), np.sum(p * np.sin(t))]) \
            * (t[1] - t[0])
        assert np.hypot(force[0] + fu, force[1] + fv) < 0.06 * math.hypot(fu, fv)


def test_the_thesis_bearings_peak_pressure():
    """The workbook's peak is the largest of the second cycle's rows, found where the
    brute-force search over the film finds it; the big end's comes with the firing."""
    r = crankbook.compute("thesis")
    x, y = (np.asarray(r[k], dtype=float) for k in ("orbit_eccentricity_x", "orbit_eccentricity_y"))
    w = np.asarray(r["orbit_mean_velocity"], dtype=float)
    vx = np.asarray(r["orbit_rate_x"], dtype=float) + w * y
    vy = np.asarray(r["orbit_rate_y"], dtype=float) - w * x
    angle = np.asarray(r["orbit_angle"], dtype=float)
    second = angle >= 0
    scale = 1.5 * float(r["film_viscosity"]) * 1e-3 * (float(np.ravel(r["bearing_length"])[0]) * 1e-3) ** 2 \
        / (float(r["bearing_clearance"]) * 1e-6) ** 2 / 1e6
    big_end = dense_peak(vx[second, 0], vy[second, 0], x[second, 0], y[second, 0]) * scale
    peak = np.asarray(r["bearing_peak_pressure"], dtype=float)
    assert peak[0] == pytest.approx(big_end.max(), rel=1e-5)
    assert 360 <= float(np.asarray(r["bearing_peak_pressure_angle"])[0]) <= 420
    assert np.allclose(peak, np.nanmax(np.where(second[:, None], r["film_pressure"], np.nan), axis=0))


# ---------------------------------------------------------------- the short bearing
@pytest.mark.parametrize("load", [2000.0, 8000.0, 20000.0])
def test_steady_load_settles_on_ocvirks_eccentricity_and_attitude(load):
    """A steady load on a fixed bush (ω̄ = ω/2): the orbit settles where the short
    bearing's closed forms put it — Goenka's fit within 1 % in ε and 1° in attitude,
    the journal displaced ahead of the load in the sense of rotation."""
    rows = 20000
    orbit = run_orbit(np.full(rows, load), np.zeros(rows), np.full(rows, OMEGA / 2), 1.0)
    x, y = orbit.x[-1, 0], orbit.y[-1, 0]
    eps, attitude = math.hypot(x, y), math.degrees(math.atan2(y, x))
    s = bearing.sommerfeld(D, C, MU, OMEGA, bearing.specific_load(load, L, D))
    eps_ocvirk = bearing.steady_eccentricity(np.arange(51), s, L / D)[0]
    assert eps == pytest.approx(eps_ocvirk, rel=0.01)
    assert attitude == pytest.approx(ocvirk_attitude(eps_ocvirk), abs=1.0)
    assert attitude > 0


def test_ocvirks_sommerfeld_number_from_the_load_formula():
    """S·(L/D)² from Ocvirk's load W = μ·U·L³/(4c²)·ε/(1 − ε²)²·√(π²(1 − ε²) + 16ε²)
    (U = R·ω), written out here from the load, not from the module's formula."""
    for eps in (0.1, 0.5, 0.9):
        load = MU * (D / 2 * OMEGA) * L ** 3 / (4 * C ** 2) * eps / (1 - eps ** 2) ** 2 \
            * math.sqrt(math.pi ** 2 * (1 - eps ** 2) + 16 * eps ** 2)
        s = bearing.sommerfeld(D, C, MU, OMEGA, load / (L * D))
        assert bearing.short_bearing_sommerfeld(eps, L / D) == pytest.approx(s, rel=1e-12)
        assert bearing.steady_eccentricity(np.arange(51), s, L / D)[0] == \
            pytest.approx(eps, abs=1e-12)


def test_petroff_power_is_the_full_film_shear_at_the_centre():
    """Petroff: T = 4π²·r³·l·μ·N/c and f·W·r = T; the orbit's friction power at ε = 0
    is T·ω."""
    n = OMEGA / (2 * math.pi)
    torque = 4 * math.pi ** 2 * (D / 2) ** 3 * L * MU * n / C
    load = 5000.0
    f = bearing.petroff_friction(D, C, MU, OMEGA, load / (L * D))
    assert f * load * D / 2 == pytest.approx(torque, rel=1e-12)
    assert bearing.friction_power(0.0, 0.0, OMEGA / 2, D, L, C, MU) == \
        pytest.approx(torque * OMEGA, rel=1e-12)


# ---------------------------------------------------------------- identities
def test_the_rod_force_lies_on_the_rods_axis():
    """Without the big end's centrifugal force the pin load is the rod force S:
    P_t = S·sin(ψ + β), P_r = S·cos(ψ + β); in the rod's frame it is (S, 0)."""
    psi = np.radians(np.arange(0, 720, 7.0))
    beta = np.arcsin(0.3 * np.sin(psi))
    s = 1e4 * np.cos(psi / 2) + 3e3
    u, v = bearing.big_end_load(s * np.sin(psi + beta), s * np.cos(psi + beta), 0.0, 0.05,
                                300.0, psi, beta)
    assert np.allclose(u, s, rtol=0, atol=1e-9)
    assert np.allclose(v, 0.0, atol=1e-9)


def test_the_film_does_not_depend_on_the_frame():
    """The same loads turned by a fixed angle give the same orbit turned by it."""
    rows = 1441
    angle = np.radians(np.arange(rows))
    u = 6000 + 9000 * np.cos(angle / 2) ** 8
    v = 3000 * np.sin(angle)
    w = np.full(rows, OMEGA / 2)
    a = run_orbit(u, v, w, 1.0)
    turn = 0.7
    b = run_orbit(u * math.cos(turn) - v * math.sin(turn),
                  u * math.sin(turn) + v * math.cos(turn), w, 1.0)
    assert np.allclose(np.hypot(a.x, a.y), np.hypot(b.x, b.y), atol=1e-9)
    assert np.allclose(a.x * math.cos(turn) - a.y * math.sin(turn), b.x, atol=1e-9)


def test_an_unloaded_journal_turns_at_the_mean_angular_velocity():
    """F = 0: the film neither squeezes nor lifts; ε⃗ only turns at ω̄ (Heun's step
    keeps its length to second order)."""
    x, y = np.array([0.5, 0.5]), np.array([0.0, 0.0])
    dx, dy = bearing.eccentricity_rate(x, y, 0.0, 0.0, 100.0, 1.0, 0.5)
    assert np.allclose(dx, 0.0) and np.allclose(dy, 50.0)


# ---------------------------------------------------------------- the step
def engine_like_load(step_deg):
    """A heavy big-end-like load: a firing spike on a rotating inertia load."""
    angle = np.radians(np.arange(-720, 720 + step_deg / 2, step_deg))
    firing = 25000 * np.exp(-((np.mod(angle, 4 * np.pi) - 2 * np.pi) / 0.35) ** 2)
    u = firing - 6000 * np.cos(angle)
    v = 4000 * np.sin(angle)
    return angle, u, v


def min_film_second_cycle(step_deg, euler=False):
    angle, u, v = engine_like_load(step_deg)
    w = np.full(angle.size, OMEGA / 2)
    if not euler:
        orbit = run_orbit(u, v, w, step_deg)
        eps = np.hypot(orbit.x[:, 0], orbit.y[:, 0])
    else:
        h = math.radians(step_deg) / OMEGA
        scale = bearing.mobility_scale(D, L, C, MU)
        x = y = 0.0
        eps = np.zeros(angle.size)
        for k in range(1, angle.size):
            dx, dy = bearing.eccentricity_rate(x, y, u[k - 1], v[k - 1], OMEGA / 2, scale, L / D)
            x, y = x + h * dx, y + h * dy
            eps[k] = math.hypot(x, y)
    return C * (1 - eps[angle >= 0].max())


def test_heuns_step_at_one_degree_is_the_fine_orbit():
    """At 1° Heun's minimum film is within 1 % of a 0.05° reference; Euler's at 1° is
    further off (the issue's reason for a second-order step)."""
    reference = min_film_second_cycle(0.05)
    heun = min_film_second_cycle(1.0)
    euler = min_film_second_cycle(1.0, euler=True)
    assert heun == pytest.approx(reference, rel=0.01)
    assert abs(euler - reference) > 2 * abs(heun - reference)


def test_an_impossible_load_is_clamped_and_flagged():
    """A load far beyond the film's capacity holds ε at the limit, flagged, no NaN."""
    rows = 800
    orbit = run_orbit(np.full(rows, 5e7), np.zeros(rows), np.full(rows, OMEGA / 2), 1.0)
    eps = np.hypot(orbit.x, orbit.y)
    assert np.all(np.isfinite(eps)) and eps.max() <= bearing.ECCENTRICITY_LIMIT + 1e-12
    assert bearing.clamped(orbit.predictor_scale, orbit.scale)[1:].max() == 1.0


# ---------------------------------------------------------------- the workbook's numbers
def test_the_thesis_bearings():
    """The thesis engine: the big end's ω̄ is (ω + dβ/dt)/2, the checked main bearing
    is the most loaded, films are c·(1 − ε), the results read the second cycle."""
    r = crankbook.compute("thesis")
    omega = float(r["angular_velocity"])
    w = np.asarray(r["bearing_mean_velocity"], dtype=float)
    assert np.allclose(w[:, 0], (omega + np.asarray(r["rod_angular_velocity"])) / 2)
    assert np.allclose(w[:, 1], omega / 2)
    means = np.asarray(r["journal_load_mean"], dtype=float)
    assert means[int(r["checked_journal"]) - 1] == pytest.approx(means.max())
    film = np.asarray(r["film_thickness"], dtype=float)
    angle = np.asarray(r["orbit_angle"], dtype=float)
    # the time step is one grid step at ω (the constant orbit_step and the grid's step)
    assert np.allclose(np.diff(np.radians(angle)), float(r["orbit_time_step"]) * omega)
    low = np.asarray(r["bearing_min_film"], dtype=float)
    assert np.allclose(low, film[angle >= 0].min(axis=0))
    assert 0 < low.min() < float(r["bearing_clearance"])
    assert float(r["bearing_ok"]) == float(low.min() >= float(r["min_film_allowable"]))
    power = np.asarray(r["friction_power"], dtype=float)
    one_cycle = (angle >= 0) & (angle < 720)              # the closing row left out
    assert np.allclose(np.asarray(r["bearing_friction_power"]), power[one_cycle].mean(axis=0))
    # the rod force (no centrifugal part) is the big end's load along the rod's axis
    assert np.asarray(r["bearing_load_u"])[:, 0].max() > 0


def test_a_larger_clearance_thins_the_big_ends_film_at_its_peak_load():
    thin = crankbook.compute("thesis", bearing_clearance=60.0)
    base = crankbook.compute("thesis")
    assert float(np.asarray(thin["bearing_max_eccentricity"])[0]) > \
        float(np.asarray(base["bearing_max_eccentricity"])[0])


def test_a_grade_typed_in_any_case_is_that_grade(tmp_path):
    """The sheet's MATCH and drop-down ignore letter case in every engine, so "sae30"
    in the cell is computed as SAE30 there; the command line and the reader agree."""
    from tests.conftest import edit_cells
    graded = crankbook.compute("thesis", oil_grade=" sae30 ")
    assert graded["oil_grade"] == 4.0
    built = crankbook.compute("thesis").to_excel(tmp_path / "thesis.xlsx")
    edit_cells(built, tmp_path / "typed.xlsx", {"oil_grade": "Sae30"})
    assert crankbook.read(tmp_path / "typed.xlsx")["oil_grade"] == 4.0


# SAE J300 (2015): kinematic viscosity at 100 °C [mm²/s], at least … below
J300_BANDS = {20: (6.9, 9.3), 30: (9.3, 12.5), 40: (12.5, 16.3), 50: (16.3, 21.9),
              60: (21.9, 26.1)}
OIL_DENSITY_100C = 820.0   # kg/m³: a mineral engine oil's 870 at 15 °C, expanded


def test_the_sae_fit_is_seireg_and_dandages_in_their_own_units():
    """The kelvin form the sheet and calc use against the fit as printed: µreyn and
    °F (Shigley Table 12-1), converted here from the inch and the pound-force."""
    from crankbook.calc import lubricant
    reyn = 4.4482216152605 / 0.0254 ** 2
    printed = {10: (0.0158, 1157.5), 20: (0.0136, 1271.6), 30: (0.0141, 1360.0),
               40: (0.0121, 1474.4), 50: (0.0170, 1509.6), 60: (0.0187, 1564.0)}
    celsius = np.linspace(0.0, 150.0, 31)
    for grade, (base, slope) in printed.items():
        fahrenheit = celsius * 9 / 5 + 32
        expected = base * 1e-6 * reyn * np.exp(slope / (fahrenheit + 95))
        assert np.allclose(lubricant.sae_viscosity(grade, celsius + 273.15), expected,
                           rtol=1e-12)
    grades = np.array([lubricant.sae_viscosity(g, celsius + 273.15) for g in printed])
    assert np.all(np.diff(grades, axis=0) > 0) and np.all(np.diff(grades, axis=1) < 0)


def test_the_sheets_grade_words_are_calcs_grades_in_order():
    """The choice's index picks the fit's constants in the sheet's CHOOSE and in calc:
    the words and calc's table must be in one order."""
    from crankbook.calc import lubricant
    from crankbook.spec.loader import load
    words = next(p.choices for p in load("engine").parameters if p.key == "oil_grade")
    assert words == lubricant.OIL_GRADES
    assert [int(w[3:]) for w in words[1:]] == list(lubricant.SAE_VISCOSITY_FIT)
    # the sheet's own copy of the constants (its two CHOOSE lists) is calc's, grade by
    # grade: the engines recompute only the grades the cross-check workbooks choose
    import re
    formula = next(q.formula for q in load("engine").quantities() if q.key == "film_viscosity")
    lists = [[float(v) for v in body.split(",")] for body in
             re.findall(r"CHOOSE\(MAX\(1,\{oil_grade\}-1\),([^)]*)\)", formula)]
    assert lists == [[base for base, _ in lubricant.SAE_VISCOSITY_FIT.values()],
                     [slope for _, slope in lubricant.SAE_VISCOSITY_FIT.values()]]


@pytest.mark.parametrize("grade", sorted(J300_BANDS))
def test_each_sae_grade_at_100c_sits_at_its_j300_band(grade):
    """The fit is of older straight grades and runs near the band's lower edge: within
    2 % of it or inside (SAE 40 is 0.9 % under at this density)."""
    from crankbook.calc import lubricant
    nu = lubricant.sae_viscosity(grade, 373.15) / OIL_DENSITY_100C * 1e6
    low, high = J300_BANDS[grade]
    assert 0.98 * low <= nu < high


def test_an_sae_grades_film_is_the_film_of_its_viscosity_typed():
    """The choice only supplies μ: every film result equals the typed route's at the
    same viscosity, and a hotter oil is thinner and gives a thinner film."""
    graded = crankbook.compute("thesis", oil_grade="SAE30", oil_temperature=393.15)
    mu = float(graded["film_viscosity"])
    assert mu == pytest.approx(0.0141 * 6.894757293168361
                               * math.exp(1360.0 / (1.8 * 120 + 32 + 95)), rel=1e-12)
    typed = crankbook.compute("thesis", oil_viscosity=mu)
    for key in ("sommerfeld", "bearing_min_film", "bearing_min_film_steady",
                "bearing_peak_pressure", "bearing_friction_power"):
        assert np.allclose(np.asarray(graded[key], dtype=float),
                           np.asarray(typed[key], dtype=float), rtol=1e-12), key
    hot = crankbook.compute("thesis", oil_grade="SAE30", oil_temperature=413.15)
    assert float(hot["film_viscosity"]) < mu
    assert np.all(np.asarray(hot["bearing_min_film"]) < np.asarray(graded["bearing_min_film"]))


@pytest.mark.parametrize("values,words", [
    (["bearing_clearance=900"], "clearance too large"),
    (["oil_groove_width=30"], "oil groove"),
    (["check_bearing=5"], "main bearing analysed"),
    (["oil_viscosity=0"], "oil_viscosity"),
    (["oil_grade=SAE35"], "oil_grade"),
    (["oil_grade=SAE30", "oil_temperature=900"], "oil_temperature"),
])
def test_bad_bearing_inputs_are_one_line(tmp_path, values, words):
    assert_build_refused_in_one_line(tmp_path, "thesis", values, words)


@pytest.mark.parametrize("inputs,flag,words", [
    ({"bearing_clearance": 0.03}, "clearance_implausible", "mm typed into the µm cell"),
    ({"oil_viscosity": 0.01}, "viscosity_implausible", "typed in Pa·s"),
    ({"min_film_allowable": 0.001}, "film_allowable_implausible", "mm typed into the µm cell"),
])
def test_a_bearing_value_in_the_wrong_unit_is_warned_and_built(inputs, flag, words):
    """0.03 (mm) for a 30 µm clearance, 0.01 (Pa·s) for 10 mPa·s, 0.001 (mm) for a 1 µm
    allowable film: a warning naming the likely unit, the workbook still computed."""
    assert_slip_warned("thesis", inputs, flag, words)


def test_the_orbit_file_is_the_workbooks_second_cycle(tmp_path):
    """`export bearing`: one row per angle of the second cycle and bearing, the film
    c·(1 − |e/c|) of the row's own components, as the workbook holds them."""
    import csv
    from crankbook.writer import bearing_csv
    r = crankbook.compute("thesis")
    path = bearing_csv.write(r, tmp_path / "orbit.csv")
    with open(path, encoding="utf-8-sig", newline="") as handle:
        table = list(csv.reader(handle))
    assert table[0][:5] == ["crank angle [deg]", "bearing", "e_u/c", "e_v/c", "h_min [um]"]
    body = table[1:]
    assert len(body) == 2 * 721
    c = float(r["bearing_clearance"])
    for angle, name, x, y, film, peak, broke in body[::97]:
        assert 0 <= float(angle) <= 720 and name in ("big end", f"main {int(r['checked_journal'])}")
        assert float(film) == pytest.approx(c * (1 - math.hypot(float(x), float(y))), abs=1e-5)
    films = np.array([float(row[4]) for row in body]).reshape(-1, 2)
    assert np.allclose(films.min(axis=0), np.asarray(r["bearing_min_film"]), atol=1e-6)
    peaks = np.array([float(row[5]) for row in body]).reshape(-1, 2)
    assert table[0][5] == "p_max [MPa]"
    assert np.allclose(peaks.max(axis=0), np.asarray(r["bearing_peak_pressure"]), atol=1e-5)


def test_export_bearing_without_a_workbook_is_one_line(tmp_path):
    import subprocess
    import sys
    run = subprocess.run([sys.executable, "-m", "crankbook", "export", "bearing", "-o",
                          str(tmp_path / "o.csv")], capture_output=True, text=True)
    assert run.returncode == 2 and "needs the engine WORKBOOK" in run.stderr
    assert "Traceback" not in run.stderr and not (tmp_path / "o.csv").exists()


def test_the_orbit_chart_draws_the_second_cycle_only(tmp_path):
    """rows_from = 0: every range of the orbit chart (the orbits, the clearance circle
    and the equal-axis frame's sources) starts at the row of 0°, the start transient
    left out, and the cached points are the 721 of the second cycle."""
    import re
    import zipfile
    from crankbook.writer.layout import FIRST_ROW
    path = crankbook.compute("thesis").to_excel(tmp_path / "t.xlsx", lang="en")
    with zipfile.ZipFile(path) as book:
        charts = [book.read(n).decode() for n in book.namelist()
                  if n.startswith("xl/charts/chart")]
    orbit = [c for c in charts if "Journal orbit e/c" in c]
    assert len(orbit) == 2                            # on its sheet and on the Charts sheet
    for chart in orbit:
        refs = re.findall(r"<c:f>'Journal orbit'!\$[A-Z]+\$(\d+):\$[A-Z]+\$(\d+)</c:f>", chart)
        grid = [(int(a), int(b)) for a, b in refs if int(b) == FIRST_ROW + 1440 + 1]
        assert len(grid) == 6                         # two orbits and the circle, x and y
        assert {first for first, _ in grid} == {FIRST_ROW + 1 + 720}
        assert set(re.findall(r'<c:ptCount val="(\d+)"/>', chart)) >= {"721"}


def test_a_wide_gap_and_thin_oil_break_the_big_ends_film():
    """200 µm and 2 mPa·s at 6100 r/min: rows held at ε = 0.995 are counted, the
    smallest film is c·(1 − 0.995) and the verdict fails."""
    r = crankbook.compute("thesis", bearing_clearance=200.0, oil_viscosity=2.0, speed=6100.0)
    rows = np.asarray(r["orbit_clamped_rows"], dtype=float)
    assert rows[0] > 0 and float(r["bearing_broken_rows"]) == rows.sum()
    assert float(np.asarray(r["bearing_min_film"])[0]) == pytest.approx(200.0 * 0.005)
    assert float(r["bearing_ok"]) == 0.0


def test_a_coarse_grid_feeds_the_orbit_linearly():
    """On a 4° grid the 1° orbit reads each load linearly between grid points: 2° past
    a point is the mean of its two neighbours (not a tie an engine rounds either way),
    and the grid points themselves are the grid's values."""
    r = crankbook.compute("thesis", step=4)
    load = np.asarray(r["bearing_load_u"], dtype=float)
    orbit = np.asarray(r["orbit_load_u"], dtype=float)
    angle = np.asarray(r["orbit_angle"], dtype=float)
    at = {a: k for k, a in enumerate(angle)}
    assert np.allclose(orbit[at[8.0]], load[2]) and np.allclose(orbit[at[-712.0]], load[2])
    assert np.allclose(orbit[at[10.0]], (load[2] + load[3]) / 2)
    assert np.allclose(orbit[at[9.0]], 0.75 * load[2] + 0.25 * load[3])
    assert float(r["crank_step"]) == pytest.approx(4.0)


# ------------------------------------------- the short bearing against the finite one
def finite_reynolds_load(eps, length_ratio, drive, n_theta=180, n_xi=24):
    """The film force of a finite bearing by finite differences (numpy, red-black SOR,
    p ≥ 0: Reynolds' cavitation condition, as Raimondi and Boyd's), nondimensional.

    H = 1 + ε·cos θ over θ ∈ [0, 2π) and ξ = z/R ∈ [−L/D, L/D], p = 0 at the ends;
    ∂/∂θ(H³ ∂P/∂θ) + ∂/∂ξ(H³ ∂P/∂ξ) = 6 ∂H/∂θ for a journal turning at ω in a still
    bush (``drive="rotation"``, P = p·c²/(μωR²)), = 12 cos θ for the journal squeezed
    towards the thin film at dε/dt (``"squeeze"``, P = p·c²/(μ·(dε/dt)·R²)).  Returns
    |∫∫P·(cos θ, sin θ) dθ dξ|: the force over μωR⁴/c² or μ(dε/dt)R⁴/c²."""
    theta = np.arange(n_theta) * 2 * np.pi / n_theta
    d_theta, d_xi = theta[1], 2 * length_ratio / n_xi
    east = (1 + eps * np.cos(theta + d_theta / 2)) ** 3 / d_theta ** 2
    west = (1 + eps * np.cos(theta - d_theta / 2)) ** 3 / d_theta ** 2
    north = (1 + eps * np.cos(theta)) ** 3 / d_xi ** 2
    source = -6 * eps * np.sin(theta) if drive == "rotation" else 12 * np.cos(theta)
    centre = east + west + 2 * north
    p = np.zeros((n_theta, n_xi + 1))
    colour = np.add.outer(np.arange(n_theta), np.arange(n_xi + 1)) % 2
    inner = np.zeros_like(p, dtype=bool)
    inner[:, 1:-1] = True
    for sweep in range(20000):
        before = p.copy()
        for shade in (0, 1):
            gauss_seidel = (east[:, None] * np.roll(p, -1, 0) + west[:, None] * np.roll(p, 1, 0)
                            + north[:, None] * (np.roll(p, -1, 1) + np.roll(p, 1, 1))
                            - source[:, None]) / centre[:, None]
            p = np.where(inner & (colour == shade), np.maximum(0, p + 1.7 * (gauss_seidel - p)), p)
        if sweep % 100 == 0 and np.abs(p - before).max() < 1e-10 * max(1.0, p.max()):
            break
    else:
        raise AssertionError("the finite-difference film did not converge")
    weights = np.full(n_xi + 1, d_xi)
    weights[[0, -1]] = d_xi / 2
    return math.hypot((p * np.cos(theta)[:, None] * weights).sum() * d_theta,
                      (p * np.sin(theta)[:, None] * weights).sum() * d_theta)


@pytest.mark.parametrize("table,length_ratio", [("1", 1.0), ("1/2", 0.5), ("1/4", 0.25)])
def test_a_finite_difference_film_gives_raimondi_and_boyds_tables(table, length_ratio):
    """The solver below is checked first: Raimondi and Boyd's Sommerfeld numbers (the
    tables the sheet ships) from its own film, S = 2(L/D)/(π·force), within 2 % for
    every row from h₀/c = 0.1 (the grid is 2°)."""
    rows = dict(bearing.RAIMONDI_BOYD)[table]
    for film_ratio, sommerfeld, _ in rows:
        if film_ratio >= 0.1:
            force = finite_reynolds_load(1 - film_ratio, length_ratio, "rotation")
            assert 2 * length_ratio / (math.pi * force) == pytest.approx(sommerfeld, rel=0.02), \
                film_ratio


def test_the_sheets_short_bearing_mobility_is_the_finite_bearings_limit_and_optimistic():
    """Pure squeeze: the force the sheet's mobility (Goenka's short bearing) gives,
    4(L/D)/M_ζ, against a finite bearing's.  They meet as L/D → 0 (within Goenka's 4 %
    fit of the short bearing), and the finite bearing carries less, the less the longer
    the bearing and the higher ε: the sheet's films are optimistic, as labelled."""
    def finite_over_sheet(eps, length_ratio):
        m_zeta, _ = bearing.short_bearing_mobility(eps, 0.0, length_ratio)
        return finite_reynolds_load(eps, length_ratio, "squeeze") / (4 * length_ratio / m_zeta)

    eccentricities = (0.3, 0.6, 0.8)
    for eps in eccentricities:
        assert finite_over_sheet(eps, 0.05) == pytest.approx(1.0, abs=0.04)
    ratios = np.array([[finite_over_sheet(eps, ld) for eps in eccentricities]
                       for ld in (0.25, 0.5, 1.0)])
    assert np.all(ratios < 1)
    assert np.all(np.diff(ratios, axis=0) < 0) and np.all(np.diff(ratios, axis=1) < 0)


def test_the_main_bearings_name_says_which_bearing_live(tmp_path, soffice, ssconvert):
    """The main bearing's name — its rows, its columns' headers in both languages, its
    curves in the load, orbit and film charts — holds its number (q_checked_journal),
    live: a bearing typed in the cells renames every one of them in LibreOffice and
    Gnumeric, and a bearing that does not exist leaves "?" beside the status's words."""
    from crankbook.reading import recalc
    path = crankbook.compute("inline-4", step=6).to_excel(tmp_path / "i4.xlsx", lang="en")
    journal = round(named(path, only=["q_checked_journal"])["q_checked_journal"])
    texts = text_formulas(path, "Main bearing ")
    legends = {text for _, text in legend_names(path) if "Main bearing" in text}
    assert {"Main bearing %d (engine frame)" % journal,
            "Minimum film thickness h_min = c·(1 − ε) — Main bearing %d (engine frame)"
            % journal} <= legends
    assert len(texts) > 20 and all(f"Main bearing {journal} " in t for t in texts.values())
    assert any("主轴承" in t for t in text_formulas(path, "主轴承").values())   # the zh row
    other = 1 if journal != 1 else 2
    edited = {}
    for case, number in (("typed", other), ("missing", 9)):
        edited[case] = tmp_path / f"{case}.xlsx"
        edit_cells(path, edited[case], {"check_bearing": float(number)})
    for engine in ("libreoffice", "gnumeric"):
        typed, missing = recalc.computed_values([edited["typed"], edited["missing"]],
                                                tmp_path / engine, engine=engine)
        for (sheet, row, col), text in texts.items():
            renamed = text.replace(f"Main bearing {journal} ", f"Main bearing {other} ")
            assert typed.values(sheet, row, col, row, col)[0] == renamed, (engine, sheet, row)
            unknown = text.replace(f"Main bearing {journal} ", "Main bearing ? ")
            assert missing.values(sheet, row, col, row, col)[0] == unknown, (engine, sheet, row)
