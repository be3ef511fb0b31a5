"""Forces: the thesis's masses, torque = F·v/ω, and virtual work over the cycle."""
import numpy as np
import pytest

from crankbook.calc import cycle, forces, kinematics as k, pressure as p
from crankbook.spec import evaluate
from crankbook.spec import params
from tests.conftest import assert_slip_warned


def test_thesis_reciprocating_mass_is_515_g():
    # thesis §3.2.2: piston group 316 g, rod 328 g, m_j = 515 g (to the gram)
    spec, values, _ = params.load_preset("thesis")
    m_j = forces.reciprocating_mass(values["piston_mass"], values["rod_mass"],
                                    values["rod_cg_from_big_end"] / 1000,
                                    values["rod_length"] / 1000)
    assert m_j == pytest.approx(0.515, abs=0.0005)


def test_two_mass_rod_keeps_the_rod_mass():
    m1 = forces.small_end_mass(0.328, 0.091, 0.150)
    m_r = forces.rotating_mass(0.0, 0.328, 0.091, 0.150)
    assert m1 + m_r == pytest.approx(0.328)
    # the centre of gravity is kept: m1·(l − l_cg) = m2·l_cg
    assert m1 * (0.150 - 0.091) == pytest.approx(m_r * 0.091)


@pytest.mark.parametrize("offset", [0.0, 0.015])
def test_torque_equals_force_times_velocity_over_omega(offset):
    r, l, w = 0.05, 0.16, 400.0
    alpha = np.linspace(0, 4 * np.pi, 1441)
    force = 20000 * np.sin(alpha / 2) ** 2 - 3000      # any force history
    psi = k.crank_angle_from_axis(alpha, r, l, offset)
    beta = k.rod_angle(alpha, r, l, offset)
    torque = forces.torque(forces.tangential_force(force, psi, beta), r)
    v = k.piston_velocity_exact(alpha, r, l, offset, w)
    assert np.allclose(torque, force * v / w, atol=1e-9 * np.abs(torque).max())


def test_force_components_close_the_triangle():
    r, l = 0.05, 0.15
    alpha = np.linspace(0, 4 * np.pi, 721)
    psi, beta = k.crank_angle_from_axis(alpha, r, l, 0), k.rod_angle(alpha, r, l, 0)
    f = np.full_like(alpha, 1000.0)
    rod = forces.rod_force(f, beta)
    assert np.allclose(rod ** 2, f ** 2 + forces.side_force(f, beta) ** 2)
    assert np.allclose(rod ** 2, forces.tangential_force(f, psi, beta) ** 2
                       + forces.radial_force(f, psi, beta) ** 2)


def test_virtual_work_mean_torque_times_omega_is_indicated_power():
    """∮M dα = ∮(p − p0) dV: the mean torque gives the indicated work per cycle."""
    spec, values, _ = params.load_preset("thesis")
    values = params.validate(spec, values)
    grid = evaluate.crank_angle_grid(spec, 0.25)
    out = evaluate.evaluate(spec, values, {}, grid)
    work_from_torque = out["mean_torque"] * 4 * np.pi                        # J per cycle
    work_from_pressure = cycle.indicated_work(out["cylinder_pressure"] * 1e6,
                                              out["cylinder_volume"] * 1e-6)
    assert work_from_torque == pytest.approx(work_from_pressure, rel=2e-3)
    # and the workbook's own formulas for the same quantities
    assert out["indicated_work"] == pytest.approx(work_from_pressure, rel=1e-12)
    assert out["indicated_power"] == pytest.approx(
        work_from_pressure * values["speed"] / 120 / 1000, rel=2e-3)


def test_inertia_torque_averages_to_zero():
    r, l, w, m = 0.05, 0.15, 500.0, 0.5
    alpha = np.linspace(0, 4 * np.pi, 1441)
    a = k.piston_acceleration_exact(alpha, r, l, 0.0, w)
    psi, beta = k.crank_angle_from_axis(alpha, r, l, 0), k.rod_angle(alpha, r, l, 0)
    torque = forces.torque(forces.tangential_force(forces.inertia_force(m, a), psi, beta), r)
    assert abs(cycle.cycle_mean(torque)) < 1e-9 * np.abs(torque).max()


def test_pressure_model_is_plausible_for_the_thesis_engine():
    spec, values, _ = params.load_preset("thesis")
    values = params.validate(spec, values)
    grid = evaluate.crank_angle_grid(spec)
    out = evaluate.evaluate(spec, values, {}, grid)
    assert 3.0 < out["cylinder_pressure_max"] < 9.0                  # a few MPa
    assert 360 < out["cylinder_pressure_max_angle"] < 400            # shortly after firing TDC
    xb = out["burned_fraction"]
    assert np.all(np.diff(xb) >= 0) and xb.min() == 0 and xb.max() <= 1
    # compression is continuous where the intake stroke ends
    assert out["model_pressure"][180] == pytest.approx(values["intake_pressure"], rel=1e-12)


def test_trace_interpolation_matches_numpy_interp():
    angles = np.array([-10.0, 0.0, 100.0, 400.0, 730.0])
    pressures = np.array([0.2, 0.1, 0.3, 5.0, 0.2])
    x = np.linspace(0, 720, 97)
    assert np.allclose(p.trace_pressure(x, angles, pressures), np.interp(x, angles, pressures))
    assert np.isnan(p.trace_pressure(x, angles[:1], pressures[:1])).all()


@pytest.mark.parametrize("inputs,flag,words", [
    ({"crank_radius": 0.045}, "stroke_bore_implausible", "a length in m typed into an mm cell"),
    ({"heat_released": 20000.0}, "peak_pressure_implausible", "above 40 MPa"),
])
def test_a_length_in_metres_or_a_heat_tenfold_is_warned(inputs, flag, words):
    """A crank radius of 0.045 (m for 45 mm) made a 0.09 mm stroke and a 4,596 MPa peak
    pressure without a word; ten times the heat gives 56 MPa.  Both now warn."""
    assert_slip_warned("thesis", inputs, flag, words)
