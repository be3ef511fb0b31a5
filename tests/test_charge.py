"""The charge, friction and brake figures (issue 41): identities, the ideal cycle's
limit, published values, design changes that must move the power by what the charge
predicts, and bad inputs."""
import numpy as np
import pytest

import crankbook
from crankbook.calc import charge, cycle
from crankbook.errors import CrankbookError
from tests.conftest import assert_slip_warned, run_cli


@pytest.fixture(scope="module")
def four():
    return crankbook.compute("inline-4")


def points(r, key):
    return np.array([r.scalars[f"operating_{key}[{k}]"]
                     for k in range(1, len(r.parameters["operating_speed"]) + 1)])


# ---------------------------------------------------------------- identities
def test_brake_figures_obey_their_definitions(four):
    """BMEP = 4π·T_b/V_D (four-stroke), P = T·ω, η_m = BMEP/IMEP, IMEP·V_d = ∮p·dV,
    BSFC = 3.6·10⁶·ṁ_f/P_b — at the design speed and at every operating point."""
    s = four.scalars
    displacement = s["engine_displacement"] / 1000                      # L -> m³
    omega = s["angular_velocity"]
    assert s["bmep"] * 1e6 == pytest.approx(4 * np.pi * s["brake_torque"] / displacement,
                                            rel=1e-12)
    assert s["brake_power"] * 1000 == pytest.approx(s["brake_torque"] * omega, rel=1e-12)
    assert s["indicated_mean_effective_pressure"] * 1e6 * s["displaced_volume"] * 1e-6 == \
        pytest.approx(s["indicated_work"], rel=1e-12)
    assert s["mechanical_efficiency"] == pytest.approx(
        s["bmep"] / s["indicated_mean_effective_pressure"], rel=1e-12)
    fuel_flow = 4 * s["fuel_mass"] * 1e-6 * omega / (4 * np.pi)        # kg/s
    assert s["bsfc"] == pytest.approx(3.6e6 * fuel_flow / (s["brake_power"] * 1000) * 1000,
                                      rel=1e-12)
    speeds = np.array(four.parameters["operating_speed"]) * np.pi / 30
    assert np.allclose(points(four, "bmep") * 1e6,
                       4 * np.pi * points(four, "brake_torque") / displacement, rtol=1e-12)
    assert np.allclose(points(four, "brake_power") * 1000,
                       points(four, "brake_torque") * speeds, rtol=1e-12)
    assert np.allclose(points(four, "bmep"), points(four, "imep") - points(four, "fmep"),
                       rtol=1e-12)
    flow = 4 * points(four, "fuel_mass") * 1e-6 * speeds / (4 * np.pi)
    assert np.allclose(points(four, "bsfc"), 3.6e9 * flow / (points(four, "brake_power") * 1000),
                       rtol=1e-12)


def test_the_engine_indicated_work_is_the_cylinders_work(four):
    """One integration, the p–V loop's: the engine's work is Z times one cylinder's
    (before, the mean torque's and the loop's differed by 0.007 %)."""
    s = four.scalars
    assert s["engine_indicated_work"] == 4 * s["indicated_work"]
    # the mean torque integrates the same cycle another way: they agree to 0.01 %
    assert s["engine_mean_torque"] * 4 * np.pi == pytest.approx(s["engine_indicated_work"],
                                                                rel=1e-4)


def test_the_charge_sets_the_heat(four):
    """m_a = η_v·p_i/(R·T_i)·V_d, m_f = m_a/AFR, Q = m_f·Q_LHV·η_c, from the inputs."""
    s, p = four.scalars, four.parameters
    density = p["intake_pressure"] * 1e6 / (287.0 * p["intake_temperature"])
    air = s["volumetric_efficiency"] * density * s["displaced_volume"] * 1e-6
    assert s["trapped_air_mass"] == pytest.approx(air * 1e6, rel=1e-12)
    assert s["fuel_mass"] == pytest.approx(air * 1e6 / p["air_fuel_ratio"], rel=1e-12)
    assert s["heat_per_cycle"] == pytest.approx(
        air / p["air_fuel_ratio"] * p["fuel_lhv"] * 1e6 * p["combustion_efficiency"], rel=1e-12)
    # η_v at the design speed is the table read there (5000 r/min is a table point)
    table = dict(zip(p["charge_speed"], p["charge_volumetric_efficiency"]))
    assert s["volumetric_efficiency"] == table[p["speed"]]


def test_the_charge_table_is_read_linearly_and_held_beyond_its_ends():
    x, y = [1000.0, 3000.0, 5000.0], [0.8, 0.9, 0.7]
    at = np.array([500.0, 1000.0, 2000.0, 3000.0, 4500.0, 5000.0, 9000.0])
    got = charge.table_value(at, x, y, charge.table_segment(at, x))
    assert np.allclose(got, [0.8, 0.8, 0.85, 0.9, 0.75, 0.7, 0.7], rtol=1e-15)


# ---------------------------------------------------------------- published values
def test_standard_air_density_is_heywoods():
    """Heywood §2.10: dry air at 1.013 bar and 25 °C has ρ = 1.184 kg/m³."""
    assert charge.intake_air_density(101325.0, 298.15) == pytest.approx(1.184, abs=5e-4)


def test_the_default_friction_is_barnes_moss_for_a_100_mm_stroke():
    """The default Chen–Flynn coefficients recast the Barnes-Moss total friction of
    four-cylinder SI engines printed by Heywood (§13.6): tfmep = 0.97 + 0.15·(N/1000) +
    0.05·(N/1000)² bar, for a 100 mm stroke (S_p = N/300 m/s)."""
    r = crankbook.compute("inline-4", crank_radius=50.0)
    p = r.parameters
    for n in (1000.0, 2500.0, 4000.0, 6000.0):
        barnes_moss = (0.97 + 0.15 * n / 1000 + 0.05 * (n / 1000) ** 2) * 1e5
        got = charge.chen_flynn_fmep(5e6, 2 * 0.1 * n / 60, p["fmep_constant"] * 1e6,
                                     p["fmep_pressure_factor"], p["fmep_speed_factor"] * 1e6,
                                     p["fmep_speed_squared_factor"] * 1e6)
        assert got == pytest.approx(barnes_moss, rel=1e-12), n


def test_full_load_figures_are_those_of_a_naturally_aspirated_gasoline_engine(four):
    """The defaults give what Heywood's Table 2.1 and §2.9 print for a naturally
    aspirated spark-ignition engine at full load: a maximum BMEP of about 0.85–1.2 MPa
    (1.05 the classic figure, modern four-valve engines above it), a BSFC of 250–330
    g/kWh at the peak power, the peak torque well below the peak power's speed."""
    s = four.scalars
    assert 0.85 <= max(points(four, "bmep")) <= 1.2
    peak = int(np.argmax(points(four, "brake_power")))
    assert 250 <= points(four, "bsfc")[peak] <= 330
    assert s["peak_torque_speed"] < s["peak_power_speed"]
    assert min(points(four, "mechanical_efficiency")) > 0.6


# ---------------------------------------------------------------- the ideal cycle's limit
def test_instant_combustion_without_losses_gives_the_otto_efficiency():
    """With the polytropes isentropic (n = κ = γ) and the heat released at TDC within
    one grid step, the closed cycle's work is the ideal constant-volume cycle's:
    W/Q = 1 − r^(1−γ) (Heywood eq. 5.31)."""
    gamma, ratio = 1.4, 9.0
    r = crankbook.compute("thesis", step=0.1, compression_ratio=ratio,
                          compression_exponent=gamma, expansion_exponent=gamma,
                          heat_capacity_ratio=gamma, combustion_start=360.0,
                          combustion_duration=0.1, wiebe_efficiency=20.0,
                          exhaust_valve_opening=540.0)
    angle = np.asarray(r["crank_angle"])
    closed = (angle >= 180) & (angle <= 540)
    work = cycle.indicated_work(np.asarray(r["closed_pressure"])[closed] * 1e6,
                                np.asarray(r["cylinder_volume"])[closed] * 1e-6)
    assert work / r["heat_per_cycle"] == pytest.approx(charge.otto_efficiency(ratio, gamma),
                                                       rel=2e-3)


# ---------------------------------------------------------------- design changes
def test_a_larger_bore_raises_the_power_by_its_displacement():
    """At fixed η_v the charge, the heat and the chamber all grow with V_d, the pressure
    curve stays, and the brake power grows as the bore squared (the default friction has
    no pressure term)."""
    base = crankbook.compute("inline-4")
    wider = crankbook.compute("inline-4", bore=base.parameters["bore"] * 1.09)
    assert wider["brake_power"] == pytest.approx(base["brake_power"] * 1.09 ** 2, rel=1e-9)
    assert np.allclose(points(wider, "brake_power"), points(base, "brake_power") * 1.09 ** 2,
                       rtol=1e-9)
    assert wider["indicated_mean_effective_pressure"] == pytest.approx(
        base["indicated_mean_effective_pressure"], rel=1e-9)


def test_boost_raises_the_charge_and_the_closed_cycle_work_in_proportion():
    """1.5 times the intake pressure: 1.5 times the air, fuel and heat; the closed part
    of the cycle scales with it (the exhaust back pressure does not)."""
    base = crankbook.compute("inline-4")
    boosted = crankbook.compute("inline-4", intake_pressure=base.parameters["intake_pressure"]
                                * 1.5)
    for key in ("trapped_air_mass", "fuel_mass", "heat_per_cycle"):
        assert boosted[key] == pytest.approx(base[key] * 1.5, rel=1e-12), key
    angle = np.asarray(base["crank_angle"])
    closed = (angle >= 180) & (angle <= 500)
    assert np.allclose(np.asarray(boosted["closed_pressure"])[closed],
                       np.asarray(base["closed_pressure"])[closed] * 1.5, rtol=1e-12)
    assert boosted["brake_power"] > 1.4 * base["brake_power"]


@pytest.mark.parametrize("preset", ["inline-4", "v6-60"])
def test_the_stroke_study_agrees_with_a_rebuild_at_the_other_stroke(preset):
    """The study redoes the pressure model for S′ (its volumes, chamber and charge): the
    workbook rebuilt with S′ gives the same figures, in the study's direction."""
    r = crankbook.compute(preset)
    s = r.scalars
    other = crankbook.compute(preset, crank_radius=s["alternative_crank_radius"],
                              alternative_stroke=r.parameters["crank_radius"] * 2).scalars
    for key, there in (("indicated_power", "indicated_power"),
                       ("peak_torque", "torque_max"), ("peak_side_force", None),
                       ("peak_inertia_force", None)):
        want = other[there] if there else other[f"stroke_study_{key}"]
        assert s[f"stroke_study_{key}_alternative"] == pytest.approx(want, rel=1e-9), key
    # and the change's sign is the rebuild's: a longer stroke, more power
    longer = s["stroke_study_indicated_power_alternative"] > s["stroke_study_indicated_power"]
    assert longer == (s["alternative_crank_radius"] > r.parameters["crank_radius"])


def test_the_thesis_keeps_its_typed_heat_and_its_pressure():
    """Issue 41.5: the thesis preset's pressure is its own (1400 J at every speed, the
    same p(α) in its stroke study)."""
    r = crankbook.compute("thesis")
    assert r.parameters["heat_release_source"] == "typed" and r["heat_per_cycle"] == 1400.0
    assert r.scalars["operating_pressure_from[1]"] == 0
    assert np.array_equal(np.asarray(r["alt_cylinder_pressure"]),
                          np.asarray(r["cylinder_pressure"]))


def test_each_point_has_its_own_pressure(four):
    peaks = points(four, "peak_pressure")
    assert len(set(np.round(peaks, 9))) == len(peaks)
    assert all(four.scalars[f"operating_pressure_from[{k}]"] == 2 for k in range(1, 13))
    # the full-load curves peak inside the range, not at its ends
    speeds = four.parameters["operating_speed"]
    assert speeds[0] < four["peak_torque_speed"] < speeds[-1]


# ---------------------------------------------------------------- bad inputs
@pytest.mark.parametrize("setting,words", [
    ("air_fuel_ratio=0", "parameter air_fuel_ratio = 0: must be > 0"),
    ("combustion_efficiency=1.2", "parameter combustion_efficiency = 1.2: must be"),
    ("charge_speed=1000,3000,2000,4000,5000,6000,7000", "strictly ascending"),
    ("heat_release_source=fuel", "heat_release_source"),
])
def test_bad_charge_inputs_are_one_line(tmp_path, setting, words):
    out = tmp_path / "engine.xlsx"
    done = run_cli("build", "--preset", "inline-4", "--set", setting, "-o", out)
    assert done.returncode == 2, done.stderr
    assert done.stderr.count("\n") == 1 and words in done.stderr, done.stderr
    assert not out.exists()
    with pytest.raises(CrankbookError):
        key, value = setting.split("=")
        crankbook.compute("inline-4", **{key: value.split(",") if "," in value else value})


@pytest.mark.parametrize("inputs", [{"intake_pressure": 0.95}, {"exhaust_pressure": 1.1},
                                    {"ambient_pressure": 1.0}])
def test_a_gas_exchange_pressure_typed_in_bar_is_warned(inputs):
    """0.95 bar at the intake typed as 0.95 MPa charges the cylinder tenfold; 1.1 at
    the exhaust turns the brake torque negative: a warning that says bar."""
    assert_slip_warned("inline-4", inputs, "gas_pressure_looks_like_bar",
                       "is it in bar? It must be in MPa (0.95 bar is typed 0.095)")
