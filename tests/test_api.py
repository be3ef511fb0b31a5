"""The Python API: compute, Results, to_excel, read, verify — and the defects of
issue 9 (English status, engine-saved files audited, near-zero scalars, caches)."""
import re
import zipfile

import numpy as np
import pandas as pd
import pytest

import crankbook
from crankbook.errors import (GeometryError, ParameterValueError, UnknownParameterError,
                              UnknownPresetError, WorkbookReadError)
from crankbook.audit.returned import audit_workbook
from crankbook.writer.series_sheet import cached
from crankbook.reading.xlsx_reader import XlsxBook
from tests.conftest import run_cli


@pytest.fixture(scope="module")
def thesis():
    return crankbook.compute("thesis")


def test_compute_gives_frames_in_sheet_units(thesis):
    frame = thesis.series()
    assert frame.index.name == "crank_angle" and len(frame) == 721
    assert frame.index[0] == 0 and frame.index[-1] == 720
    # torque = F_t·r in N·m from the N and mm columns (an identity, not a copy)
    assert np.allclose(frame["torque"], frame["tangential_force"] * 50 / 1000)
    assert thesis.scalars["crank_rod_ratio"] == pytest.approx(1 / 3)
    assert thesis.scalars["reciprocating_mass"] == pytest.approx(0.515, abs=5e-4)
    assert thesis.parameters["bore"] == 88 and thesis.grids == [
        "crank_angle", "holzer_frequency", "torsion_order", "torsion_station", "campbell_speed",
        "sweep_candidate", "sweep_speed", "response_order", "steady_step", "rb_row", "orbit_angle"]
    course = crankbook.compute("course-design")
    assert len(course.series("pos_crank_angle")) == 30
    assert "pos_crank_angle" in course.grids
    with pytest.raises(crankbook.CrankbookError, match="unknown grid"):
        course.series("nope")


def test_parameters_and_step_change_the_results():
    slow = crankbook.compute("thesis", speed=2500, step=2)
    assert len(slow.series()) == 361
    fast = crankbook.compute("thesis", speed=5000, step=2)
    # inertia force scales with ω²
    assert np.allclose(fast["inertia_force"], 4 * slow["inertia_force"])


def test_a_pressure_dataframe_is_a_measured_trace(tmp_path):
    angles = np.arange(0.0, 720.0, 5.0)
    trace = pd.DataFrame({"angle": angles, "p": 0.1 + 3 * np.exp(-((angles - 370) / 30) ** 2)})
    from_frame = crankbook.compute("thesis", pressure=trace)
    assert from_frame.parameters["pressure_source"] == 1
    csv = tmp_path / "trace.csv"
    trace.to_csv(csv, index=False)
    from_file = crankbook.compute("thesis", pressure=csv)
    assert np.array_equal(from_frame["cylinder_pressure"], from_file["cylinder_pressure"])
    assert from_frame["cylinder_pressure_max"] == pytest.approx(3.1, abs=0.01)


@pytest.mark.parametrize("kwargs,error,words", [
    ({"speed": 0}, ParameterValueError, "parameter speed = 0: must be > 0"),
    ({"speed": "fast"}, ParameterValueError, "'fast' is not a number"),
    ({"sped": 3000}, UnknownParameterError, "unknown parameter 'sped'"),
    ({"rod_length": 40}, GeometryError, "rod too short"),
    ({"preset": "nope"}, UnknownPresetError, "unknown preset 'nope'"),
    ({"preset": "../presets/thesis"}, UnknownPresetError, "unknown preset"),
    ({"step": 7}, crankbook.CrankbookError, "must divide 720"),
])
def test_bad_input_raises_the_command_lines_typed_error(kwargs, error, words):
    with pytest.raises(error, match=words.replace("(", r"\(")):
        crankbook.compute(**kwargs)


def test_the_command_line_says_the_same(tmp_path):
    done = run_cli("build", "--set", "speed=0", "-o", tmp_path / "x.xlsx")
    with pytest.raises(ParameterValueError) as caught:
        crankbook.compute(speed=0)
    assert done.stderr.strip() == f"crankbook: error: {caught.value}"


def test_read_gives_back_what_compute_wrote(tmp_path, thesis):
    path = thesis.to_excel(tmp_path / "thesis.xlsx", lang="en")
    back = crankbook.read(path)
    assert back.template == "engine" and back.preset["name"] == "thesis"
    assert back.values == thesis.values
    for key, value in thesis.results.items():
        assert np.allclose(np.asarray(back[key], float), np.asarray(value, float), rtol=1e-15,
                           atol=0, equal_nan=True), key
    pd.testing.assert_frame_equal(back.series(), thesis.series())


def test_read_says_when_the_stored_results_are_not_the_inputs(tmp_path):
    """An input typed with calculation set to manual (or by a script) leaves the old
    results in the file: read gives them as stored, and warns in one line naming the
    first result the inputs no longer give; the untouched file reads without a word."""
    import warnings
    from crankbook.errors import StaleWorkbookWarning
    from tests.conftest import edit_cells
    path = crankbook.compute("thesis", step=6).to_excel(tmp_path / "thesis.xlsx")
    with warnings.catch_warnings():
        warnings.simplefilter("error", crankbook.CrankbookWarning)
        stored = crankbook.read(path)
    edit_cells(path, tmp_path / "manual.xlsx", {"speed": 3000.0})
    with pytest.warns(StaleWorkbookWarning, match="no longer give .*recalculate=True") as said:
        manual = crankbook.read(tmp_path / "manual.xlsx")
    name = said[0].message.name
    assert name.startswith("q_") and name in str(said[0].message)
    # the warning is about what was read: the old speed's results under the new input
    assert manual.parameters["speed"] == 3000.0
    assert manual.scalars["mean_torque"] == stored.scalars["mean_torque"]
    fresh = crankbook.compute("thesis", step=6, speed=3000.0)
    assert fresh.results[name[2:]] != pytest.approx(manual.results[name[2:]])
    # a rod typed too short: its sheets must be blank, yet the file says its inputs
    # are valid and holds the old rod's results
    edit_cells(path, tmp_path / "short.xlsx", {"rod_length": 40.0})
    with pytest.warns(StaleWorkbookWarning) as said:
        crankbook.read(tmp_path / "short.xlsx")
    assert said[0].message.name == "q_inputs_valid"


def test_a_workbook_from_before_an_input_existed_reads_with_its_default(tmp_path):
    """A workbook written by an earlier crankbook lacks the inputs added since: read
    takes their defaults (the behaviour the earlier version computed), per-item ones
    one per item."""
    thesis = crankbook.compute("thesis", step=6)
    path = thesis.to_excel(tmp_path / "thesis.xlsx", lang="en")
    older = tmp_path / "older.xlsx"
    with zipfile.ZipFile(path) as zin, zipfile.ZipFile(older, "w") as zout:
        for item in zin.infolist():
            data = zin.read(item.filename)
            if item.filename == "xl/workbook.xml":
                data, count = re.subn(rb'<definedName name="p_(operating_)?trace_speed"[^<]*'
                                      rb'</definedName>', b"", data)
                assert count == 2
            zout.writestr(item, data)
    back = crankbook.read(older)
    assert back.parameters["trace_speed"] == 0.0
    assert back.parameters["operating_trace_speed"] == [0.0] * 12
    assert back.scalars["mean_torque"] == thesis.scalars["mean_torque"]


def test_workbooks_record_what_wrote_them(tmp_path, thesis):
    book = XlsxBook(thesis.to_excel(tmp_path / "t.xlsx"))
    assert book.custom_properties["crankbook_template"] == "engine"
    assert book.custom_properties["crankbook_version"] == crankbook.__version__
    assert book.custom_properties["crankbook_preset"] == "thesis"


def test_no_infinity_or_nan_is_ever_cached(tmp_path, thesis):
    assert cached(float("inf")) == "" and cached(float("nan")) == "" and cached(2.5) == 2.5
    path = thesis.to_excel(tmp_path / "t.xlsx")
    with zipfile.ZipFile(path) as archive:
        for name in archive.namelist():
            if name.startswith("xl/worksheets/"):
                text = archive.read(name)
                assert b"inf</v>" not in text and b"nan</v>" not in text, name


def test_same_input_same_bytes(tmp_path, thesis):
    a, b = tmp_path / "a.xlsx", tmp_path / "b.xlsx"
    thesis.to_excel(a)
    crankbook.compute("thesis").to_excel(b)
    assert a.read_bytes() == b.read_bytes()


@pytest.mark.libreoffice
def test_verify_and_read_recalculated(tmp_path, soffice):
    result = crankbook.compute("thesis", speed=3100, step=4)
    path = result.to_excel(tmp_path / "t.xlsx", lang="en")
    frame = crankbook.verify(path)
    assert frame.attrs["valid"] == 1 and frame["ok"].all()
    assert len(frame) == len(result.spec.quantities())        # one row per q_ name
    back = crankbook.read(path, recalculate=True)
    assert np.allclose(back["torque"], result["torque"], rtol=0, atol=1e-9 * 300)
    done = run_cli("verify", path)                  # an English workbook verifies (issue 9)
    assert done.returncode == 0, done.stdout


def test_verify_names_what_a_workbook_does_not_define(tmp_path, ssconvert):
    """A workbook built before a quantity existed lacks its name: verify lists it as not
    in the workbook and says to rebuild, where it printed an infinite difference; the
    audit's finding says it may be an older workbook's as well as a deletion."""
    path = crankbook.compute("thesis", step=12).to_excel(tmp_path / "t.xlsx")
    older = tmp_path / "older.xlsx"
    with zipfile.ZipFile(path) as source:
        items = {n: source.read(n) for n in source.namelist()}
    pattern = rb'<definedName name="q_gas_pressure_looks_like_bar"[^>]*>[^<]*</definedName>'
    assert re.search(pattern, items["xl/workbook.xml"])
    items["xl/workbook.xml"] = re.sub(pattern, b"", items["xl/workbook.xml"])
    with zipfile.ZipFile(older, "w", zipfile.ZIP_DEFLATED) as target:
        for name, data in items.items():
            target.writestr(name, data)
    with pytest.raises(KeyError, match="this workbook does not hold it"):
        crankbook.read(older)["gas_pressure_looks_like_bar"]
    frame = crankbook.verify(older, engine="gnumeric")
    assert list(frame.name[frame.absent]) == ["q_gas_pressure_looks_like_bar"]
    assert frame.ok[~frame.absent].all()
    done = run_cli("verify", older, "--engine", "gnumeric")
    assert done.returncode == 1, done.stdout
    line = next(t for t in done.stdout.splitlines() if "q_gas_pressure_looks_like_bar" in t)
    assert line.rstrip().endswith("NOT IN THE WORKBOOK")
    assert f"1 of {len(frame)} names are not in the workbook" in done.stdout
    assert "rebuild it with 'crankbook build'" in done.stdout
    assert "differ from numpy" not in done.stdout and "DIFFERS" not in done.stdout
    # the auditor is told the same two readings of a missing result name
    done = run_cli("audit", older)
    assert done.returncode == 1
    assert "q_gas_pressure_looks_like_bar        the defined name is missing" in done.stdout
    assert "built by an older crankbook lacks the result names" in done.stdout


@pytest.mark.parametrize("engine", ["libreoffice", "gnumeric"])
def test_audit_accepts_files_the_engines_saved_unchanged(checked, engine):
    for name in ("thesis_step3", "course", "optimization"):
        spec, findings, recalculated, rule = audit_workbook(checked[name].saved[engine])
        assert not findings, (engine, name, findings[:3])


def test_verify_accepts_a_mean_torque_that_is_zero_up_to_rounding(checked, tmp_path):
    """A constant-pressure trace: the mean torque is 0 up to rounding in every engine."""
    trace = pd.DataFrame({"a": np.arange(0.0, 720.0, 10.0), "p": 0.1})
    result = crankbook.compute("thesis", pressure=trace)
    assert abs(result["mean_torque"]) < 1e-9
    frame = crankbook.verify(result.to_excel(tmp_path / "c.xlsx"), engine="gnumeric")
    assert frame["ok"].all(), frame[~frame.ok]


def test_charts_stand_beside_their_own_columns_whatever_the_trace(tmp_path):
    """The pressure sheet's charts were anchored after its input table — at column
    1,513 of a wide trace file, or dropped past Excel's last column; they now stand
    beside the sheet's own columns and the trace block follows them."""
    import openpyxl
    angle = np.arange(0.0, 720.0, 2.0)
    frame = pd.DataFrame({"angle": angle,
                          **{f"{n}": 0.1 + 4 * np.exp(-((angle - 372) / 30) ** 2)
                             for n in (1000, 2000, 3000, 4000, 5000)}})
    path = crankbook.compute("thesis", pressure=frame, step=6.0).to_excel(tmp_path / "t.xlsx",
                                                                        lang="en")
    book = openpyxl.load_workbook(path)
    sheet = book["Pressure"]
    trace = min(c for c in range(1, 60)
                if str(sheet.cell(3, c).value or "").startswith("Measured crank angle"))
    anchors = [chart.anchor._from.col + 1 for chart in sheet._charts]      # 1-based
    assert anchors and all(col < trace for col in anchors), (anchors, trace)


def _without_values(path, out):
    """``path`` as a program that does not calculate saves it (openpyxl: every formula
    kept, no stored value), made in the archive itself: openpyxl's own round trip of
    an engine workbook takes a quarter of a minute."""
    with zipfile.ZipFile(path) as archive:
        items = {n: archive.read(n) for n in archive.namelist()}
    for name, data in items.items():
        if name.startswith("xl/worksheets/sheet"):
            items[name] = re.sub(rb"(<f[^>]*/>|<f[^>]*>[^<]*</f>)<v>[^<]*</v>", rb"\1", data)
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, data in items.items():
            archive.writestr(name, data)
    return out


def test_an_export_never_writes_blank_or_stale_results(tmp_path, soffice):
    """A workbook saved without calculated values (the docs' openpyxl edit): export
    recalculates it in LibreOffice first and says so, where it wrote NaN (torsion,
    trace: the same reading) or crashed (bearing); Python's read of it is refused by
    the writer, not exported.  One whose stored results its inputs no longer give
    (typed with calculation set to manual) is recalculated too, where the old
    results were exported.  A workbook whose inputs break a rule holds blank
    results by design: each export refuses it in one line naming the rule, and
    writes nothing."""
    import csv
    from tests.conftest import edit_cells

    def orbit(csv_path):
        with open(csv_path, newline="", encoding="utf-8-sig") as handle:
            return [[float(row[k]) for k in ("e_u/c", "h_min [um]")]
                    for row in csv.DictReader(handle)]

    path = crankbook.compute("thesis", step=5.0).to_excel(tmp_path / "thesis.xlsx")
    typed = _without_values(path, tmp_path / "typed.xlsx")
    assert run_cli("export", "bearing", path, "-o", tmp_path / "stored.csv").returncode == 0
    done = run_cli("export", "bearing", typed, "-o", tmp_path / "typed.csv")
    assert done.returncode == 0, done.stderr
    assert "recalculated in LibreOffice first" in done.stdout
    assert np.allclose(orbit(tmp_path / "typed.csv"), orbit(tmp_path / "stored.csv"),
                       rtol=1e-6, atol=1e-6)
    with pytest.warns(crankbook.CrankbookWarning, match="no calculated values"):
        uncalculated = crankbook.read(typed)
    with pytest.raises(WorkbookReadError, match="recalculate=True"):
        uncalculated.to_bearing_csv(tmp_path / "python.csv")
    assert not (tmp_path / "python.csv").exists()

    # a speed typed with calculation set to manual: the stored orbit is the old speed's,
    # so export recalculates and writes the new speed's, as a fresh build at it has
    edit_cells(path, tmp_path / "manual.xlsx", {"speed": 3000.0})
    done = run_cli("export", "bearing", tmp_path / "manual.xlsx", "-o", tmp_path / "m.csv")
    assert done.returncode == 0 and "inputs no longer give" in done.stdout, done.stdout
    fresh = crankbook.compute("thesis", step=5.0, speed=3000.0).to_excel(tmp_path / "n.xlsx")
    assert run_cli("export", "bearing", fresh, "-o", tmp_path / "n.csv").returncode == 0
    assert np.allclose(orbit(tmp_path / "m.csv"), orbit(tmp_path / "n.csv"),
                       rtol=1e-6, atol=1e-6)
    assert not np.allclose(orbit(tmp_path / "m.csv"), orbit(tmp_path / "stored.csv"),
                           rtol=1e-3)

    # too short a rod typed with calculation set to manual: the old results are not
    # exported; recalculated, the file is refused in one line naming the rule
    edit_cells(path, tmp_path / "short-manual.xlsx", {"rod_length": 40.0})
    done = run_cli("export", "bearing", tmp_path / "short-manual.xlsx", "-o",
                   tmp_path / "sm.csv")
    assert done.returncode == 2 and "rod too short" in done.stderr, (done.stdout, done.stderr)
    assert not (tmp_path / "sm.csv").exists()

    # too short a rod, typed and saved uncalculated: recalculated, then refused
    edit_cells(path, tmp_path / "short.xlsx", {"rod_length": 40.0})
    broken = _without_values(tmp_path / "short.xlsx", tmp_path / "broken.xlsx")
    done = run_cli("export", "bearing", broken, "-o", tmp_path / "b.csv")
    assert done.returncode == 2, (done.stdout, done.stderr)
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and "rod too short" in lines[0] and "Traceback" not in lines[0]
    assert not (tmp_path / "b.csv").exists()
    with pytest.warns(crankbook.CrankbookWarning):
        blank = crankbook.read(broken)
    from crankbook.writer.torsion_csv import write_trace
    for export, output in ((blank.to_torsion_csv, "tv"),
                           (lambda out: write_trace(blank, out), "t.csv")):
        with pytest.raises(WorkbookReadError, match="rod too short"):
            export(tmp_path / output)
        assert not (tmp_path / output).exists()
