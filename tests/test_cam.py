"""Cam motion laws and the offset roller follower (calc/cam.py) against boundary
conditions, finite differences, geometry, and the worked report R07 of seed 001."""
import numpy as np
import pytest

from crankbook.calc import cam

RISE, DWELL, RETURN = np.radians(50.0), np.radians(10.0), np.radians(50.0)


@pytest.mark.parametrize("law", range(1, 6))
def test_each_law_starts_at_rest_and_ends_at_the_lift(law):
    f, df, _ = cam.law_shape(np.array([0.0, 1.0]), law)
    assert f[0] == 0 and f[1] == pytest.approx(1.0)
    if law != 1:                                   # constant velocity jumps in speed
        assert df[0] == pytest.approx(0.0, abs=1e-12) and df[1] == pytest.approx(0, abs=1e-12)


def away_from_joints(delta, margin=np.radians(1.0)):
    """Cam angles more than ``margin`` from where two pieces (or law halves) meet."""
    joints = np.array([0.0, RISE / 2, RISE, RISE + DWELL, RISE + DWELL + RETURN / 2,
                       RISE + DWELL + RETURN, 2 * np.pi])
    return np.min(np.abs(delta[:, None] - joints[None, :]), axis=1) > margin


@pytest.mark.parametrize("law", range(1, 6))
def test_derivatives_are_finite_differences_of_the_displacement(law):
    delta = np.linspace(0.0, 2 * np.pi, 36001)
    s, ds, dds = cam.follower_derivatives(delta, 0.008, RISE, DWELL, RETURN, law, law)
    h = delta[1] - delta[0]
    inside = away_from_joints(delta)
    assert np.allclose(ds[inside], np.gradient(s, h)[inside], atol=1e-8)
    assert np.allclose(dds[inside], np.gradient(ds, h)[inside], atol=1e-6)


def test_pitch_curve_radius_and_pressure_angle_are_the_geometry():
    delta = np.linspace(0, 2 * np.pi, 7201)
    e, r0 = 0.005, 0.035
    s, ds, dds = cam.follower_derivatives(delta, 0.008, RISE, DWELL, RETURN, 3, 3)
    x, y = cam.pitch_curve(delta, s, e, r0, 1)
    s0 = np.sqrt(r0 ** 2 - e ** 2)
    assert np.allclose(np.hypot(x, y), np.hypot(s0 + s, e))
    # pressure angle: the angle between the follower's path (the y axis turned by δ)
    # and the normal of the pitch curve, from the tangent of the curve
    x1, y1 = np.gradient(x, delta), np.gradient(y, delta)
    normal = np.array([y1, -x1]) / np.hypot(x1, y1)
    geometric = np.arcsin(np.clip(np.abs(np.sum(normal * np.array(
        [np.cos(delta), -np.sin(delta)]), axis=0)), 0, 1))
    inside = away_from_joints(delta)
    assert np.allclose(np.abs(cam.pressure_angle(s, ds, e, r0))[inside], geometric[inside],
                       atol=1e-5)


def test_curvature_of_a_dwell_is_its_radius():
    delta = np.linspace(np.radians(70), np.radians(100), 5)
    s, ds, dds = cam.follower_derivatives(delta, 0.008, RISE, DWELL, RETURN, 3, 3)
    rho = cam.pitch_curvature_radius(delta, s, ds, dds, 0.0, 0.035)
    dwell = cam.piece(delta, RISE, DWELL, RETURN) == 3
    assert np.allclose(rho[dwell], 0.035)


def test_curvature_against_a_numerical_one():
    delta = np.linspace(0, 2 * np.pi, 36001)
    e, r0 = 0.005, 0.035
    s, ds, dds = cam.follower_derivatives(delta, 0.008, RISE, DWELL, RETURN, 4, 5)
    x, y = cam.pitch_curve(delta, s, e, r0, 1)
    x1, y1 = np.gradient(x, delta), np.gradient(y, delta)
    x2, y2 = np.gradient(x1, delta), np.gradient(y1, delta)
    numeric = -(x1 * y2 - y1 * x2) / (x1 ** 2 + y1 ** 2) ** 1.5          # curvature 1/ρ
    exact = 1 / cam.pitch_curvature_radius(delta, s, ds, dds, e, r0)
    inside = away_from_joints(delta)
    assert np.allclose(exact[inside], numeric[inside], rtol=0, atol=1e-4 * np.abs(exact).max())


def test_worked_report_r07_cam():
    # R07 §2.2: cosine rise and return of h = 8 mm over 50° each, e = 5 mm, r0 = 35 mm,
    # the camshaft at half the crank's 68.068 rad/s
    omega = cam.cam_angular_velocity(68.068, 2.0)
    assert omega == pytest.approx(34.034)
    delta = np.linspace(0, RISE, 2001)
    s, ds, dds = cam.follower_derivatives(delta, 0.008, RISE, DWELL, RETURN, 3, 3)
    assert np.max(dds) * omega ** 2 * 1000 == pytest.approx(60047, rel=2e-4)   # mm/s²
    x, y = cam.pitch_curve(np.array([RISE + DWELL / 2]), np.array([0.008]), 0.005, 0.035, 1)
    assert np.hypot(x, y)[0] * 1000 == pytest.approx(42.933, abs=5e-4)       # far dwell
    assert np.sqrt(0.035 ** 2 - 0.005 ** 2) * 1000 == pytest.approx(34.641, abs=5e-4)


def test_required_base_radius_meets_the_allowed_pressure_angle():
    delta = np.linspace(0, 2 * np.pi, 3601)
    s, ds, _ = cam.follower_derivatives(delta, 0.008, RISE, DWELL, RETURN, 4, 4)
    r0 = cam.required_base_radius(s, ds, 0.005, np.radians(30)).max()
    alpha = np.abs(cam.pressure_angle(s, ds, 0.005, r0))
    assert alpha.max() == pytest.approx(np.radians(30), abs=1e-6)
