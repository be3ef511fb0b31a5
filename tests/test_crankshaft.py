"""The crankshaft sheets against independent computations: the crank-pin load as a
vector sum of the rod force (from the mechanism's geometry) and the big end's
centrifugal force, journal loads summing to the throw loads, stresses by hand at a
stated angle, the thesis's rules and dimensions, and seed 002's safety factor."""
import numpy as np
import pytest

import crankbook
from crankbook.errors import GeometryError, ParameterValueError
from tests.conftest import assert_slip_warned


@pytest.fixture(scope="module")
def thesis():
    return crankbook.compute("thesis", step=1)


def test_crankpin_load_is_the_rod_force_plus_the_big_end_centrifugal_force(thesis):
    g, s, p = thesis.series(), thesis.scalars, thesis.parameters
    r, l = p["crank_radius"] / 1000, p["rod_length"] / 1000
    psi = np.radians(g.index.to_numpy())                      # centric: ψ = α
    pin = np.column_stack([r * np.sin(psi), r * np.cos(psi)])
    piston = np.column_stack([np.zeros_like(psi),
                              r * np.cos(psi) + np.sqrt(l ** 2 - (r * np.sin(psi)) ** 2)])
    along = (pin - piston) / l                                # from piston pin to crank pin
    force = g["rod_force"].to_numpy()[:, None] * along       # compression pushes the pin
    tangential = force[:, 0] * np.cos(psi) - force[:, 1] * np.sin(psi)
    inward = -(force[:, 0] * np.sin(psi) + force[:, 1] * np.cos(psi))
    centrifugal = s["big_end_mass"] * r * s["angular_velocity"] ** 2
    size = np.abs(g["crankpin_load[1]"]).max()
    head = slice(0, -1)           # the closing point repeats 0° (the cycle is periodic)
    assert np.allclose(g["crankpin_load_tangential[1]"][head], tangential[head], rtol=0,
                       atol=1e-9 * size)
    assert np.allclose(g["crankpin_load_radial[1]"][head], (inward - centrifugal)[head],
                       rtol=0, atol=1e-9 * size)


@pytest.mark.parametrize("preset,sets", [("inline-4", {}),
                                         ("v8-crossplane", {"counterweights": 1})])
def test_journal_loads_sum_to_the_throw_loads(preset, sets):
    result = crankbook.compute(preset, step=2, **sets)
    g, s, p = result.series(), result.scalars, result.parameters
    alpha = g.index.to_numpy()
    throws = int(max(p["throw"]))
    throw = [int(t) for t in p["throw"]]
    total = np.zeros((alpha.size, 2))
    for t in range(1, throws + 1):
        first = throw.index(t)
        theta = np.radians(alpha - p["firing_angle"][first] + p["bank_angle"][first])
        e_r = np.column_stack([np.sin(theta), np.cos(theta)])
        e_t = np.column_stack([np.cos(theta), -np.sin(theta)])
        rods = throw.count(t)
        rotating = p["crank_unbalanced_mass"] + rods * s["big_end_mass"]
        counter = p["counterweights"] * (rotating + p["balance_fraction"] * rods
                                         * s["reciprocating_mass"])
        web = (p["crank_unbalanced_mass"] - counter) * p["crank_radius"] / 1000 * \
            s["angular_velocity"] ** 2
        total += g[f"crankpin_load_tangential[{t}]"].to_numpy()[:, None] * e_t \
            - g[f"crankpin_load_radial[{t}]"].to_numpy()[:, None] * e_r + web * e_r
    journals = [f"[{j}]" for j in range(1, throws + 2)]
    x = sum(g[f"journal_load_x{j}"] for j in journals)
    y = sum(g[f"journal_load_y{j}"] for j in journals)
    size = np.abs(total).max()
    assert np.allclose(x, total[:, 0], rtol=0, atol=1e-9 * size)
    assert np.allclose(y, total[:, 1], rtol=0, atol=1e-9 * size)


@pytest.mark.parametrize("theory,factor", [(3, 4.0), (4, 3.0)])
def test_pin_stresses_by_hand_at_375_degrees(theory, factor):
    result = crankbook.compute("thesis", strength_theory=theory, crankpin_bore=16.0)
    g, p = result.series(), result.parameters
    row = g.loc[375.0]
    d, bore = p["crankpin_diameter"] / 1000, p["crankpin_bore"] / 1000
    w = np.pi * d ** 3 / 32 * (1 - (bore / d) ** 4)
    a = (p["main_journal_length"] / 2 + p["web_thickness"] + p["crankpin_length"] / 2) / 1000
    plane = row["crankpin_load_radial[1]"] * a / 2 / w / 1e6
    perpendicular = row["crankpin_load_tangential[1]"] * a / 2 / w / 1e6
    torque = row["crankpin_load_tangential[1]"] * p["crank_radius"] / 1000 / 2   # one throw
    tau = torque / (2 * w) / 1e6
    bending = np.hypot(plane, perpendicular)
    assert row["pin_bending_stress_plane"] == pytest.approx(plane, rel=1e-12)
    assert row["pin_bending_stress_perpendicular"] == pytest.approx(perpendicular, rel=1e-12)
    assert row["pin_torsional_stress"] == pytest.approx(tau, rel=1e-12)
    assert row["pin_combined_stress"] == pytest.approx(np.sqrt(bending ** 2 + factor * tau ** 2),
                                                       rel=1e-12)
    assert result.scalars["stress_at_check_angle"] == pytest.approx(row["pin_combined_stress"])


def test_the_thesis_dimensions_and_rules(thesis):
    s = thesis.scalars
    assert s["cylinder_pitch"] == 83.0                        # §4.4.1: L = 2h + L1 + L2
    assert s["throw_span"] == 41.5                            # the thesis prints 44.5
    within = {k: s[f"{k}_within_rule"] for k in ("main_journal_diameter", "main_journal_length",
                                                  "crankpin_diameter", "crankpin_length",
                                                  "web_thickness", "web_width")}
    # L2 = 20 mm is 0.227·D (rule 0.25–0.45) and b = 70 mm 0.795·D (rule 0.8–1.2)
    assert within == {"main_journal_diameter": 1, "main_journal_length": 1,
                      "crankpin_diameter": 1, "crankpin_length": 0, "web_thickness": 1,
                      "web_width": 0}


def test_seed_002_fatigue_safety_factor():
    s = crankbook.compute("thesis", fatigue_stress_source=1).scalars
    assert s["fatigue_stress_amplitude"] == 178.45 and s["fatigue_mean_stress"] == 267.65
    assert s["fatigue_safety_factor_bending"] == pytest.approx(1.4812, abs=5e-5)  # printed 1.4813
    assert s["fatigue_safety_factor"] == pytest.approx(s["fatigue_safety_factor_bending"])
    assert s["fatigue_within_band"] == 1


@pytest.mark.parametrize("band_max, verdict", [(1.3, 2), (1.5, 1), (1.4812, 1)])
def test_a_factor_above_the_band_is_heavier_not_failing(band_max, verdict):
    """Above the band the crankshaft is safe but heavier than needed (2), below it is
    unsafe (0): a factor of 120 once read 'outside 不符合' like a failing one."""
    s = crankbook.compute("thesis", fatigue_stress_source=1, fatigue_band_min=1.3,
                          fatigue_band_max=band_max).scalars
    assert s["fatigue_within_band"] == verdict
    below = crankbook.compute("thesis", fatigue_stress_source=1, fatigue_band_min=1.5,
                              fatigue_band_max=1.8).scalars
    assert below["fatigue_within_band"] == 0


def test_fatigue_from_the_series_combines_bending_and_torsion(thesis):
    s, g = thesis.scalars, thesis.series()
    sigma = g["pin_bending_stress"]
    assert s["fatigue_stress_amplitude"] == pytest.approx((sigma.max() - sigma.min()) / 2)
    n_s, n_t = s["fatigue_safety_factor_bending"], s["fatigue_safety_factor_torsion"]
    assert s["fatigue_safety_factor"] == pytest.approx(n_s * n_t / np.hypot(n_s, n_t))


@pytest.mark.parametrize("sets,error,words", [
    ({"crankpin_bore": 48.0}, GeometryError, "bore must be smaller"),
    ({"web_width": 300.0}, GeometryError, r"\(0, 3·bore\]"),
    ({"stress_concentration": 0.0}, ParameterValueError, "stress_concentration"),
    ({"check_throw": 2}, GeometryError, "carries no cylinder"),
])
def test_bad_crankshaft_inputs(sets, error, words):
    with pytest.raises(error, match=words):
        crankbook.compute("thesis", **sets)


def test_stroke_study_of_the_same_stroke_changes_nothing(thesis):
    same = crankbook.compute("thesis", alternative_stroke=100.0)
    g, s = same.series(), same.scalars
    assert np.allclose(g["alt_torque"], g["torque"], rtol=0, atol=1e-9 * g["torque"].abs().max())
    for metric in ("swept_volume", "peak_inertia_force", "peak_side_force", "peak_torque"):
        assert abs(s[f"stroke_study_{metric}_change"]) < 1e-9, metric


def test_stroke_study_of_the_thesis_96_to_100_mm():
    """§4.8.3: the thesis's engine (100 mm) beside the 96 mm it came from, compression
    ratio held by the piston's top land; every row against its closed form."""
    r = crankbook.compute("thesis")
    s, p = r.scalars, r.parameters
    assert (p["alternative_stroke"], p["stroke_study_hold"], p["exact_kinematics"]) == \
        (96.0, "compression_ratio", 0)
    area = np.pi / 4 * 8.8 ** 2                                     # cm²
    assert s["stroke_study_swept_volume"] == pytest.approx(area * 10.0, rel=1e-12)
    assert s["stroke_study_swept_volume_alternative"] == pytest.approx(area * 9.6, rel=1e-12)
    # in the thesis's direction, 96 → 100 mm: +4.17 %, its sign
    assert s["stroke_study_swept_volume_change"] == pytest.approx(100 * 4 / 96, rel=1e-12)
    assert s["stroke_study_compression_ratio_alternative"] == pytest.approx(10.0, rel=1e-12)
    assert s["stroke_study_chamber_volume_alternative"] == pytest.approx(area * 9.6 / 9,
                                                                         rel=1e-12)
    assert s["stroke_study_mean_piston_speed_alternative"] == pytest.approx(0.096 * 5000 / 30)
    assert s["stroke_study_stroke_bore_ratio_alternative"] == pytest.approx(96 / 88)
    # series kinematics, centric: the largest inertia force is at TDC, m_j·r′ω²(1 + λ′)
    omega = 5000 * np.pi / 30
    assert s["stroke_study_peak_inertia_force_alternative"] == pytest.approx(
        s["reciprocating_mass"] * 0.048 * omega ** 2 * (1 + 48 / 150), rel=1e-12)
    assert s["stroke_study_peak_inertia_force"] == pytest.approx(
        s["reciprocating_mass"] * 0.05 * omega ** 2 * (1 + 50 / 150), rel=1e-12)
    # the same p(α) through the 96 mm crank: the mean torque is the work ∮p dV′ over 4π
    # (virtual work: the torque's lever r·sin(ψ+β)/cosβ is dx/dα of the exact slider)
    g = r.series()
    alpha = np.radians(g.index.to_numpy())
    x = 0.048 * (1 - np.cos(alpha)) + 0.150 * (1 - np.cos(np.arcsin(0.32 * np.sin(alpha))))
    work = np.trapezoid(g["cylinder_pressure"].to_numpy() * 1e6, np.pi / 4 * 0.088 ** 2 * x)
    assert s["stroke_study_indicated_power_alternative"] == pytest.approx(
        work / (4 * np.pi) * omega / 1000, rel=2e-3)
    for key in ("swept_volume", "compression_ratio", "mean_piston_speed", "stroke_bore_ratio",
                "peak_inertia_force", "peak_side_force", "peak_torque", "indicated_power",
                "chamber_volume"):
        new, old = s[f"stroke_study_{key}"], s[f"stroke_study_{key}_alternative"]
        assert s[f"stroke_study_{key}_change"] == pytest.approx((new - old) / old * 100,
                                                                 abs=1e-12), key


def test_stroke_study_reads_either_way():
    """The thesis went from 96 to 100 mm; a designer asks what the alternative would
    do: the same two engines, the change read from either end."""
    thesis = crankbook.compute("thesis").scalars
    forward = crankbook.compute("thesis", stroke_study_direction="to_alternative").scalars
    assert forward["stroke_study_swept_volume_change"] == pytest.approx(-4.0, rel=1e-12)
    for key in ("swept_volume", "peak_inertia_force", "peak_side_force", "indicated_power"):
        up, down = thesis[f"stroke_study_{key}_change"], forward[f"stroke_study_{key}_change"]
        assert (1 + up / 100) * (1 + down / 100) == pytest.approx(1, rel=1e-12), key


def test_stroke_study_can_hold_the_chamber_instead():
    s = crankbook.compute("thesis", stroke_study_hold="chamber_volume").scalars
    v_c = np.pi / 4 * 8.8 ** 2 * 10.0 / 9                       # cm³: ε = 10 at 100 mm
    assert s["stroke_study_chamber_volume_alternative"] == pytest.approx(v_c, rel=1e-12)
    assert s["stroke_study_compression_ratio_alternative"] == pytest.approx(
        (np.pi / 4 * 8.8 ** 2 * 9.6 + v_c) / v_c, rel=1e-12)


def test_stroke_study_follows_the_kinematics_choice():
    g = crankbook.compute("thesis", exact_kinematics=1).series()
    assert np.array_equal(g["alt_piston_acceleration"], g["alt_piston_acceleration_exact"])
    g = crankbook.compute("thesis").series()
    assert np.array_equal(g["alt_piston_acceleration"], g["alt_piston_acceleration_series"])


def test_the_crankshaft_inputs_stand_in_the_thesiss_order():
    """§4.4.1 lists D1, L1, D2, L2, h, b: the Parameters sheet too, though the inputs
    come from two libraries (the group's order in the template language)."""
    from crankbook.spec.loader import load
    keys = [p.key for p in load("engine").parameters if p.group == "crankshaft"]
    assert keys[:6] == ["main_journal_diameter", "main_journal_length", "crankpin_diameter",
                        "crankpin_length", "web_thickness", "web_width"]


@pytest.mark.parametrize("inputs", [{"allowable_stress": 0.8}, {"fatigue_limit": 0.495},
                                    {"fatigue_limit_torsion": 0.285}])
def test_a_strength_typed_in_gpa_is_warned(inputs):
    """0.495 (GPa) for σ₋₁ = 495 MPa would make every safety factor a thousand times
    too small without a word."""
    assert_slip_warned("thesis", inputs, "crank_strengths_implausible",
                       "GPa typed into the MPa cell? (495 MPa is typed 495)")
