"""Course-design mechanism: synthesis against seed 003, finite differences and the
virtual-work identity of the kinetostatic analysis."""
import numpy as np
import pytest

from crankbook.calc import kinematics as k, mechanism as m

H, K = 0.152, 1.2


def test_synthesis_reproduces_seed_003_optimum():
    # seed 003 §四: X = [71.9797, 185.8900, 54.4448] from H = 152 mm, K = 1.2
    e = 0.0544448
    assert m.crank_radius_from_design(H, e, K) * 1000 == pytest.approx(71.9797, abs=2e-4)
    assert m.rod_length_from_design(H, e, K) * 1000 == pytest.approx(185.8900, abs=2e-4)


@pytest.mark.parametrize("stroke,offset,ratio", [(0.3, 0.05, 1.05), (0.152, 0.0544448, 1.2),
                                                 (0.36, 0.06, 1.08)])
def test_synthesised_mechanism_has_the_stroke_and_time_ratio(stroke, offset, ratio):
    r = m.crank_radius_from_design(stroke, offset, ratio)
    l = m.rod_length_from_design(stroke, offset, ratio)
    assert k.stroke(r, l, offset) == pytest.approx(stroke, rel=1e-12)
    lowest = m.lowest_position_angle(r, l, offset)
    # downstroke takes π + θ, upstroke π − θ: K = (π + θ)/(π − θ)
    assert lowest / (2 * np.pi - lowest) == pytest.approx(ratio, rel=1e-12)
    assert lowest - np.pi == pytest.approx(m.extreme_angle(ratio), rel=1e-12)
    phi = np.linspace(0, 2 * np.pi, 400001)
    s = k.piston_displacement_exact(phi, r, l, offset)
    assert phi[np.argmax(s)] == pytest.approx(lowest, abs=2e-5)


def test_newton_finds_the_maximum_speed_positions():
    r, l, e, w = 0.1404, 0.4933, 0.05, 610 * np.pi / 30
    for upstroke in (False, True):
        start = m.max_speed_start(r, l, e, upstroke)
        root = m.newton_iterates(np.arange(7), start, r, l, e, w)[-1]
        assert k.piston_acceleration_exact(root, r, l, e, w) == pytest.approx(0, abs=1e-9)
        phi = np.linspace(root - 0.3, root + 0.3, 600001)
        v = np.abs(k.piston_velocity_exact(phi, r, l, e, w))
        assert phi[np.argmax(v)] == pytest.approx(root, abs=2e-6)


@pytest.mark.parametrize("e", [0.0, 0.05])
def test_rod_angular_motion_by_finite_differences(e):
    r, l, w, h = 0.14, 0.49, 64.0, 1e-6
    phi = np.linspace(0, 4 * np.pi, 997)
    beta = lambda x: k.rod_angle(x, r, l, e)  # noqa: E731
    # ω2 is dθ2/dt with θ2 = 90° + β measured counter-clockwise
    numeric = (beta(phi + h) - beta(phi - h)) / (2 * h) * w
    assert np.allclose(numeric, m.rod_angular_velocity(phi, r, l, e, w), atol=1e-6)
    numeric = (m.rod_angular_velocity(phi + h, r, l, e, w)
               - m.rod_angular_velocity(phi - h, r, l, e, w)) / (2 * h) * w
    assert np.allclose(numeric, m.rod_angular_acceleration(phi, r, l, e, w), atol=1e-4)
    numeric = (k.piston_acceleration_exact(phi + h, r, l, e, w)
               - k.piston_acceleration_exact(phi - h, r, l, e, w)) / (2 * h)
    assert np.allclose(numeric, m.acceleration_slope(phi, r, l, e, w), atol=1e-3)


def test_rod_cg_velocity_is_the_derivative_of_its_position():
    r, l, e, w, kk, h = 0.14, 0.49, 0.05, 64.0, 0.35, 1e-6
    phi = np.linspace(0, 4 * np.pi, 501)

    def position(x):
        psi = k.crank_angle_from_axis(x, r, l, e)
        beta = k.rod_angle(x, r, l, e)
        ax, ay = r * np.sin(psi), r * np.cos(psi)
        by = ay + l * np.cos(beta)
        return ax + kk * (e - ax), ay + kk * (by - ay)

    (x1, y1), (x0, y0) = position(phi + h), position(phi - h)
    psi = k.crank_angle_from_axis(phi, r, l, e)
    v = k.piston_velocity_exact(phi, r, l, e, w)
    assert np.allclose((x1 - x0) / (2 * h) * w, m.rod_cg_velocity_x(psi, r, w, kk), atol=1e-6)
    assert np.allclose((y1 - y0) / (2 * h) * w, m.rod_cg_velocity_y(psi, r, w, kk, v), atol=1e-6)


def kinetostatics(phi, r=0.1404, l=0.4933, e=0.05, w=610 * np.pi / 30, kk=0.35, rho=0.2,
                  q1=160.0, q2=130.0, q3=200.0, c1=0.25, g=9.81, gas=None):
    """Everything the virtual-work test needs, straight from calc."""
    gas = 40000 * np.exp(-((phi - 2.2 * np.pi) / 0.5) ** 2) if gas is None else gas
    m2, m3 = q2 / g, q3 / g
    psi = k.crank_angle_from_axis(phi, r, l, e)
    beta = k.rod_angle(phi, r, l, e)
    v = k.piston_velocity_exact(phi, r, l, e, w)
    a = k.piston_acceleration_exact(phi, r, l, e, w)
    w2 = m.rod_angular_velocity(phi, r, l, e, w)
    a2 = m.rod_angular_acceleration(phi, r, l, e, w)
    acx, acy = m.rod_cg_acceleration_x(psi, r, w, kk), m.rod_cg_acceleration_y(psi, r, w, kk, a)
    vcx, vcy = m.rod_cg_velocity_x(psi, r, w, kk), m.rod_cg_velocity_y(psi, r, w, kk, v)
    f3 = m.piston_load(gas, q3, m3, a)
    f2x, f2y = m.rod_load_x(m2, acx), m.rod_load_y(m2, acy, q2)
    m2_ = m.rod_inertia_moment(m2, rho * l, a2)
    r03 = m.wall_reaction(beta, l, kk, f2x, f2y, f3, m2_)
    r12x, r12y = m.crank_pin_force_x(f2x, r03), m.crank_pin_force_y(f2y, f3)
    mb = m.balancing_torque(psi, r, r12x, r12y, q1, c1 * r)
    # power of every applied load (gas, gravity, inertia) at its point of application
    crank_cg_vy = -c1 * r * w * np.sin(psi)
    power = f3 * (-v) + f2x * vcx + f2y * vcy + m2_ * w2 + (-q1) * crank_cg_vy
    return mb, power, w, (r03, r12x, r12y, f2x, f2y, f3, beta, psi)


def test_balancing_torque_obeys_virtual_work():
    phi = np.linspace(0, 4 * np.pi, 1441)
    mb, power, w, _ = kinetostatics(phi)
    assert np.allclose(mb * w, -power, atol=1e-9 * np.abs(power).max())


def test_balancing_torque_is_negative_while_gas_drives():
    phi = np.radians(np.array([400.0, 420.0, 450.0]))
    mb, _, _, _ = kinetostatics(phi, q1=0, q2=0, q3=0, w=1e-3)   # quasi-static, gas only
    assert np.all(mb < 0)


def test_rod_is_in_equilibrium():
    phi = np.linspace(0, 4 * np.pi, 181)
    _, _, _, (r03, r12x, r12y, f2x, f2y, f3, beta, psi) = kinetostatics(phi)
    # forces on the piston: R23 + R03 + F3 = 0 with R23 = −R32 = (−R03, −F3y)
    r32x, r32y = r03, f3
    assert np.allclose(r12x + r32x + f2x, 0, atol=1e-6)
    assert np.allclose(r12y + r32y + f2y, 0, atol=1e-6)


def test_flywheel_energy_closes_over_the_cycle():
    phi = np.linspace(0, 4 * np.pi, 721)
    torque = 100 + 300 * np.sin(phi) + 50 * np.cos(3 * phi)
    mean = m.closed_cycle_mean(phi, torque)
    assert mean == pytest.approx(100, rel=1e-9)
    energy = m.energy_fluctuation(phi, torque, mean)
    assert energy[0] == 0 and energy[-1] == pytest.approx(0, abs=1e-9)
    fine = np.linspace(0, 4 * np.pi, 200001)
    exact = 300 * (1 - np.cos(fine)) + 50 / 3 * np.sin(3 * fine)      # ∫(M − 100) dφ
    assert m.energy_swing(energy) == pytest.approx(exact.max() - exact.min(), rel=1e-3)
