"""The course design's valve train as the workbook computes it (calc via the template's
own wiring): the worked report R07's cam and gears, the valve timing identities, and
bad input.  The formulas themselves are recomputed in LibreOffice and Gnumeric by the
cross-checks (every course-design workbook there carries these sheets)."""
import numpy as np
import pytest

import crankbook
from crankbook.errors import CrankbookError, LayoutError, ParameterValueError


@pytest.fixture(scope="module")
def r07():
    # R07: n1 = 650 rpm, the cosine cam of the defaults, z = 21/15/42, m = 4 mm, x2 = 0.11765
    return crankbook.compute("course-design", speed=650.0, gear_teeth=[21, 15, 42],
                             gear_shift=[0.0, 0.11765, 0.0], gear_module=4.0)


def test_worked_report_r07_cam(r07):
    s, cam = r07.scalars, r07.series("cam_angle")
    assert s["cam_angular_velocity"] == pytest.approx(34.034, abs=5e-4)
    assert cam["intake_cam_acceleration"].max() == pytest.approx(60047, rel=3e-4)
    far = cam.loc[55.0]
    assert np.hypot(far["intake_cam_pitch_x"], far["intake_cam_pitch_y"]) == \
        pytest.approx(42.933, abs=5e-4)
    assert s["intake_cam_base_offset"] == pytest.approx(34.641, abs=5e-4)


def test_worked_report_r07_gears(r07):
    s = r07.scalars
    assert s["mesh_working_pressure_angle[1]"] == pytest.approx(20.98, abs=0.005)
    assert s["mesh_working_centre_distance[1]"] == pytest.approx(72.45975, abs=2e-5)
    assert s["mesh_contact_ratio[1]"] == pytest.approx(1.48092, abs=1e-4)
    assert s["gear_addendum[2]"] == pytest.approx(4.45974, abs=1e-4)     # the idler
    newton = r07.series("involute_step")
    assert newton["mesh_newton[1]"].iloc[-1] == pytest.approx(newton["mesh_newton[1]"].iloc[-2],
                                                           rel=1e-14)          # converged


def test_the_follower_returns_and_dwells(r07):
    cam = r07.series("cam_angle")
    p = r07.parameters
    s = cam["intake_cam_displacement"]
    assert s.loc[0.0] == 0 and s.loc[p["intake_rise_angle"]] == p["intake_lift"]
    assert s.loc[360.0] == 0 and (s.loc[130.0:360.0] == 0).all()
    # the profile stays a roller radius inside the pitch curve
    gap = np.hypot(cam["intake_cam_pitch_x"] - cam["intake_cam_profile_x"],
                   cam["intake_cam_pitch_y"] - cam["intake_cam_profile_y"])
    assert np.allclose(gap, p["intake_roller_radius"])


def test_valve_timing_identities():
    result = crankbook.compute("course-design")
    s, p = result.scalars, result.parameters
    assert s["valve_overlap"] == p["exhaust_closes"] - p["intake_opens"]
    assert s["intake_open_duration"] == pytest.approx(
        s["lowest_position_angle"] + p["intake_closes"] - p["intake_opens"])
    lift = result.series()["intake_valve_lift"]
    opens = s["intake_open_angle"] % 720
    # the valve lifts only while it is open: from its opening for the cam's working angle
    open_rows = ((lift.index - opens) % 720) < s["intake_cam_working_angle"]
    assert (lift[~open_rows] == 0).all() and lift[open_rows].max() == p["intake_lift"]


@pytest.mark.parametrize("sets,error,words", [
    ({"intake_base_radius": 4.0}, CrankbookError, "base radius must exceed"),
    ({"exhaust_rise_angle": 200.0, "exhaust_return_angle": 170.0}, CrankbookError,
     "fit in 360"),
    ({"intake_return_law": "spline"}, ParameterValueError, "must be one of"),
    ({"gear_teeth": [36, 4, 72]}, ParameterValueError, "gear 2"),
    ({"gear_teeth": [36, 72]}, LayoutError, "set together"),
    ({"intake_roller_radius": 25.0}, CrankbookError, "roller radius must be smaller"),
    ({"gear_shift": [0.0, 1.5, 0.0]}, CrankbookError, "gear 2: .*pointed"),
])
def test_bad_valve_train_inputs(sets, error, words):
    with pytest.raises(error, match=words):
        crankbook.compute("course-design", **sets)
