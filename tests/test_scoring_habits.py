"""Issue 40.3-5 and 8: numbers as Chinese students type them, angles judged in
degrees, J and N·m one unit for an energy, sign slips at any magnitude — each case
scored by the grader's own score_cell against the course-design rubric."""
import math

import pytest

from crankbook.assignment import template
from crankbook.assignment.scoring import read_answer, score_cell

ASSIGNMENT = template.for_preset("course-design")
RUBRIC = ASSIGNMENT.rubric


def scored(key, typed, expected):
    item = ASSIGNMENT.item[key]
    result = score_cell("", typed, expected, item, RUBRIC)
    return result.reason, result.fraction


@pytest.mark.parametrize("typed, number", [
    ("2,605", 2605.0), ("2，605", 2605.0), ("２，６０５", 2605.0), ("1,234.5", 1234.5),
    ("-3,500", -3500.0), ("1,000,000", 1e6), ("2,605 mm", 2605.0),
    ("2,6", 2.6), ("12,3456", 12.3456),            # a decimal comma stays one
])
def test_thousands_as_chinese_students_type_them(typed, number):
    assert read_answer(typed)[0] == number


@pytest.mark.parametrize("typed", ["2.605,3", "1.234.567,8", "2.605,3 mm"])
def test_a_point_before_a_comma_is_ambiguous_not_guessed(typed):
    assert scored("crank_radius", typed, 2605.3) == ("ambiguous_number", 0.0)


@pytest.mark.parametrize("key, typed, expected, outcome", [
    # φ: 0.5° absolute, whatever the size of the angle (1 % of 300° was 3°)
    ("pos_crank_angle", 301.4, 300.0, ("wrong", 0.0)),
    ("pos_crank_angle", 300.4, 300.0, ("correct", 1.0)),
    ("extreme_angle", 12.4, 12.0, ("correct", 1.0)),        # 1 % of 12° was 0.12°
    # mounting angles: "= −φ_open/i mod 360°" — −20° is 340°
    ("intake_cam_mounting_angle", -20.0, 340.0, ("correct", 1.0)),
    ("intake_cam_mounting_angle", 700.2, 340.0, ("correct", 1.0)),
    ("intake_cam_mounting_angle", 341.0, 340.0, ("wrong", 0.0)),
    # a pressure angle is no mounting angle: no modulo
    ("intake_cam_max_pressure_angle", 390.0, 30.0, ("wrong", 0.0)),
    # in radians, the same 0.5°
    ("intake_cam_max_pressure_angle", f"{math.radians(30.3):.6f} rad", 30.0,
     ("unit_slip", 0.5)),
])
def test_angles_are_judged_in_degrees(key, typed, expected, outcome):
    assert scored(key, typed, expected) == outcome


@pytest.mark.parametrize("typed, outcome", [
    ("352.1 N·m", ("correct", 1.0)), ("352.1 N.m", ("correct", 1.0)),
    ("352.1 J", ("correct", 1.0)), ("0.3521 kJ", ("unit_slip", 0.5)),
    ("352100 N·mm", ("unit_slip", 0.5)), ("352.1 kg", ("wrong_unit", 0.0)),
])
def test_an_energy_in_newton_metres_is_in_joules(typed, outcome):
    assert scored("pos_energy_swing", typed, 352.1) == outcome


def test_a_sign_slip_earns_the_sign_credit_at_any_magnitude():
    # M_b's floor is 5 N·m: 12.3 N·m was "not clearly non-zero" and −12.31 got 0 %
    assert scored("pos_balancing_torque", -12.31, 12.3) == ("sign_slip", 0.5)
    assert scored("pos_balancing_torque", -120.3, 120.0) == ("sign_slip", 0.5)
    assert scored("pos_balancing_torque", 0.0, 12.3)[1] == 0.0      # zero is no slip
    assert scored("pos_balancing_torque", -4.0, 3.0)[0] == "wrong"   # the floor can't tell


@pytest.mark.parametrize("value, text", [
    (-2e-7, "−2 × 10⁻⁷"), (3.25e-5, "3.25 × 10⁻⁵"), (1.23456e-9, "1.235 × 10⁻⁹"),
    (0.000123456, "0.0001235"), (0.0362, "0.0362"),
])
def test_tiny_typed_numbers_are_shown_readably(value, text):
    """Issue 40.11: a student's 2e-07 came back as "-0.0000002"."""
    from crankbook.assignment.results import shown
    assert shown(value, typed=True) == text


def test_a_comma_read_as_thousands_says_so_when_a_point_was_meant():
    """A student who typed "104,135" for 104.135 mm is told the comma was read as
    thousands — no credit (the rule is the class's), but no bare "wrong" either."""
    result = score_cell("", "104,135", 104.135, ASSIGNMENT.item["crank_radius"], RUBRIC)
    assert (result.reason, result.fraction) == ("thousands_read", 0.0)
    assert result.detail == {"number": "104135", "decimal": "104.135"}
    assert scored("crank_radius", "104,135", 99.0) == ("wrong", 0.0)
