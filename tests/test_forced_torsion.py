"""The forced, damped torsional response (issue 42, its calc layer): the two-pass
recurrence against numpy's complex solve, Den Hartog's published damper optima, and
the IACS UR M68 limit's closed form."""
import numpy as np
import pytest

import crankbook
from crankbook.calc import forced_torsion as ft, torsional

GROUND = 1e12            # kg·m²: a station this heavy stands still (a grounded spring)


@pytest.mark.parametrize("preset", ["thesis", "inline-4", "inline-6", "v8-crossplane"])
def test_the_recurrence_is_the_complex_solve_for_every_preset(preset):
    r = crankbook.compute(preset, step=30.0)
    inertia = np.asarray(r["station_inertia"])
    stiffness = np.asarray(r["section_stiffness"])
    rng = np.random.default_rng(7)
    for omega in (50.0, 2 * np.pi * np.asarray(r["natural_frequency"])[0] * 0.999, 3000.0):
        force = rng.normal(size=inertia.size) + 1j * rng.normal(size=inertia.size)
        ground = np.abs(rng.normal(size=inertia.size)) * 5
        got = ft.forced_response(omega, inertia, stiffness, force, loss_factor=0.04,
                                 ground_damping=ground)
        want = ft.direct_response(omega, inertia, stiffness, force, loss_factor=0.04,
                                  ground_damping=ground)
        assert np.allclose(got, want, rtol=1e-9, atol=1e-12 * np.abs(want).max()), omega


def test_hidden_engine_like_systems():
    """Chains an engine could have — a pulley, one to twelve throws of like inertia and
    stiffness, a flywheel — excited anywhere up to 1.5 times their highest mode, with
    viscous couplings and dampers to ground: the recurrence is the solve to 1e-7 of the
    largest amplitude.  (A transfer recurrence loses digits where its free pass grows
    as (ω²J/k)ⁿ over many unlike stations, far above the modes an engine excites.)"""
    rng = np.random.default_rng(11)
    for _ in range(40):
        throws = int(rng.integers(1, 13))
        inertia = np.concatenate([[rng.uniform(0.005, 0.05)],
                                  rng.uniform(0.005, 0.02, throws), [rng.uniform(0.1, 1.0)]])
        stiffness = rng.uniform(1e5, 1e6, throws + 1)
        coupling = rng.uniform(0.0, 20.0, throws + 1)
        ground = rng.uniform(0.0, 5.0, throws + 2)
        highest = torsional.natural_frequencies(inertia, stiffness).max() * 2 * np.pi
        omega = rng.uniform(0.02, 1.5) * highest
        force = rng.normal(size=throws + 2) + 1j * rng.normal(size=throws + 2)
        got = ft.forced_response(omega, inertia, stiffness, force, loss_factor=0.02,
                                 section_damping=coupling, ground_damping=ground)
        want = ft.direct_response(omega, inertia, stiffness, force, loss_factor=0.02,
                                  section_damping=coupling, ground_damping=ground)
        assert np.abs(got - want).max() <= 1e-7 * np.abs(want).max(), (throws, omega / highest)


def _peak(inertia, stiffness, coupling, force_at, omegas, station):
    force = np.zeros(len(inertia), dtype=complex)
    force[force_at] = 1.0
    return max(abs(ft.forced_response(w, inertia, stiffness, force,
                                      section_damping=coupling)[station]) for w in omegas)


@pytest.mark.parametrize("mu", [0.1, 0.25, 0.5])
def test_den_hartogs_untuned_viscous_damper(mu):
    """Den Hartog §5.9: with c = 2·J_d·ω_n·ζ_opt, ζ_opt = 1/√(2(1 + μ)(2 + μ)), the main
    inertia's peak amplification is 1 + 2/μ — and any other damping gives more."""
    j, k = 1.0, 1e4
    wn = np.sqrt(k / j)
    omegas = np.linspace(0.2, 1.5, 6000) * wn
    best = 2 * mu * j * wn * ft.untuned_damper_optimum_ratio(mu)
    system = ([mu * j, j, GROUND], [0.0, k])
    peak = _peak(*system, [best, 0.0], 1, omegas, 1) * k
    assert peak == pytest.approx(ft.untuned_damper_peak(mu), rel=0.01)
    for other in (0.5 * best, 2 * best):
        assert _peak(*system, [other, 0.0], 1, omegas, 1) * k > peak


@pytest.mark.parametrize("mu", [0.05, 0.1, 0.2])
def test_den_hartogs_tuned_absorber(mu):
    """Den Hartog §3.3: tuned to f = 1/(1 + μ) with ζ = √(3μ/(8(1 + μ)³)), the two peaks
    of the main inertia stand at about √(1 + 2/μ), the height of the fixed points."""
    j, k = 1.0, 1e4
    wn = np.sqrt(k / j)
    absorber = mu * j
    k_a = absorber * (ft.tuned_absorber_frequency_ratio(mu) * wn) ** 2
    c_a = 2 * absorber * wn * ft.tuned_absorber_damping_ratio(mu)
    omegas = np.linspace(0.5, 1.5, 8000) * wn
    peak = _peak([absorber, j, GROUND], [k_a, k], [c_a, 0.0], 1, omegas, 1) * k
    assert peak == pytest.approx(np.sqrt(1 + 2 / mu), rel=0.05)


def test_the_section_torque_and_stress():
    theta = np.array([0.01, 0.004, 0.0])
    torque = ft.section_torque(theta, [2e5, 3e5])
    assert np.allclose(torque, [1200.0, 1200.0])
    # a solid 60 mm shaft under 1200 N·m: 16T/(πd³)
    assert ft.section_shear_stress(1200.0, 0.06) == pytest.approx(16 * 1200 / (np.pi * 0.06 ** 3))


def test_m68_limit_closed_form():
    """IACS UR M68: σ_B = 600 N/mm², C_K = 1, d = 100 mm, λ = 0.5: τ_C = (760/18)·C_D·2.5
    with C_D = 0.35 + 0.93·100^−0.2; at λ ≥ 0.9 the factor is 1.38."""
    cd = 0.35 + 0.93 * 100 ** -0.2
    assert ft.m68_continuous_limit(600e6, 1.0, 0.1, 0.5) == pytest.approx(760 / 18 * cd * 2.5e6)
    assert ft.m68_continuous_limit(600e6, 1.0, 0.1, 1.0) == pytest.approx(760 / 18 * cd * 1.38e6)
    assert ft.m68_transient_limit(10e6, 0.8) == pytest.approx(1.7 * 10e6 / np.sqrt(0.8))
