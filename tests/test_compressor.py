"""The compressor workbook (seed 002) against independent computations: pressure
continuity at every phase boundary and the boundaries' closed forms, the p–V loops'
work against the shaft torque, torque = F·v/ω, the volumetric efficiency against the
delivery, the seed's stage-1 numbers, and the crank-pin load and fatigue check
rebuilt from the rod force and the beam formulas by hand."""
import numpy as np
import pytest

import crankbook
from crankbook.errors import CrankbookError


@pytest.fixture(scope="module")
def seed():
    return crankbook.compute("compressor", step=0.5)


def test_pressure_is_continuous_through_every_phase(seed):
    p = seed.series()[[f"stage_pressure[{i}]" for i in (1, 2, 3)]].to_numpy()
    jumps = np.abs(np.diff(p, axis=0)) / p[:-1]
    assert jumps.max() < 0.2                              # no step, only steep slopes
    ps = np.array(seed.parameters["stage_suction_pressure"])
    pd = np.array(seed.parameters["stage_discharge_pressure"])
    assert np.allclose(p.min(axis=0), ps) and np.allclose(p.max(axis=0), pd)


def test_phase_boundaries_are_the_closed_forms(seed):
    s, par = seed.scalars, seed.parameters
    r, l = par["crank_radius"], par["rod_length"]
    for i in (1, 2, 3):
        column = int(par["stage_column"][i - 1])
        phase = par["column_phase"][column - 1]
        alpha = np.radians(s[f"stage_expansion_end_angle[{i}]"] - phase)
        x = r * (1 - np.cos(alpha)) + l - np.sqrt(l ** 2 - (r * np.sin(alpha)) ** 2)
        assert x == pytest.approx(s[f"stage_expansion_end_displacement[{i}]"], rel=1e-9)
        sc = par["stage_clearance_length"][i - 1]
        ps, pd = par["stage_suction_pressure"][i - 1], par["stage_discharge_pressure"][i - 1]
        m = par["stage_expansion_exponent"][i - 1]
        assert pd * (sc / (x + sc)) ** m == pytest.approx(ps, rel=1e-9)   # re-expanded to ps
        assert s[f"stage_volumetric_efficiency[{i}]"] == pytest.approx(1 - x / 36.0)


def test_the_loops_work_is_the_shaft_torques_without_friction():
    result = crankbook.compute("compressor", friction_coefficient=0.0, step=0.5)
    s = result.scalars
    total = sum(s[f"stage_indicated_power[{i}]"] for i in (1, 2, 3))          # kW
    assert s["shaft_power"] == pytest.approx(total, rel=2e-3)    # trapezoids of two grids


def test_friction_takes_f_times_twice_the_stroke_per_column_and_turn(seed):
    s = seed.scalars
    loops = sum(s[f"stage_indicated_power[{i}]"] for i in (1, 2, 3))
    friction = 2 * s["friction_force"] * 0.036 * 2 * 1500 / 60 / 1000            # kW
    assert s["shaft_power"] == pytest.approx(loops + friction, rel=2e-3)


def test_torque_is_force_times_velocity_over_omega(seed):
    g, s, p = seed.series(), seed.scalars, seed.parameters
    r, l, omega = p["crank_radius"] / 1000, p["rod_length"] / 1000, s["angular_velocity"]
    for c in (1, 2):
        alpha = np.unwrap(np.radians(g[f"column_angle[{c}]"].to_numpy()))
        x = r * (1 - np.cos(alpha)) + l - np.sqrt(l ** 2 - (r * np.sin(alpha)) ** 2)
        v = np.gradient(x, alpha) * omega                               # m/s, numerical
        torque = g[f"column_piston_force[{c}]"].to_numpy() * v / omega
        inside = slice(3, -3)
        size = np.abs(torque).max()
        assert np.allclose(g[f"column_torque[{c}]"].to_numpy()[inside], torque[inside],
                           rtol=0, atol=2e-3 * size)


def test_delivery_and_the_seeds_numbers(seed):
    s = seed.scalars
    lam, area = s["stage_volumetric_efficiency[1]"], s["stage_area[1]"] / 1e6
    assert s["free_air_delivery"] == pytest.approx(lam * area * 0.036 * 1500)
    assert s["free_air_delivery"] == pytest.approx(0.1, rel=0.05)      # Table 4.1: Q = 0.1
    assert s["stroke"] == 36.0
    assert s["crank_rod_ratio"] == pytest.approx(1 / 4.4)
    # the mean torque of a compressor is negative: the shaft absorbs power
    assert s["mean_torque"] < 0 and s["shaft_power"] > 0


def test_crankpin_load_is_the_rod_force_less_the_big_ends_centrifugal_force(seed):
    """Without the big end's mass the pin carries the rod force, whatever its
    components; with it, the radial part loses m2·r·ω² (m2 = 0.65·0.18 kg here)."""
    g, s = seed.series(), seed.scalars
    omega, r = s["angular_velocity"], seed.parameters["crank_radius"] / 1000
    for c in (1, 2):
        rod = g[f"column_rod_force[{c}]"].to_numpy()
        centrifugal = 0.65 * 0.18 * r * omega ** 2
        t, k = g[f"crankpin_load_tangential[{c}]"], g[f"crankpin_load_radial[{c}]"]
        assert np.allclose(np.hypot(t, k + centrifugal), np.abs(rod), rtol=1e-9, atol=1e-9)
        assert np.allclose(np.hypot(t, k), g[f"crankpin_load[{c}]"], rtol=1e-12)


def test_fatigue_factor_follows_from_the_checked_pins_load_by_hand():
    """Seed 002 eq. 3.3 applied by hand to column 2's pin: the simply supported throw
    (a = L1/2 + h + L2/2) bends under the pin load, the journal ahead of it carries
    column 1's torque."""
    result = crankbook.compute("compressor", check_throw=2, step=1)
    g, s = result.series(), result.scalars
    d, a = 0.070, 0.037 / 2 + 0.028 + 0.042 / 2                 # seed 002 §5.1 dimensions
    w = np.pi * d ** 3 / 32
    sigma = g["crankpin_load[2]"].to_numpy() * a / 2 / w / 1e6          # MPa
    torque = g["column_torque[1]"].to_numpy() + g["column_tangential_force[2]"].to_numpy() \
        * 0.018 / 2
    tau = torque / (2 * w) / 1e6
    amplitude, mean = np.ptp(sigma) / 2, (sigma.max() + sigma.min()) / 2
    n_sigma = 495 / (1.55 * amplitude / (1.5 * 0.75) + 0.33 * mean)
    tau_a, tau_m = np.ptp(tau) / 2, (tau.max() + tau.min()) / 2
    n_tau = 285 / (1.35 * tau_a / (1.5 * 0.75) + 0.15 * tau_m)
    assert s["fatigue_safety_factor_bending"] == pytest.approx(n_sigma, rel=1e-9)
    assert s["fatigue_safety_factor"] == pytest.approx(
        n_sigma * n_tau / np.hypot(n_sigma, n_tau), rel=1e-9)
    assert s["static_safety_factor"] == pytest.approx(
        800 / np.sqrt(sigma ** 2 + 4 * tau ** 2).max(), rel=1e-9)


def test_one_stage_on_one_column():
    result = crankbook.compute("compressor", stage_bore=[60.0], stage_suction_pressure=[0.1],
                               stage_discharge_pressure=[0.8], stage_expansion_exponent=[1.3],
                               stage_compression_exponent=[1.35], stage_clearance_length=[1.0],
                               stage_column=[1], column_phase=[0.0], piston_mass=[0.4],
                               rod_mass=[0.2], rod_small_end_share=[0.35], check_throw=1,
                               step=2)
    assert result.scalars["shaft_power"] > 0


@pytest.mark.parametrize("sets,words", [
    ({"stage_suction_pressure": [0.1, 0.6, 30.0]}, "suction pressure must be below"),
    ({"stage_expansion_exponent": [1.0, 1.4, 1.4]}, "stage_expansion_exponent"),
    ({"stage_clearance_length": [0.0, 1.26, 1.26]}, "stage_clearance_length"),
    ({"stage_column": [1, 2, 3]}, "column that does not exist"),
    ({"check_throw": 3}, "column checked for strength does not exist"),
    ({"crankpin_bore": 70.0}, "bore must be smaller"),
])
def test_bad_compressor_inputs(sets, words):
    with pytest.raises(CrankbookError, match=words):
        crankbook.compute("compressor", **sets)
