"""The workbook specification and the named-range contract."""
import re

import numpy as np
import pytest

from crankbook import evaluate, params, spec as specs
from crankbook.pressure_file import close_cycle
from crankbook.reader import named_values, open_workbook
from tests.conftest import run_cli

CONTRACT = {  # issue 3: q_ names and their units
    "crank_angle": "deg", "piston_displacement": "mm", "piston_velocity": "m/s",
    "piston_acceleration": "m/s²", "rod_angle": "deg", "cylinder_pressure": "MPa",
    "gas_force": "N", "inertia_force": "N", "piston_force": "N", "side_force": "N",
    "rod_force": "N", "tangential_force": "N", "radial_force": "N", "torque": "N·m",
}
PARAMETERS = {
    "crank_radius": "mm", "rod_length": "mm", "offset": "mm", "bore": "mm", "speed": "rpm",
    "piston_mass": "kg", "rod_mass": "kg", "rod_cg_from_big_end": "mm",
    "crank_unbalanced_mass": "kg", "ambient_pressure": "MPa", "exact_kinematics": "-",
}
CELL_LIKE = re.compile(r"^([A-Za-z]{1,3}\d+|[Rr]\d*[Cc]\d*|[RrCc])$")


def test_contract_keys_and_units():
    spec = specs.load("engine")
    for key, unit in CONTRACT.items():
        assert spec.unit_of(key) == unit, key
    for key, unit in PARAMETERS.items():
        assert spec.parameter[key].unit == unit, key


def test_every_quantity_has_labels_formula_and_calc():
    spec = specs.load("engine")
    for q in spec.quantities():
        if q is spec.grid:
            continue
        assert q.zh and q.en and q.formula and q.calc, q.key
        q.calc_function()


def test_defined_names_are_valid_and_complete(tmp_path):
    path = tmp_path / "t.xlsx"
    assert run_cli("build", "--step", "10", "-o", path).returncode == 0
    names = named_values(open_workbook(path))
    spec = specs.load("engine")
    expected = {f"p_{k}" for k in spec.parameter} | {f"p_{k}" for k in spec.table_column} | \
        {f"q_{q.key}" for q in spec.quantities()}
    assert expected <= set(names)
    for name in names:
        assert re.fullmatch(r"[A-Za-z_][A-Za-z0-9_.]*", name) and not CELL_LIKE.match(name)
    assert len(names["q_torque"]) == 73


def test_template_references_are_checked():
    spec = specs.load("engine")
    bad = specs.Quantity(key="x", kind="scalar", unit="mm", zh="x", en="x",
                         formula="{no_such_key}", calc="calc.kinematics.stroke")
    spec.scalars.append(bad)
    try:
        with pytest.raises(ValueError, match="no_such_key"):
            specs.WorkbookSpec.__post_init__(spec) or specs.check(spec)
    finally:
        spec.scalars.remove(bad)
        specs.WorkbookSpec.__post_init__(spec)


def test_trace_is_wrapped_sorted_and_closed():
    angles, pressures = close_cycle("t", np.array([370.0, -360.0, 0.0, 10.0, 360.0] +
                                                  list(np.arange(20.0, 720.0, 20.0))),
                                    np.ones(40) * 0.2)
    assert angles[0] <= 0 and angles[-1] >= 720 and np.all(np.diff(angles) > 0)


def test_grid_step_must_divide_the_cycle():
    spec = specs.load("engine")
    assert len(evaluate.crank_angle_grid(spec, 0.5)) == 1441
    with pytest.raises(Exception, match="divide"):
        evaluate.crank_angle_grid(spec, 0.7)


def test_preset_bounds_agree_with_validation():
    spec, values, _ = params.load_preset("thesis")
    params.validate(spec, values)
    for p in spec.parameters:
        assert not params.breaks_bounds(p, values[p.key]), p.key
