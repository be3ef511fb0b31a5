"""The compressor workbook (seed 002) against independent computations: pressure
continuity at every phase boundary and the boundaries' closed forms, the p–V loops'
work against the shaft torque, torque = F·v/ω, the volumetric efficiency against the
delivery, and the seed's stage-1 numbers."""
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
    s, par, g = seed.scalars, seed.parameters, seed.series()
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


def test_one_stage_on_one_column():
    result = crankbook.compute("compressor", stage_bore=[60.0], stage_suction_pressure=[0.1],
                               stage_discharge_pressure=[0.8], stage_expansion_exponent=[1.3],
                               stage_compression_exponent=[1.35], stage_clearance_length=[1.0],
                               stage_column=[1], column_phase=[0.0], piston_mass=[0.4],
                               rod_mass=[0.2], rod_small_end_share=[0.35], step=2)
    assert result.scalars["shaft_power"] > 0


@pytest.mark.parametrize("sets,words", [
    ({"stage_suction_pressure": [0.1, 0.6, 30.0]}, "suction pressure must be below"),
    ({"stage_expansion_exponent": [1.0, 1.4, 1.4]}, "stage_expansion_exponent"),
    ({"stage_clearance_length": [0.0, 1.26, 1.26]}, "stage_clearance_length"),
    ({"stage_column": [1, 2, 3]}, "column that does not exist"),
])
def test_bad_compressor_inputs(sets, words):
    with pytest.raises(CrankbookError, match=words):
        crankbook.compute("compressor", **sets)
