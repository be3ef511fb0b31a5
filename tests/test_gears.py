"""Profile-shifted timing gears (calc/gears.py) against identities and the worked
report R07 §2.1 of seed 001 (z = 21, 15, 42; m = 4 mm; α = 20°; x2 = 0.11765)."""
import numpy as np
import pytest

from crankbook.calc import gears

ALPHA = np.radians(20.0)


@pytest.fixture(scope="module")
def r07():
    return gears.train([21, 15, 42], [0.0, 0.11765, 0.0], 0.004, ALPHA, 1.0, 0.25)


def test_inverse_involute_inverts(r07):
    angles = np.radians([14.5, 20.0, 20.98, 25.0, 35.0])
    assert np.allclose(gears.inverse_involute(gears.involute(angles)), angles, rtol=0,
                       atol=1e-14)


def test_working_centre_distance_both_ways(r07):
    # a′ from α′, and α′ back from a′: a′·cos α′ = a·cos α
    assert np.allclose(r07["a_w"] * np.cos(r07["alpha_w"]), r07["a"] * np.cos(ALPHA))


def test_contact_ratio_is_the_path_of_contact_over_the_base_pitch(r07):
    # ε = (√(ra1² − rb1²) + √(ra2² − rb2²) − a′·sin α′)/(π·m·cos α)
    ra, rb = r07["da"] / 2, r07["db"] / 2
    path = np.sqrt(ra[:-1] ** 2 - rb[:-1] ** 2) + np.sqrt(ra[1:] ** 2 - rb[1:] ** 2) \
        - r07["a_w"] * np.sin(r07["alpha_w"])
    assert np.allclose(r07["epsilon"], path / (np.pi * 0.004 * np.cos(ALPHA)))


def test_worked_report_r07(r07):
    mm = 1000.0
    assert np.degrees(r07["alpha_w"][0]) == pytest.approx(20.98, abs=0.005)
    assert r07["a_w"][0] * mm == pytest.approx(72.45975, abs=2e-5)
    assert r07["y"][0] == pytest.approx(0.11493, abs=1e-5)
    assert r07["dy"][0] == pytest.approx(0.002713, abs=5e-6)    # R07 rounds α′ to 0.01°
    # R07 prints a′23 = 114.46236; its own inputs give 114.4636 (a finding for the audit)
    assert r07["a_w"][1] * mm == pytest.approx(114.4636, abs=1e-4)
    assert r07["epsilon"][0] == pytest.approx(1.48092, abs=1e-4)
    assert r07["epsilon"][1] == pytest.approx(1.55683, abs=1e-3)
    assert r07["ha"][1] * mm == pytest.approx(4.45974, abs=1e-4)     # the idler: larger Δy
    assert r07["da"][0] * mm == pytest.approx(91.9783, abs=1e-3)
    assert r07["df"][1] * mm == pytest.approx(50.94118, abs=1e-4)
    assert r07["db"][0] * mm == pytest.approx(78.934, abs=1e-3)
    # R07's tip thickness of the idler, 2.02356 mm, leaves out the shift's 2xm·tan α in s:
    # with it the idler's tip is 2.417 mm thick (a finding for the audit)
    s_unshifted = gears.tip_thickness(np.pi * 0.004 / 2, r07["d"][1], r07["da"][1], ALPHA,
                                      r07["alpha_a"][1])
    assert s_unshifted * mm == pytest.approx(2.02356, abs=1e-2)
    assert r07["s_a"][1] * mm == pytest.approx(2.417, abs=1e-3)


def test_minimum_shift_avoids_undercut():
    assert gears.minimum_shift(15, 1.0) == pytest.approx(2 / 17)
    assert gears.minimum_shift(20, 1.0) == 0.0


@pytest.mark.parametrize("teeth,shift", [(21, 0.0), (15, 0.11765), (42, 0.0), (30, -0.3)])
def test_base_tangent_span_touches_the_flanks_near_the_reference_circle(teeth, shift):
    # the calliper touches the flanks where the involute's roll angle is W/r_b: that
    # diameter lies between root and tip, near the reference circle
    g = gears.train([teeth, teeth], [shift, shift], 1.0, ALPHA, 1.0, 0.25)
    rb = g["db"][0] / 2
    touch = 2 * np.hypot(rb, g["W"][0] / 2)
    assert g["df"][0] < touch < g["da"][0]
    # and a shift widens the span by 2xm·sin α
    plain = gears.base_tangent_length(teeth, 0.0, 1.0, ALPHA, g["k"][0])
    assert g["W"][0] - plain == pytest.approx(2 * shift * np.sin(ALPHA))
