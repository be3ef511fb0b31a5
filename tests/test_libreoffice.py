"""Every formula column recomputed by LibreOffice (recalculation forced) against numpy.

Workbooks are built through the command line and parameter sets are also written
into the cells of a built workbook (as a user editing in Excel would); all files
are recalculated in one LibreOffice run.
"""

import numpy as np
import openpyxl
import pytest

from tests.conftest import run_cli
from crankbook import evaluate, params, recalc
from crankbook.reader import named_values, open_workbook
from crankbook.verify import compare, inputs_of

pytestmark = pytest.mark.libreoffice

# Built through the CLI: name -> extra arguments
BUILDS = {
    "thesis": [],
    "offset_en": ["--set", "offset=12", "--set", "rod_length=165", "--lang", "en",
                  "--step", "2"],
    "series": ["--set", "exact_kinematics=0", "--set", "speed=3200"],
    "measured": ["--pressure", "{trace}", "--step", "0.5"],
}
# Written into the cells of the thesis workbook: name -> parameter edits (+ trace?)
EDITS = {
    "edit_offset": {"offset": -9.0, "rod_length": 172.0, "bore": 92.0},
    "edit_speed": {"speed": 2300.0, "crank_radius": 45.0, "piston_mass": 0.41},
    "edit_series": {"exact_kinematics": 0.0, "speed": 6100.0},
    "edit_trace": {"pressure_source": 1.0},
}


def synthetic_trace(path):
    """A measured-looking trace on −360…359.5° in scrambled order (its own grid)."""
    angles = np.arange(-360.0, 360.0, 0.7)
    pressures = 0.1 + 4.5 * np.exp(-((angles - 12) / 28) ** 2) + 0.02 * np.cos(angles / 40)
    order = np.random.default_rng(7).permutation(len(angles))
    lines = ["crank angle [deg],pressure [MPa]"] + \
        [f"{float(angles[i])!r},{float(pressures[i])!r}" for i in order]
    path.write_text("\n".join(lines) + "\n")
    return angles, pressures


def edit_cells(source, target, edits, trace=None):
    book = openpyxl.load_workbook(source)
    for key, value in edits.items():
        sheet, ref = next(iter(book.defined_names[f"p_{key}"].destinations))
        book[sheet][ref.replace("$", "")] = value
    if trace is not None:
        for key, column in zip(("trace_crank_angle", "trace_pressure"), trace):
            sheet, ref = next(iter(book.defined_names[f"p_{key}"].destinations))
            cells = [c for row in book[sheet][ref.replace("$", "")] for c in row]
            for cell, value in zip(cells, list(column) + [None] * len(cells)):
                cell.value = None if value is None else float(value)
    book.save(target)


@pytest.fixture(scope="session")
def workbooks(soffice, tmp_path_factory):
    """name -> (original file, recalculated file, expected numpy results)."""
    tmp = tmp_path_factory.mktemp("lo")
    trace_file = tmp / "trace.csv"
    synthetic_trace(trace_file)
    files, expected = {}, {}
    for name, extra in BUILDS.items():
        path = tmp / f"{name}.xlsx"
        args = [a.replace("{trace}", str(trace_file)) for a in extra]
        done = run_cli("build", "-o", path, *args)
        assert done.returncode == 0, done.stderr
        files[name] = path
    spec, base, _ = params.load_preset("thesis")
    grid = evaluate.crank_angle_grid(spec)
    pasted = (np.arange(-5.0, 726.0, 5.0), None)
    pasted = (pasted[0], 0.12 + 3.0 * np.exp(-((pasted[0] - 372) / 25) ** 2))
    for name, edits in EDITS.items():
        path = tmp / f"{name}.xlsx"
        trace = pasted if name == "edit_trace" else None
        edit_cells(files["thesis"], path, edits, trace)
        values = params.validate(spec, {**base, **edits}, trace_points=3 if trace else 0)
        tables = {"trace_crank_angle": trace[0], "trace_pressure": trace[1]} if trace else {}
        expected[name] = evaluate.evaluate(spec, values, tables, grid)
        files[name] = path
    invalid = tmp / "edit_invalid.xlsx"
    edit_cells(files["thesis"], invalid, {"rod_length": 40.0})
    files["edit_invalid"] = invalid
    converted = recalc.convert(list(files.values()), tmp / "recalculated")
    out = {}
    for name, recalculated_path in zip(files, converted):
        cached = named_values(open_workbook(files[name]))
        recalculated = named_values(open_workbook(recalculated_path))
        want = expected.get(name)
        if want is None and name != "edit_invalid":
            values, tables, grid_ = inputs_of(spec, cached, files[name])
            want = evaluate.evaluate(spec, values, tables, grid_)
        out[name] = (files[name], recalculated_path, want, cached, recalculated)
    return spec, out


@pytest.mark.parametrize("name", list(BUILDS) + list(EDITS))
def test_every_formula_matches_numpy_after_recalculation(workbooks, name):
    spec, files = workbooks
    _, _, expected, cached, recalculated = files[name]
    assert recalculated["q_inputs_valid"] == 1, recalculated["q_input_status"]
    comparisons = compare(spec, expected, recalculated, cached)
    assert len(comparisons) == len(spec.quantities())
    bad = [(c.name, c.relative) for c in comparisons if not c.ok]
    assert not bad, f"formulas disagree with numpy: {bad}"


@pytest.mark.parametrize("name", list(BUILDS))
def test_cached_values_equal_recalculated_values(workbooks, name):
    spec, files = workbooks
    _, _, expected, cached, recalculated = files[name]
    comparisons = compare(spec, expected, recalculated, cached)
    worst = sorted(((c.cached_relative, c.name) for c in comparisons
                    if not c.name.endswith(("_max_angle", "_min_angle"))), reverse=True)
    assert worst[0][0] < 1e-9, worst[:3]


def test_measured_trace_drives_the_pressure_column(workbooks):
    spec, files = workbooks
    recalculated = files["measured"][4]
    assert recalculated["p_pressure_source"] == 1
    # the measured column equals a plain linear interpolation of the file's points
    trace_a = np.array([v for v in recalculated["p_trace_crank_angle"] if v is not None])
    trace_p = np.array([v for v in recalculated["p_trace_pressure"] if v is not None])
    grid = np.array(recalculated["q_crank_angle"])
    assert np.allclose(recalculated["q_cylinder_pressure"], np.interp(grid, trace_a, trace_p),
                       rtol=1e-12)
    assert recalculated["q_cylinder_pressure_max"] == pytest.approx(4.6, abs=0.05)


def test_impossible_geometry_shows_words_not_errors(workbooks):
    spec, files = workbooks
    recalculated = files["edit_invalid"][4]
    assert recalculated["q_inputs_valid"] == 0
    assert "rod too short" in recalculated["q_input_status"]
    assert "连杆过短" in recalculated["q_input_status"]
    torque = recalculated["q_torque"]
    assert all(v in (None, "") for v in torque), "results must be blank, not #NUM!"
