"""IACS UR M53 crankshaft fatigue (issue 43): the rule's factors against a second,
independent transcription (coefficient tables, evaluated by Horner's scheme), the
fatigue strength against hand arithmetic, the throw's statics against a hand
calculation, the workbook's three places and bad inputs."""
import math

import numpy as np
import pytest

import crankbook
from crankbook.calc import crankshaft_m53 as m53
from tests.conftest import assert_build_refused_in_one_line

# ---------------------------------------------------------------- a second transcription
# UR M53 §3: each factor a product of fits; polynomials as coefficient lists from the
# constant term up.
PIN_B = {"c": 2.6914,
         "sw": ([-4.1883, 29.2004, -77.5925, 91.9454, -40.0416],
                [9.5440, -58.3480, 159.3415, -192.5846, 85.2916],
                [-3.8399, 25.0444, -70.5571, 87.0328, -39.1832]),
         "w": (2.1790, 0.7171), "b": [0.6840, -0.0077, 0.1473], "r": (0.2081, -0.5231),
         "dG": [0.9993, 0.27, -1.0211, 0.5306], "dH": [0.9978, 0.3145, -1.5241, 2.4147]}
JOURNAL_B = {"c": 2.7146,
             "sw": ([-1.7625, 2.9821, -1.5276], [5.1169, -5.8089, 3.1391],
                    [-2.1567, 2.3297, -1.2952]),
             "w": (2.2422, 0.7548), "b": [0.5616, 0.1197, 0.1176], "r": (0.1908, -0.5568),
             "dG": [1.0012, -0.6441, 1.2265], "dH": [1.0022, -0.1903, 0.0073]}


def horner(coefficients, x):
    total = 0.0
    for c in reversed(coefficients):
        total = total * x + c
    return total


def bending(table, r, s, w, b, dG, dH, tH, tG):
    s = -0.5 if s < -0.5 else s
    sw = sum(horner(row, w) * (1 - s) ** i for i, row in enumerate(table["sw"]))
    return (table["c"] * sw * table["w"][0] * w ** table["w"][1] * horner(table["b"], b)
            * table["r"][0] * r ** table["r"][1] * horner(table["dG"], dG)
            * horner(table["dH"], dH) * (1 + (tH + tG) * (1.8 + 3.2 * s)))


def torsion(r, s, w, b):
    s = -0.5 if s < -0.5 else s
    return (0.8 * r ** (-(0.322 + 0.1015 * (1 - s))) * horner([7.8955, -10.654, 5.3482, -0.857], b)
            * w ** -0.145)


def shear(r, s, w, b, dH, tH, tG):
    s = -0.5 if s < -0.5 else s
    return (3.0128 * horner([0.4368, 2.1630, -1.5212], 1 - s) * w / (0.0637 + 0.9369 * w)
            * (b - 0.5) * 0.5331 * r ** -0.2038 * horner([0.9937, -1.1949, 1.7373], dH)
            * (1 + (tH + tG) * (1.8 + 3.2 * s)))


GEOMETRIES = [   # r_H, r_G, s, w, b, d_O, d_G, d_H, t_H, t_G
    (0.05, 0.05, 0.10, 0.30, 1.60, 0.10, 0.00, 0.00, 0.00, 0.00),
    (0.04, 0.06, -0.20, 0.45, 1.30, 0.15, 0.30, 0.40, 0.00, 0.00),
    (0.08, 0.035, 0.35, 0.25, 2.00, 0.05, 0.60, 0.20, 0.02, 0.01),   # bores and recesses
    (0.02, 0.05, -0.70, 0.90, 1.00, 0.25, 0.00, 0.00, 0.00, 0.00),   # outside every range
]


@pytest.mark.parametrize("g", GEOMETRIES)
def test_the_factors_against_a_second_transcription(g):
    rH, rG, s, w, b, dO, dG, dH, tH, tG = g
    assert m53.alpha_b(rH, s, w, b, dG, dH, tH, tG) == pytest.approx(
        bending(PIN_B, rH, s, w, b, dG, dH, tH, tG), rel=1e-12)
    assert m53.beta_b(rG, s, w, b, dG, dH, tH, tG) == pytest.approx(
        bending(JOURNAL_B, rG, s, w, b, dG, dH, tH, tG), rel=1e-12)
    assert m53.beta_q(rG, s, w, b, dH, tH, tG) == pytest.approx(
        shear(rG, s, w, b, dH, tH, tG), rel=1e-12)
    assert m53.alpha_t(rH, s, w, b) == pytest.approx(torsion(rH, s, w, b), rel=1e-12)
    assert m53.beta_t(rG, s, w, b) == pytest.approx(torsion(rG, s, w, b), rel=1e-12)
    assert m53.gamma_b(dO) == pytest.approx(3 - 5.88 * dO + 34.6 * dO ** 2, rel=1e-12)
    assert m53.gamma_t(dO) == pytest.approx(4 - 6 * dO + 30 * dO ** 2, rel=1e-12)
    inside = (0.03 <= rH <= 0.13 and 0.03 <= rG <= 0.13 and s <= 0.5 and 0.2 <= w <= 0.8
              and 1.1 <= b <= 2.2 and 0 <= dO <= 0.2 and 0 <= dG <= 0.8 and 0 <= dH <= 0.8)
    assert m53.validity(rH, rG, s, w, b, dO, dG, dH) == float(inside)


def test_plain_values_a_reader_can_redo():
    """A plain throw (s = 0, w = 0.3, b = 1.5, r = 0.05, no bores or recesses) by
    hand: the fits' factors one by one."""
    f_sw = (-4.1883 + 29.2004 * .3 - 77.5925 * .09 + 91.9454 * .027 - 40.0416 * .0081
            + 9.5440 - 58.3480 * .3 + 159.3415 * .09 - 192.5846 * .027 + 85.2916 * .0081
            - 3.8399 + 25.0444 * .3 - 70.5571 * .09 + 87.0328 * .027 - 39.1832 * .0081)
    by_hand = (2.6914 * f_sw * 2.1790 * 0.3 ** 0.7171 * (0.6840 - 0.0077 * 1.5 + 0.1473 * 2.25)
               * 0.2081 * 0.05 ** -0.5231 * 0.9993 * 0.9978)
    assert m53.alpha_b(0.05, 0.0, 0.3, 1.5, 0, 0, 0, 0) == pytest.approx(by_hand, rel=1e-12)
    assert 2.0 < by_hand < 4.0          # the range FVV's measured crankpin fillets span


@pytest.mark.parametrize("d,r,sigma,k", [
    (100.0, 5.0, 800.0, 1.0), (60.0, 3.0, 700.0, 1.05), (250.0, 12.0, 950.0, 0.93),
    (45.0, 2.0, 1100.0, 1.0)])
def test_the_fatigue_strength_is_the_rules_formula(d, r, sigma, k):
    want = k * (0.42 * sigma + 39.3) * (0.264 + 1.073 * d ** -0.2 + (785 - sigma) / 4900
                                        + 196 / sigma * math.sqrt(1 / r))
    got = m53.fatigue_strength(sigma * 1e6, d / 1e3, r / 1e3, k) / 1e6
    assert got == pytest.approx(want, rel=1e-12)


def test_the_fatigue_strength_of_one_case_by_hand():
    """D = 100 mm, R_X = 5 mm, σ_B = 800 MPa, K = 1: 375.3 × (0.264 + 0.427169
    − 0.003061 + 0.109567) = 299.37 MPa."""
    assert m53.fatigue_strength(800e6, 0.1, 0.005, 1.0) / 1e6 == pytest.approx(299.37, abs=0.01)


def test_the_throws_statics_by_hand():
    """F_R = 10 kN, F_T = 4 kN on a throw with L1 = 40, L2 = 60, L3 = 120 mm, the oil
    bore at ψ = 30°: the web carries 10 000 × 0.04 × 60/120 = 200 N·m and 5 kN, the
    pin's centre (4000·cos 30° + 10 000·sin 30°) × 0.06 × 0.06/0.12 = 253.92 N·m."""
    assert m53.web_moment(10e3, 0.04, 0.06, 0.12) == pytest.approx(200.0)
    assert m53.web_shear(10e3, 0.06, 0.12) == pytest.approx(5000.0)
    assert m53.oil_bore_moment(4e3, 10e3, 0.06, 0.12, math.radians(30)) == pytest.approx(
        253.923, abs=1e-3)
    # over a cycle the rule takes half the range
    assert m53.alternating(m53.web_moment([-2e3, 10e3, 4e3], 0.04, 0.06, 0.12)) == \
        pytest.approx(120.0)


def _values(r, key):
    return np.asarray(r[key], dtype=float)


def test_an_inline_six_reads_its_three_places():
    """The inline-6 as an engineer reads it: three Q's, each σ_DW/σ_v of the sheet's
    printed intermediates, σ_v rebuilt from the printed factors and nominal stresses,
    and M_TN the larger forced-response torque of the sections beside the throw."""
    r = crankbook.compute("inline-6")
    q = _values(r, "m53_acceptability")
    assert q.shape == (3,) and np.isfinite(q).all()
    sigma_v = _values(r, "m53_equivalent_stress")
    assert np.allclose(q, _values(r, "m53_fatigue_strength") / sigma_v)
    pin = math.hypot(float(r["m53_alpha_b"]) * float(r["m53_nominal_bending"])
                     + float(r.parameters["additional_bending_stress"]),
                     math.sqrt(3) * float(r["m53_alpha_t"]) * float(r["m53_nominal_torsion_pin"]))
    assert sigma_v[0] == pytest.approx(pin, rel=1e-9)
    throw = int(r.parameters["check_throw"])
    beside = _values(r, "alternating_torque_journal")[throw - 1:throw + 1]
    assert float(r["m53_alternating_torque"]) == pytest.approx(np.nanmax(beside))
    assert float(r["m53_ok"]) == float(q.min() >= 1.15 and r["m53_within_validity"] == 1)
    assert float(r["m53_acceptability_min"]) == pytest.approx(q.min())
    # a typed M_TN replaces the response's
    typed = crankbook.compute("inline-6", alternating_torque_typed=1234.0)
    assert float(typed["m53_alternating_torque"]) == 1234.0
    assert float(typed["m53_torque_from_response"]) == 0.0


def test_a_ratio_out_of_range_is_named_and_fails_the_rule():
    """A fillet of 1 mm on the inline-6's pin (r < 0.03): the factors are still shown,
    but the rule is not passed, and the Summary's status says which ratio."""
    with pytest.warns(UserWarning, match="fillet ratio r = R/D is outside 0.03–0.13"):
        r = crankbook.compute("inline-6", pin_fillet_radius=1.0)
    assert float(r["m53_fillet_out"]) == 1.0
    assert float(r["m53_within_validity"]) == 0.0 and float(r["m53_ok"]) == 0.0
    assert np.isfinite(float(r["m53_alpha_b"]))


@pytest.mark.parametrize("values,words", [
    (["fillet_radius=0"], "fillet_radius"),
    (["tensile_strength=300"], "tensile_strength"),
    (["oil_bore_diameter=80"], "oil bore must be narrower"),
    (["m53_l2_typed=90", "m53_l3_typed=80"], "L2 must be shorter than L3"),
])
def test_bad_m53_inputs_are_one_line(tmp_path, values, words):
    assert_build_refused_in_one_line(tmp_path, "inline-6", values, words)
