"""The course-design and optimisation workbooks: the named-range contract and bad
input (their engine cross-checks are in test_cross_check.py)."""
import pytest

from tests.conftest import run_cli
from tests.test_cli import _assert_clean_refusal
from crankbook.spec import params

POS_NAMES = ["pos_crank_angle", "pos_cylinder_pressure", "pos_slider_displacement",
             "pos_slider_velocity", "pos_rod_angular_velocity", "pos_rod_cg_velocity",
             "pos_slider_acceleration", "pos_rod_angular_acceleration", "pos_rod_cg_acceleration",
             "pos_balancing_torque"]

BAD = [
    (["--set", "time_ratio=0.9"], "parameter time_ratio = 0.9: must be > 1"),
    (["--set", "time_ratio=1"], "must be > 1"),
    (["--set", "offset=5000"], "no crank exists"),
    (["--set", "offset=-10"], "parameter offset = -10: must be > 0"),
    (["--group", "99"], "--group 99: no such group"),
    (["--set", "rod_weight=0"], "parameter rod_weight = 0: must be > 0"),
    (["--set", "speed_fluctuation=0"], "speed_fluctuation"),
    (["--set", "stroke=-3"], "stroke"),
]


@pytest.mark.parametrize("args,expected", BAD)
def test_bad_course_design_input_is_refused(tmp_path, args, expected):
    output = tmp_path / "out.xlsx"
    done = run_cli("build", "--preset", "course-design", "-o", output, *args)
    _assert_clean_refusal(done, expected, output)


def test_group_on_a_preset_without_groups(tmp_path):
    output = tmp_path / "out.xlsx"
    done = run_cli("build", "--group", "1", "-o", output)
    _assert_clean_refusal(done, "has no table of groups", output)


def test_every_group_is_a_valid_mechanism():
    spec, values, preset = params.load_preset("course-design")
    for number in range(1, 13):
        params.validate(spec, params.apply_group(spec, values, preset, number))


def test_named_range_contract(checked):
    cached = checked["course"].cached
    for key in POS_NAMES:
        assert len(cached[f"q_{key}"]) == 30, key
    for key in ("cycle_crank_angle", "cycle_cylinder_pressure", "cycle_balancing_torque"):
        assert len(cached[f"q_{key}"]) == 721, key
    for key in ("crank_radius", "rod_length", "extreme_angle", "flywheel_inertia",
                "indicated_power"):
        assert isinstance(cached[f"q_{key}"], float), key
