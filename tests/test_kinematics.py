"""Kinematics against the seeds' stated values, finite differences and identities."""
import numpy as np
import pytest

from crankbook.calc import kinematics as k

R, L, W = 0.050, 0.150, 5000 * np.pi / 30        # the thesis engine (§3.1.2, §3.1.3)
ALPHA = np.linspace(0, 4 * np.pi, 2001)


def test_thesis_crank_rod_ratio_is_one_third():
    # thesis §3.1.2: λ = r/l = 50 mm / 150 mm = 1/3
    assert k.crank_rod_ratio(R, L) == pytest.approx(1 / 3, rel=1e-15)


@pytest.mark.parametrize("offset", [0.0, 0.012, -0.02])
def test_velocity_and_acceleration_are_time_derivatives(offset):
    h = 1e-6
    for f, df in ((k.piston_displacement_exact, k.piston_velocity_exact),
                  (k.piston_velocity_exact, k.piston_acceleration_exact)):
        args = (R, L, offset) if f is k.piston_displacement_exact else (R, L, offset, W)
        numeric = (f(ALPHA + h, *args) - f(ALPHA - h, *args)) / (2 * h) * W
        exact = df(ALPHA, R, L, offset, W)
        assert np.max(np.abs(numeric - exact)) < 1e-6 * np.max(np.abs(exact))


def test_series_derivatives_and_orders():
    h = 1e-6
    numeric = (k.piston_displacement_series(ALPHA + h, R, L)
               - k.piston_displacement_series(ALPHA - h, R, L)) / (2 * h) * W
    assert np.allclose(numeric, k.piston_velocity_series(ALPHA, R, L, W), atol=1e-6)
    numeric = (k.piston_velocity_series(ALPHA + h, R, L, W)
               - k.piston_velocity_series(ALPHA - h, R, L, W)) / (2 * h) * W
    assert np.allclose(numeric, k.piston_acceleration_series(ALPHA, R, L, W), rtol=1e-6,
                       atol=1e-3)


def test_series_approximates_exact_to_third_order_in_lambda():
    # x_exact − x_series = l·(1 − λ²sin²α/2 − √(1 − λ²sin²α)) ≈ lλ⁴sin⁴α/8 ≥ 0
    diff = k.piston_displacement_exact(ALPHA, R, L, 0.0) - k.piston_displacement_series(ALPHA, R, L)
    lam = R / L
    assert diff.min() >= -1e-15
    assert diff.max() == pytest.approx(L * lam ** 4 / 8, rel=0.1)


def test_centric_extremes():
    # TDC: a = rω²(1 + λ); BDC: a = −rω²(1 − λ); stroke 2r
    assert k.piston_acceleration_exact(0.0, R, L, 0.0, W) == pytest.approx(R * W**2 * (1 + R / L))
    assert k.piston_acceleration_exact(np.pi, R, L, 0.0, W) == pytest.approx(-R * W**2 * (1 - R / L))
    assert k.piston_displacement_exact(np.pi, R, L, 0.0) == pytest.approx(2 * R)
    assert k.stroke(R, L, 0.0) == pytest.approx(2 * R)


@pytest.mark.parametrize("offset", [0.01, -0.015])
def test_offset_tdc_is_zero_displacement_and_velocity(offset):
    assert k.piston_displacement_exact(0.0, R, L, offset) == pytest.approx(0, abs=1e-15)
    assert k.piston_velocity_exact(0.0, R, L, offset, W) == pytest.approx(0, abs=1e-9)
    # the largest displacement over a revolution is the stroke formula
    s = k.piston_displacement_exact(np.linspace(0, 2 * np.pi, 200001), R, L, offset)
    assert s.max() == pytest.approx(k.stroke(R, L, offset), rel=1e-9)


def test_seed_003_velocity_formula_lacks_r():
    # seed 003 prints v = ω[r·tanβ·cosψ + sinψ]; the derivative is ω·r·[tanβ·cosψ + sinψ].
    offset = 0.01
    psi = k.crank_angle_from_axis(ALPHA, R, L, offset)
    beta = k.rod_angle(ALPHA, R, L, offset)
    printed = W * (R * np.tan(beta) * np.cos(psi) + np.sin(psi))
    derived = W * R * (np.tan(beta) * np.cos(psi) + np.sin(psi))
    assert np.allclose(derived, k.piston_velocity_exact(ALPHA, R, L, offset, W), atol=1e-12)
    assert not np.allclose(printed, derived, rtol=0.1)


def test_choose_switch():
    assert list(k.choose(1, np.array([1.0, 2.0]), np.array([3.0, 4.0]))) == [1.0, 2.0]
    assert list(k.choose(0, np.array([1.0, 2.0]), np.array([3.0, 4.0]))) == [3.0, 4.0]
