"""The command line as a user meets it: bad input gives one line, exit 2, no file."""
import hashlib
import os
from pathlib import Path

import pytest

from tests.conftest import run_cli

BAD_SETS = [
    (["--set", "rod_length=60", "--set", "offset=15"], "rod too short"),
    (["--set", "rod_length=50"], "rod_length"),
    (["--set", "bore=-88"], "parameter bore = -88: must be > 0"),
    (["--set", "speed=0"], "parameter speed = 0: must be > 0"),
    (["--set", "piston_mass=0"], "piston_mass"),
    (["--set", "speed=fast"], "parameter speed: 'fast' is not a number"),
    (["--set", "speed=nan"], "parameter speed: 'nan' is not a number"),
    (["--set", "sped=3000"], "unknown parameter 'sped' (did you mean speed?)"),
    (["--set", "speed"], "expected KEY=VALUE"),
    (["--set", "exact_kinematics=0", "--set", "offset=5"], "centric mechanism only"),
    (["--set", "exact_kinematics=2"], "must be 0 or 1"),
    (["--set", "pressure_source=1"], "pressure_source = 1 needs a measured trace"),
    (["--preset", "inline-4", "--set", "shaft_tensile_strength=0.8"],
     "must be 0 (the crankshaft material's p_tensile_strength) or at least 400 MPa"),
    (["--preset", "nosuch"], "unknown preset 'nosuch'"),
    (["--step", "7"], "must divide 720"),
    (["--step", "-1"], "the grid step must be ≥ 0.1"),
    (["--step", "7"], "crankbook: error: --step 7:"),         # the flag, not the API keyword
    (["--preset", "compressor", "--set", "stage_discharge_pressure=0.5,3.5,20"],
     "stage 2: stage_suction_pressure = 0.6 MPa: a stage cannot suck above the previous"),
]

# legal values an engineer rarely means: one warning line, exit 0, the workbook written
SLIPS = [
    (["--set", "piston_mass=316"], "grams typed for kg"),
    (["--set", "rod_mass=328"], "grams typed for kg"),
    (["--set", "speed=12000"], "mean piston speed is above 30 m/s"),
    (["--preset", "inline-4", "--set", "firing_angle=360,540,181,0"], "1–2° off a regular"),
    (["--preset", "inline-6", "--set", "speed=1000", "--set", "flywheel_inertia_typed=0"],
     "flywheel is implausible"),
    (["--step", "10"], "a 10° grid step is coarser than 5° and reads the peaks between its "
                       "rows: cylinder_pressure_max reads low"),
]


@pytest.mark.parametrize("args,expected", SLIPS)
def test_a_plausible_slip_gets_one_warning_line_and_the_workbook(tmp_path, args, expected):
    output = tmp_path / "out.xlsx"
    done = run_cli("build", *args, "-o", output)
    assert done.returncode == 0, done.stderr
    lines = done.stderr.strip().splitlines()        # the slip first; what it causes after
    assert lines and all(line.startswith("crankbook: warning: ") for line in lines), lines
    assert expected in lines[0]
    assert output.exists()


def test_the_coarse_steps_effect_is_measured_against_the_fine_grid():
    import warnings
    import crankbook
    from crankbook.errors import CoarseStepWarning
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        coarse = crankbook.compute("thesis", step=10)
    assert [w.category for w in caught] == [CoarseStepWarning]
    fine = crankbook.compute("thesis")
    low = 100 * (coarse.scalars["cylinder_pressure_max"] / fine.scalars["cylinder_pressure_max"] - 1)
    assert low < -1                                # 10° misses the peak by some per cent
    assert f"cylinder_pressure_max {coarse.scalars['cylinder_pressure_max']:.4g} " \
           f"({low:+.2f} %)" in coarse.coarse_step_effect()
    assert crankbook.compute("thesis", step=5).coarse_step_effect() is None


def test_a_build_without_a_slip_says_nothing(tmp_path):
    done = run_cli("build", "--preset", "inline-6", "-o", tmp_path / "i6.xlsx")
    assert done.returncode == 0 and done.stderr == "", done.stderr


def _assert_clean_refusal(done, expected, output):
    assert done.returncode == 2, done.stdout + done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1, done.stderr
    assert "Traceback" not in done.stderr
    assert expected in lines[0]
    assert not output.exists()
    assert not list(output.parent.glob("*.tmp")), "a temporary file was left behind"


@pytest.mark.parametrize("args,expected", BAD_SETS)
def test_bad_parameters_are_refused(tmp_path, args, expected):
    output = tmp_path / "out.xlsx"
    _assert_clean_refusal(run_cli("build", "-o", output, *args), expected, output)


BAD_TRACES = [
    ("missing.csv", None, "no such file"),
    ("one_column.csv", "angle\n0\n10\n", "needs exactly two columns"),
    ("text.csv", "angle,p\n0,0.1\nten,0.2\n", "crank angle 'ten' is not a number"),
    ("text_p.csv", "0,0.1\n10,high\n", "pressure 'high' is not a number"),
    ("one_point.csv", "angle,p\n0,0.1\n", "at least two points"),
    ("half.csv", "\n".join(f"{a},0.2" for a in range(-180, 181, 5)), "must cover the whole"),
    ("negative.csv", "\n".join(f"{a},-0.1" for a in range(0, 720, 5)), "must be > 0"),
    ("kpa.csv", "\n".join(f"{a},{100 + a}" for a in range(0, 720, 5)), "look like kPa or bar"),
    ("trace.json", "{}", "use a .csv or .xlsx"),
    ("fake.xlsx", "not a zip", "not an .xlsx file"),
]


@pytest.mark.parametrize("name,content,expected", BAD_TRACES)
def test_bad_pressure_files_are_refused(tmp_path, name, content, expected):
    trace = tmp_path / name
    if content is not None:
        trace.write_text(content)
    output = tmp_path / "out" / "out.xlsx"
    output.parent.mkdir()
    _assert_clean_refusal(run_cli("build", "-o", output, "--pressure", trace), expected, output)


SPECIAL_PATHS = [
    (("build", "-o", "{out}", "--pressure", "{path}"), "pressure file"),
    (("assign", "--roster", "{path}", "-o", "{out}"), "roster"),
    (("check", "{path}"), ""),
    (("assign", "--roster", "{roster}", "--assignment", "{path}", "-o", "{out}"), "assignment"),
]


# a pipe everywhere (it would hang the command); a device and a folder once (one helper)
@pytest.mark.parametrize("args,named,kind",
                         [(*case, "fifo") for case in SPECIAL_PATHS]
                         + [(*SPECIAL_PATHS[0], "device"), (*SPECIAL_PATHS[1], "folder")])
def test_a_path_that_is_not_a_file_is_named_as_such(tmp_path, kind, args, named):
    """A pipe would block the read and a device never end it: each is refused at
    once, in words that say what the path is (not "no such file")."""
    path = {"fifo": tmp_path / "trace.csv", "device": Path("/dev/zero"),
            "folder": tmp_path / "folder.csv"}[kind]
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "folder":
        path.mkdir()
    output, roster = tmp_path / "out.xlsx", tmp_path / "roster.csv"
    roster.write_text("student_id,name\ns001,Li\n")
    done = run_cli(*(a.format(path=path, out=output, roster=roster) for a in args), timeout=60)
    assert done.returncode == 2, done.stderr
    assert "Traceback" not in done.stderr and "no such file" not in done.stderr
    said = {"fifo": "named pipe", "device": "a device", "folder": "a folder"}[kind]
    assert said in done.stderr and named in done.stderr and path.name in done.stderr
    if args[0] == "check":                  # a student's command: said in Chinese too
        assert "不是普通文件" in done.stderr, done.stderr
    assert not output.exists()


def test_same_input_same_bytes(tmp_path):
    digests = []
    for name in ("a.xlsx", "b.xlsx"):
        done = run_cli("build", "--step", "4", "-o", tmp_path / name)
        assert done.returncode == 0, done.stderr
        digests.append(hashlib.sha256((tmp_path / name).read_bytes()).hexdigest())
    assert digests[0] == digests[1]


def test_default_build_writes_output_preset(tmp_path):
    done = run_cli("build", "--step", "5", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "output" / "thesis.xlsx").is_file()
    assert "cylinder_pressure_max" in done.stdout


def test_help_and_listing():
    assert "--pressure" in run_cli("build", "--help").stdout
    assert "thesis" in run_cli("presets").stdout
    assert "crank_radius" in run_cli("parameters").stdout


def test_verify_refuses_a_non_workbook(tmp_path):
    bogus = tmp_path / "x.xlsx"
    bogus.write_text("hello")
    done = run_cli("verify", bogus)
    assert done.returncode == 2 and "not an .xlsx file" in done.stderr
