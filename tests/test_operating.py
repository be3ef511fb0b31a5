"""Operating points (issue 21): every point of the 工况 sheet is the workbook computed
from scratch at that speed — with the same cylinder pressure, or with the measured
trace of that speed — and bad multi-speed files get one line naming the column."""
import numpy as np
import pytest

import crankbook
from crankbook.errors import CrankbookError
from tests.conftest import run_cli

SINGLE_SPEED = {      # operating-point key -> what a single-speed workbook calls it
    "gas_force_max": ("gas_force", "peak"), "inertia_force_max": ("inertia_force", "peak"),
    "piston_force_max": ("piston_force", "peak"), "side_force_max": ("side_force", "peak"),
    "rod_force_max": ("rod_force", "peak"), "tangential_force_max": ("tangential_force", "peak"),
    "radial_force_max": ("radial_force", "peak"), "torque_max": ("engine_torque_max", None),
    "torque_min": ("engine_torque_min", None), "mean_torque": ("engine_mean_torque", None),
    "indicated_power": ("engine_indicated_power", None),
    "crankpin_load_max": ("crankpin_load_max", "largest"),
    "journal_load_max": ("journal_load_max", "largest"),
    "pin_combined_stress_max": ("pin_combined_stress_max", None),
    "static_safety_factor": ("static_safety_factor", None),
    "fatigue_safety_factor": ("fatigue_safety_factor", None),
}


def _single(scalars, key, how):
    if how == "peak":
        return max(scalars[f"{key}_max"], -scalars[f"{key}_min"])
    if how == "largest":
        return max(v for k, v in scalars.items() if k.startswith(key + "["))
    return scalars[key]


def assert_points_are_single_speed_builds(operating, build_at):
    s, speeds = operating.scalars, operating.parameters["operating_speed"]
    for point, speed in enumerate(speeds, start=1):
        one = build_at(speed).scalars
        for key, (single, how) in SINGLE_SPEED.items():
            want = _single(one, single, how)
            assert s[f"operating_{key}[{point}]"] == pytest.approx(want, rel=1e-12, abs=1e-9), \
                (speed, key)


@pytest.mark.parametrize("preset", ["thesis", "inline-4", "v8-crossplane", "v-twin-90"])
def test_every_operating_point_is_a_workbook_at_that_speed(preset):
    r = crankbook.compute(preset)
    assert_points_are_single_speed_builds(r, lambda n: crankbook.compute(preset, speed=n))


def test_default_points_span_the_range_with_the_design_speed():
    r = crankbook.compute("thesis")
    speeds = r.parameters["operating_speed"]
    assert len(speeds) == 12 and r.parameters["speed"] in speeds
    assert min(speeds) <= 1000 and max(speeds) >= 6000
    assert all(v == 0 for k, v in r.scalars.items() if k.startswith("operating_pressure_from"))
    # the inertia force grows with n², the gas force does not change with the model
    s = r.scalars
    assert s["operating_inertia_force_max[1]"] == pytest.approx(
        s["operating_inertia_force_max[9]"] * (1000 / 5000) ** 2, rel=1e-12)
    assert s["operating_gas_force_max[1]"] == s["operating_gas_force_max[12]"]


def write_traces(path, speeds, step=1.0):
    """A test bench's file: angle, then one pressure column per speed (r/min)."""
    angles = np.arange(0.0, 720.0, step)
    columns = {n: 0.1 + (2.0 + n / 1500) * np.exp(-((angles - 370 - n / 1000) / 28) ** 2)
               for n in speeds}
    lines = ["angle," + ",".join(f"{n:g}" for n in speeds)]
    lines += [",".join([f"{a:g}"] + [repr(float(columns[n][i])) for n in speeds])
              for i, a in enumerate(angles)]
    path.write_text("\n".join(lines) + "\n")
    return angles, columns


@pytest.mark.parametrize("preset", ["thesis", "inline-4"])
def test_a_measured_trace_per_speed(tmp_path, preset):
    speeds = [1500.0, 3000.0, 5000.0, 6000.0]
    angles, columns = write_traces(tmp_path / "bench.csv", speeds)
    r = crankbook.compute(preset, pressure=tmp_path / "bench.csv")
    assert r.parameters["operating_speed"] == speeds
    assert r.parameters["operating_trace_count"] == 4 and r.parameters["pressure_source"] == 1
    assert all(r.scalars[f"operating_pressure_from[{k}]"] == 1 for k in range(1, 5))

    def single(speed):
        one = tmp_path / f"trace-{speed:g}.csv"
        one.write_text("\n".join(f"{a:g},{float(p)!r}" for a, p in zip(angles, columns[speed])))
        return crankbook.compute(preset, speed=speed, pressure=one)
    assert_points_are_single_speed_builds(r, single)
    # the design speed takes its own column
    assert r.scalars["cylinder_pressure_max"] == pytest.approx(columns[5000.0].max(), rel=1e-12)
    # a listed subset of the file's speeds
    part = crankbook.compute(preset, pressure=tmp_path / "bench.csv",
                             operating_speed=[3000, 6000])
    assert part.scalars["operating_gas_force_max[2]"] == r.scalars["operating_gas_force_max[4]"]


@pytest.mark.parametrize("header,rows,words", [
    ("angle,1000,fast", None, "column 3: header 'fast' is not a speed"),
    ("angle,1000,1000", None, "speed 1000 r/min appears twice"),
    ("angle,1000,-5", None, "column 3: header '-5' is not a speed"),
    ("0,1000,5000", None, "needs a header row"),
    ("angle,1000,5000", [f"{a},0.5,0.6" for a in range(0, 400, 5)],
     "column 1000 r/min: crank angles must cover the whole 0–720° cycle"),
    ("angle,1000,5000", ["0,0.5,0.6", "5,0.5,x"] + [f"{a},0.5,0.6" for a in range(10, 720, 5)],
     "column 5000 r/min, row 3: pressure 'x'"),
])
def test_bad_multi_speed_files_name_the_column(tmp_path, header, rows, words):
    rows = rows or [f"{a},0.5,0.6" for a in range(0, 720, 5)]
    path = tmp_path / "bench.csv"
    path.write_text("\n".join([header] + rows) + "\n")
    with pytest.raises(CrankbookError, match=words.replace("(", r"\(").replace(")", r"\)")):
        crankbook.compute("thesis", pressure=path)
    done = run_cli("build", "--pressure", path, "-o", tmp_path / "out.xlsx")
    assert done.returncode == 2 and done.stderr.count("\n") == 1 and words in done.stderr
    assert not (tmp_path / "out.xlsx").exists()


def test_speeds_without_a_column_are_refused(tmp_path):
    write_traces(tmp_path / "bench.csv", [1000.0, 3000.0, 5000.0])
    with pytest.raises(CrankbookError, match="operating_speed 2000 r/min has no column"):
        crankbook.compute("thesis", pressure=tmp_path / "bench.csv", operating_speed=[1000, 2000])
    with pytest.raises(CrankbookError, match="speed = 4000 r/min .the design speed. has no column"):
        crankbook.compute("thesis", pressure=tmp_path / "bench.csv", speed=4000)
    with pytest.raises(CrankbookError, match="takes one trace"):
        crankbook.compute("course-design", pressure=tmp_path / "bench.csv")


def test_trace_count_must_match_the_points():
    with pytest.raises(CrankbookError, match="operating_trace_count"):
        crankbook.compute("thesis", operating_trace_count=3)


def test_a_trace_is_tied_to_the_speed_it_was_recorded_at(tmp_path):
    """Each trace of a bench file keeps its column's speed; a design speed or a point's
    speed that differs from its trace's is refused, naming both (the workbook blanks
    its results and says the same in its status cell: test_cross_check)."""
    write_traces(tmp_path / "bench.csv", [2000.0, 3000.0, 5000.0])
    r = crankbook.compute("thesis", pressure=tmp_path / "bench.csv")
    assert r.parameters["trace_speed"] == 5000.0
    assert r.parameters["operating_trace_speed"] == [2000.0, 3000.0, 5000.0]
    with pytest.raises(CrankbookError, match="trace_speed = 4000 rpm, speed = 5000 rpm: "
                                             "the Pressure sheet's measured trace was recorded"):
        crankbook.compute("thesis", pressure=tmp_path / "bench.csv", trace_speed=4000)
    with pytest.raises(CrankbookError, match="operating_trace_speed = 2000,2500,5000 rpm: "
                                             "a point's measured trace was recorded at another"):
        crankbook.compute("thesis", pressure=tmp_path / "bench.csv",
                          operating_trace_speed=[2000, 2500, 5000])
    # the model, or a trace of no stated speed, serves any speed
    assert crankbook.compute("thesis", trace_speed=4000).scalars["mean_torque"] > 0
    plain = crankbook.compute("thesis", operating_speed=[1000, 2000])
    assert plain.parameters["operating_trace_speed"] == [0.0, 0.0]
    with pytest.raises(CrankbookError, match="operating_trace_speed has 3 values, one per point"):
        crankbook.compute("thesis", operating_speed=[1000, 2000], operating_trace_speed=[0, 0, 0])
