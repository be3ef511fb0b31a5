"""Class packs as a teacher meets them: a Chinese class from a GBK roster, answers
typed in the guide's order (made from the key workbooks' own names, not from the
grader's code), the exact scores the rubric gives, feedback in the class's
language, resubmission, no answer leaks, bad rosters, hostile files."""
import csv
import hashlib
import io
import json
import math
import re
import shutil
import zipfile

import numpy as np
import openpyxl
import pytest

from crankbook.reading import recalc
from crankbook.assignment import template as templates
from crankbook.assignment.scoring import score_cell
from crankbook.calc import mechanism
from tests.conftest import (cells_under_charts, named, run_cli, run_program,
                            texts_cut_by_a_neighbour)

ROSTER = [f"s{n:02d}" for n in range(1, 14)]
NAMES = {sid: f"学生{n}号" for n, sid in enumerate(ROSTER, start=1)}
ASSIGNMENT = templates.load("course-design")
POSITION_ITEMS = [k for s in ASSIGNMENT.sheets if s.rows == "positions" for k in s.items]
CAM_ITEMS = [k for s in ASSIGNMENT.sheets if s.rows == "cam_angle" for k in s.items]


def write_roster(path, ids, encoding="gbk", headers=("学号", "姓名", "班级")):
    text = ",".join(headers) + "\r\n" + "".join(f"{i},{NAMES.get(i, i)},机械1班\r\n" for i in ids)
    path.write_bytes(text.encode(encoding))


@pytest.fixture(scope="module")
def pack(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("pack")
    roster = tmp / "roster.csv"
    write_roster(roster, ROSTER)
    done = run_cli("assign", "--preset", "course-design", "--roster", roster, "--seed", "7",
                   "--lang", "zh", "-o", tmp / "class")
    assert done.returncode == 0, done.stderr
    return tmp / "class"


def guide_order(names):
    """Rows of the key's angle-sorted position table in the guide's order: A0…A11, the
    lowest position, the two maximum-speed positions, then the same + 360°."""
    raw = np.asarray(names["q_raw_crank_angle"], float)
    grid = np.asarray(names["q_pos_crank_angle"], float)
    wanted = np.concatenate([raw, raw + 360.0])
    return [int(np.argmin(np.abs(grid - a))) for a in wanted]


def key_answers(pack, sid, order="guide"):
    """What a student following the statement types: the key workbook's values, the
    position tables row by row in the guide's order (or the key's own order)."""
    names = named(pack / "keys" / f"{sid}.xlsx")
    rows = guide_order(names) if order == "guide" else list(range(30))
    cam_grid = list(names["q_cam_angle"])
    cam_rows = [cam_grid.index(a) for a in ASSIGNMENT.row_angles["cam_angle"]]
    out = {}
    for item in ASSIGNMENT.items:
        value = names[f"q_{item.key}"]
        if item.key in POSITION_ITEMS:
            value = [value[i] for i in rows]
        elif item.key in CAM_ITEMS:           # asked at the listed cam angles
            value = [value[i] for i in cam_rows]
        out[item.key] = value
    return out


def fill(source, target, answers, formulas=False, edit_parameters=None):
    book = openpyxl.load_workbook(source)
    for key, value in answers.items():
        sheet, ref = next(iter(book.defined_names[f"a_{key}"].destinations))
        block = book[sheet][ref.replace("$", "")]
        cells = [c for row in block for c in row] if isinstance(block, tuple) else [block]
        values = value if isinstance(value, list) else [value]
        for cell, v in zip(cells, values):
            cell.value = (f"={v!r}*1" if formulas else v) if v is not None else None
    for key, value in (edit_parameters or {}).items():
        sheet, ref = next(iter(book.defined_names[f"p_{key}"].destinations))
        book[sheet][ref.replace("$", "")] = value
    target.parent.mkdir(parents=True, exist_ok=True)
    book.save(target)


def scaled(answers, key, factor):
    out = dict(answers)
    value = out[key]
    out[key] = [v * factor for v in value] if isinstance(value, list) else value * factor
    return out


def read_gradebook(results):
    with open(results / "gradebook.csv", newline="", encoding="utf-8-sig") as handle:
        rows = list(csv.DictReader(handle))
    return {r["student_id"]: r for r in rows if r["student_id"]}, rows


@pytest.fixture(scope="module")
def graded(pack, tmp_path_factory, soffice):
    subs = tmp_path_factory.mktemp("submissions")
    student = pack / "students"
    perfect = {sid: key_answers(pack, sid) for sid in ROSTER}
    # s01 perfect, in a nested LMS folder; s02 blank; s03 within tolerance (0.4 %, and
    # 0.3° on every angle: angles are judged in degrees)
    fill(student / "s01.xlsx", subs / "lms" / "s01_attempt1" / "course.xlsx", perfect["s01"])
    shutil.copy(student / "s02.xlsx", subs / "s02.xlsx")

    def near(key, x):
        return x + 0.3 if ASSIGNMENT.item[key].angle_tolerance is not None else x * 1.004
    fill(student / "s03.xlsx", subs / "S-s03.xlsx",
         {k: ([near(k, x) for x in v] if isinstance(v, list) else near(k, v))
          for k, v in perfect["s03"].items()})
    # s04 the slider velocity in mm/s; s05 the balancing torque with its sign flipped
    fill(student / "s04.xlsx", subs / "s04.xlsx",
         scaled(perfect["s04"], "pos_slider_velocity", 1000.0))
    fill(student / "s05.xlsx", subs / "s05.xlsx",
         scaled(perfect["s05"], "pos_balancing_torque", -1.0))
    # s06: consequential — their own r and l 10 % too long, everything after consistent
    fill(student / "s06.xlsx", subs / "s06.xlsx", consequential_answers(pack, "s06"))
    # s07 hands in s08's (perfect) workbook; s08 hands in their own
    fill(student / "s08.xlsx", subs / "s08.xlsx", perfect["s08"])
    (subs / "s07").mkdir()
    shutil.copy(subs / "s08.xlsx", subs / "s07" / "x.xlsx")
    # s09 changed a parameter but answered the assignment
    fill(student / "s09.xlsx", subs / "s09.xlsx", perfect["s09"], edit_parameters={"stroke": 1.0})
    # s10 corrupt; s11 missing; s12 typed formulas, saved without values (LibreOffice recalcs)
    (subs / "s10.xlsx").write_bytes(b"PK\x03\x04 this is not a workbook")
    fill(student / "s12.xlsx", subs / "s12.xlsx", perfect["s12"], formulas=True)
    # s13 lists the positions sorted by angle instead of in the guide's order
    fill(student / "s13.xlsx", subs / "s13.xlsx", key_answers(pack, "s13", order="key"))
    # a file nobody can be matched to, with a hostile name and id
    stranger = subs / "+cmd.xlsx"
    fill(student / "s01.xlsx", stranger, {})
    book = openpyxl.load_workbook(stranger)
    sheet, ref = next(iter(book.defined_names["s_student_id"].destinations))
    book[sheet][ref.replace("$", "")] = '=HYPERLINK("http://evil","x")'
    book.save(stranger)
    results = subs.parent / "results"
    done = run_cli("grade", pack, subs, "-o", results)
    assert done.returncode == 0, done.stderr
    by_id, rows = read_gradebook(results)
    return {"rows": rows, "by_id": by_id, "results": results, "perfect": perfect,
            "subs": subs}


def consequential_answers(pack, sid):
    """s06's answers: r and l 10 % off, the rest computed with their own r and l."""
    from crankbook.spec import params
    from crankbook.assignment.grade import manifest_values
    from crankbook.assignment.key import expected, key_results
    spec, _, preset = params.load_preset("course-design")
    with open(pack / "manifest.csv", newline="", encoding="utf-8-sig") as handle:
        row = next(r for r in csv.DictReader(handle) if r["student_id"] == sid)
    key = key_results(ASSIGNMENT, spec, preset, manifest_values(spec, row))
    own = expected(ASSIGNMENT, spec, key, overrides={
        "crank_radius": key.results["crank_radius"] * 1.1,
        "rod_length": key.results["rod_length"] * 1.1})
    return {k: (v["value"].tolist() if k in POSITION_ITEMS else float(v["value"][0]))
            for k, v in own.items()}


def score(graded, sid):
    return float(graded["by_id"][sid]["score"])


def item_points(graded, sid, key):
    row = graded["by_id"][sid]
    column = next(c for c in row if c.endswith(f"(a_{key})"))
    return float(row[column])


def test_class_statuses(graded):
    statuses = {sid: r["status"] for sid, r in graded["by_id"].items()}
    assert statuses["s10"] == "unreadable" and statuses["s11"] == "missing"
    assert all(statuses[s] == "graded" for s in ROSTER if s not in ("s10", "s11"))
    unmatched = [r for r in graded["rows"] if r["status"] == "unmatched"]
    assert len(unmatched) == 1 and "+cmd.xlsx" in unmatched[0]["notes"]


def test_answers_in_the_guides_order_or_any_order_score_full(graded):
    assert score(graded, "s01") == 100.0
    assert score(graded, "s13") == 100.0          # sorted by angle: paired through the angles
    assert score(graded, "s03") == 100.0          # within the 1 % tolerance


def test_blank_scores_zero_and_is_flagged(graded):
    assert score(graded, "s02") == 0.0 and "blank" in graded["by_id"]["s02"]["flags"]


def test_unit_slip_earns_half_of_the_item(graded):
    key = "pos_slider_velocity"
    points = item_points(graded, "s04", key)
    item = ASSIGNMENT.item[key]
    # cells where the velocity is zero (dead centres) are right anyway (0 × 1000 = 0)
    zero = sum(abs(v) <= item.abs_floor for v in graded["perfect"]["s04"][key])
    expected = item.points * (zero + 0.5 * (30 - zero)) / 30
    assert points == pytest.approx(expected, abs=0.01)
    assert score(graded, "s04") == pytest.approx(100 - item.points + expected, abs=0.02)


def test_sign_slip_earns_half_of_the_item(graded):
    key = "pos_balancing_torque"
    item = ASSIGNMENT.item[key]
    credit = []
    for v in graded["perfect"]["s05"][key]:
        if abs(2 * v) <= max(item.tolerance * abs(v), item.abs_floor):
            credit.append(1.0)                    # −v is v within the tolerance
        elif abs(v) > item.abs_floor:
            credit.append(0.5)                    # the floor tells it from 0: a sign slip
        else:
            credit.append(0.0)
    expected = item.points * sum(credit) / 30
    assert item_points(graded, "s05", key) == pytest.approx(expected, abs=0.01)


def test_consequential_errors_earn_the_rubric_fraction(graded):
    row = graded["by_id"]["s06"]
    assert item_points(graded, "s06", "crank_radius") == 0.0
    assert item_points(graded, "s06", "extreme_angle") == 3.0      # independent of r and l
    for key in ("pos_slider_velocity", "pos_balancing_torque", "flywheel_inertia"):
        item = ASSIGNMENT.item[key]
        assert item_points(graded, "s06", key) >= 0.8 * item.points - 1e-9, (key, row)


def test_another_students_file_is_flagged_for_the_teacher_only(graded):
    copier, source = graded["by_id"]["s07"], graded["by_id"]["s08"]
    assert {"wrong-student", "copy-suspect"} <= set(copier["flags"].split(";"))
    assert "s08" in copier["notes"]
    assert not {"copy-suspect", "wrong-student"} & set(source["flags"].split(";")), \
        "the student copied from is told apart from the copier"
    report = openpyxl.load_workbook(graded["results"] / "integrity.xlsx").active
    rows = [[c.value for c in row] for row in report.iter_rows(min_row=5)]
    assert any(str(r[0]).startswith("s07") and str(r[1]).startswith("s08") for r in rows)
    assert not any(str(r[0]).startswith("s08") for r in rows)


def test_no_student_sees_anything_about_another(graded):
    """Feedback files and the LMS import never name a classmate, whatever the flags."""
    others = {sid: [o for o in ROSTER if o != sid] for sid in ROSTER}
    lms = {r["identifier"]: r["feedback"] for r in csv.DictReader(io.StringIO(
        (graded["results"] / "lms-import.csv").read_text(encoding="utf-8-sig")))}
    for sid in ROSTER:
        text = (graded["results"] / "feedback" / f"{sid}.md").read_text(encoding="utf-8")
        for other in others[sid]:
            assert other not in text and NAMES[other] not in text, (sid, other)
            assert other not in lms[sid], (sid, other)
        assert "feedback/" not in lms[sid] and ".md" not in lms[sid]


def test_edited_parameter_is_flagged_but_graded_against_the_assignment(graded):
    row = graded["by_id"]["s09"]
    assert row["flags"] == "parameters-changed" and "stroke" in row["notes"]
    assert score(graded, "s09") == 100.0


def test_formulas_saved_without_values_are_recalculated(graded):
    assert score(graded, "s12") == 100.0


def test_csv_outputs_cannot_execute_and_ids_stay_ids(graded):
    for name in ("gradebook.csv", "lms-import.csv"):
        text = (graded["results"] / name).read_text(encoding="utf-8-sig")
        for row in csv.reader(io.StringIO(text)):
            for field in row:
                assert not field.startswith(("=", "+", "-", "@")), (name, field)
    lms = list(csv.DictReader(io.StringIO((graded["results"] / "lms-import.csv")
                                          .read_text(encoding="utf-8-sig"))))
    assert [r["identifier"] for r in lms] == ROSTER


def test_missing_students_are_blank_in_the_lms_import(graded):
    lms = {r["identifier"]: r for r in csv.DictReader(io.StringIO(
        (graded["results"] / "lms-import.csv").read_text(encoding="utf-8-sig")))}
    assert lms["s11"]["grade"] == "" and lms["s10"]["grade"] == ""
    assert graded["by_id"]["s11"]["status"] == "missing" and graded["by_id"]["s11"]["score"] == ""
    assert float(lms["s01"]["grade"]) == 100.0


def test_a_chinese_class_gets_chinese_feedback_and_report(graded):
    feedback = (graded["results"] / "feedback" / "s04.md").read_text(encoding="utf-8")
    assert "得分" in feedback and "单位换算错误" in feedback and "滑块速度 v_B" in feedback
    assert "a_pos_" not in feedback and "unit slip" not in feedback
    assert "学生4号" in feedback
    book = openpyxl.load_workbook(graded["results"] / "class-report.xlsx")
    assert {"各题", "总分分布", "学生"} <= set(book.sheetnames)
    assert book["各题"]._charts and book["总分分布"]._charts
    assert book["各题"]["A4"].value == "极位夹角 θ"
    counts = [book["总分分布"].cell(row=r, column=4).value for r in range(4, 14)]
    assert all(isinstance(c, int) or float(c).is_integer() for c in counts)
    assert sum(counts) == 11                       # the graded students
    # every column headed, the band's words apart from the right-aligned counts (a
    # count against a band read "10–10 %"), and an axis of at most ten steps
    sheet = book["总分分布"]
    assert all(sheet.cell(row=3, column=c).value for c in range(1, 5))
    assert [sheet.cell(row=r, column=1).value for r in (4, 13)] == ["0–10", "90–100"]
    with zipfile.ZipFile(graded["results"] / "class-report.xlsx") as archive:
        xml = "".join(archive.read(n).decode() for n in archive.namelist()
                      if n.startswith("xl/charts/"))
    axes = re.findall(r'<c:max val="([\d.]+)"/>.*?<c:majorUnit val="([\d.]+)"/>', xml, re.S)
    assert len(axes) == 2 and all(float(top) / float(step) <= 10 for top, step in axes)


def test_the_gradebook_prints_readable(graded, tmp_path):
    """Every column at its longest header or note, fitted one page wide, printed the
    class in text a few points high; now no word of the printed gradebook is smaller
    than 10-point text at 62 % (its box about 7 points tall), whatever the items."""
    pdf = recalc.convert([graded["results"] / "gradebook.xlsx"], tmp_path, target="pdf")[0]
    text = run_program("pdftotext", "-bbox", str(pdf), "-")
    heights = [float(b) - float(a) for a, b in
               re.findall(r'<word xMin="[\d.]+" yMin="([\d.]+)" xMax="[\d.]+" '
                          r'yMax="([\d.]+)">', text)]
    assert heights and min(heights) >= 7.0, min(heights)
    assert "s13" in text and "s01" in text                  # every student is on paper


@pytest.mark.parametrize("mode", ["score-only", "hints"])
def test_feedback_can_keep_the_key_hidden(graded, pack, tmp_path, mode):
    done = run_cli("grade", pack, graded["subs"], "-o", tmp_path / mode, "--feedback", mode)
    assert done.returncode == 0, done.stderr
    text = (tmp_path / mode / "feedback" / "s04.md").read_text(encoding="utf-8")
    assert "参考答案" not in text
    names = named(pack / "keys" / "s04.xlsx")
    for secret in names["q_pos_slider_velocity"][1:5] + [names["q_crank_radius"]]:
        assert f"{secret:.6g}" not in text
    if mode == "hints":
        assert "单位换算错误" in text          # says what is wrong and why
    else:
        assert "|" not in text


def test_a_resubmission_round_keeps_the_best_or_latest(graded, pack, tmp_path):
    second = tmp_path / "round2"
    fill(pack / "students" / "s04.xlsx", second / "s04.xlsx", graded["perfect"]["s04"])
    shutil.copy(pack / "students" / "s05.xlsx", second / "s05.xlsx")     # blank this time
    for keep in ("best", "latest"):
        done = run_cli("grade", pack, second, "-o", tmp_path / keep, "--previous",
                       graded["results"], "--keep", keep)
        assert done.returncode == 0, done.stderr
        rows, _ = read_gradebook(tmp_path / keep)
        assert float(rows["s04"]["score"]) == 100.0
        assert float(rows["s01"]["score"]) == 100.0 and "沿用" in rows["s01"]["notes"]
        first = score(graded, "s05")
        assert float(rows["s05"]["score"]) == (first if keep == "best" else 0.0)


def test_the_statement_and_the_key_agree_on_the_resisting_torque(graded, pack):
    """M_r is the mean of M_d = −M_b, positive for an engine: the statement says so."""
    names = named(pack / "keys" / "s01.xlsx")
    driving = -np.asarray(names["q_pos_balancing_torque"])
    assert names["q_pos_resisting_torque"] > 0
    assert item_points(graded, "s01", "pos_resisting_torque") == 2.0
    assert "M_d = −M_b" in ASSIGNMENT.statement_en and "M_r > 0" in ASSIGNMENT.statement_en
    closed = np.append(driving, driving[0])
    angles = np.append(names["q_pos_crank_angle"], 720.0)
    trapezoids = np.sum((closed[1:] + closed[:-1]) / 2 * np.diff(angles))
    assert names["q_pos_resisting_torque"] == pytest.approx(trapezoids / 720, rel=1e-9)


@pytest.mark.parametrize("value,expected,unit,floor,reason", [
    (-7.79536, 1.50555e-15, "N·m", 1.0, "wrong"),        # near zero: no ×1000 credit
    (100 * 180 / math.pi, 100.0, "N·m", 1.0, "wrong"),   # no angle slip on a torque
    (100 * 180 / math.pi, 100.0, "rad/s", 0.01, "wrong"),
    (100 * 30 / math.pi, 100.0, "rad/s", 0.01, "unit_slip"),   # rad/s given as rpm
    (0.1, 100.0, "mm", 0.05, "unit_slip"),                # mm given in m
    (-100.0, 100.0, "N·m", 1.0, "sign_slip"),
    (-2.0, 2.0, "N·m", 1.0, "sign_slip"),                # any magnitude the floor tells
    (-0.8, 0.8, "N·m", 1.0, "wrong"),                    # … from zero: not this one
    ("１００", 100.0, "mm", 0.05, "correct"),            # full-width digits (an IME)
    ("５８．８１", 58.81, "m/s", 0.01, "correct"),
    ("100,0", 100.0, "mm", 0.05, "correct"),             # a decimal comma
    ("103.4mm", 103.4, "mm", 0.05, "correct"),           # the header's own unit typed
    ("4.019 m/s", 4.019, "m/s", 0.01, "correct"),
    ("0.1034 m", 103.4, "mm", 0.05, "unit_slip"),        # another unit of the dimension
    ("103.4 N", 103.4, "mm", 0.05, "wrong_unit"),
    ("about 5", 5.0, "mm", 0.05, "not_a_number"),
    (0.0, 4000.0, "N·m", 5.0, "wrong"),                  # a zero is never a slip
    (0.0, 103.4, "mm", 0.05, "wrong"),
    (0.0, 0.0, "N·m", 5.0, "correct"),                   # … but right where the key is 0
    (4.763, -139.05, "N·m", 5.0, "wrong"),               # judged in the item's unit
    (4.0e6, 4000.0, "N·m", 5.0, "unit_slip"),            # N·mm, the textbooks' unit
    (1.3754, 1375.4, "N·m", 5.0, "unit_slip"),           # kN·m: small, yet no zero
    (0.02216, 22.16, "mm", 0.05, "unit_slip"),           # metres for a short stroke
    (0.001, 22.16, "mm", 0.05, "wrong"),
    (-1.3905e5, -139.05, "N·m", 5.0, "unit_slip"),
    (25.3e6, 25.3, "kg·m²", 0.5, "unit_slip"),           # kg·mm²
    (2.53e5, 25.3, "kg·m²", 0.5, "unit_slip"),           # kg·cm²
])
def test_slips_follow_the_items_dimension(value, expected, unit, floor, reason):
    item = templates.Item(key="x", points=1, tolerance=0.01, zh="x", en="x", unit=unit,
                          abs_floor=floor)
    assert score_cell("", value, expected, item, ASSIGNMENT.rubric).reason == reason


def test_synthesis_key_matches_an_independent_synthesis(pack):
    with open(pack / "manifest.csv", newline="", encoding="utf-8-sig") as handle:
        rows = list(csv.DictReader(handle))
    for row in rows:
        values = named(pack / "keys" / f"{row['student_id']}.xlsx",
                       only={"q_crank_radius", "q_rod_length"})
        values = {k[2:]: v for k, v in values.items()}
        H, e, K = (float(row[f"p_{k}"]) / s for k, s in
                   (("stroke", 1000), ("offset", 1000), ("time_ratio", 1)))
        assert values["crank_radius"] == pytest.approx(
            mechanism.crank_radius_from_design(H, e, K) * 1000, rel=1e-12)
        assert values["rod_length"] == pytest.approx(
            mechanism.rod_length_from_design(H, e, K) * 1000, rel=1e-12)


def test_variants_are_distinct_valid_and_printable(pack):
    with open(pack / "manifest.csv", newline="", encoding="utf-8-sig") as handle:
        rows = list(csv.DictReader(handle))
    assert [r["student_id"] for r in rows] == ROSTER and rows[0]["班级"] == "机械1班"
    assert rows[0]["name"] == "学生1号"
    assert len({r["fingerprint"] for r in rows}) == len(rows)
    for row in rows:
        assert float(row["p_stroke"]) % 10 == 0 and float(row["p_offset"]).is_integer()
        assert round(float(row["p_time_ratio"]), 2) == float(row["p_time_ratio"])
        names = named(pack / "keys" / f"{row['student_id']}.xlsx",
                      only={"q_min_transmission_angle", "q_raw_crank_angle"})
        assert names["q_min_transmission_angle"] >= 45.0
        raw = np.sort(np.asarray(names["q_raw_crank_angle"]) % 360)
        assert np.diff(np.concatenate([raw, [raw[0] + 360]])).min() >= 4.0


def test_no_answer_leaks_into_student_files(pack):
    for sid in ROSTER:
        with zipfile.ZipFile(pack / "students" / f"{sid}.xlsx") as archive:
            blob = b"".join(archive.read(n) for n in archive.namelist())
        assert b"<f>" not in blob, "student files carry no formulas"
        keys = ("crank_radius", "rod_length", "extreme_angle", "flywheel_inertia",
                "pos_resisting_torque", "pos_balancing_torque", "pos_slider_velocity",
                "pos_crank_angle")
        names = named(pack / "keys" / f"{sid}.xlsx",       # only the sheets these are on
                      only={"q_raw_crank_angle", *(f"q_{k}" for k in keys)})
        rows = guide_order(names)
        values = {k: [names[f"q_{k}"][i] for i in rows] if k in POSITION_ITEMS
                  else names[f"q_{k}"] for k in keys}
        secrets = [values["crank_radius"], values["rod_length"], values["extreme_angle"],
                   values["flywheel_inertia"], values["pos_resisting_torque"],
                   *values["pos_balancing_torque"][1:6], *values["pos_slider_velocity"][1:6],
                   *values["pos_crank_angle"][12:15]]
        for secret in secrets:
            for text in (repr(float(secret)), f"{secret:.10g}", f"{secret:.8g}"):
                assert text.encode() not in blob, (sid, text)
        book = openpyxl.load_workbook(pack / "students" / f"{sid}.xlsx")
        assert all(n.startswith(("p_", "a_", "s_")) for n in book.defined_names)
        assert all(ws.sheet_state == "visible" for ws in book.worksheets)


def test_the_student_workbook_asks_everything_the_statement_asks(pack):
    book = openpyxl.load_workbook(pack / "students" / "s01.xlsx")
    for item in ASSIGNMENT.items:
        assert f"a_{item.key}" in book.defined_names, item.key
    assert {"a_min_transmission_angle", "a_pos_energy_swing"} <= set(book.defined_names)
    sheet, ref = next(iter(book.defined_names["a_pos_slider_velocity"].destinations))
    labels = [book[sheet].cell(row=r, column=1).value for r in range(6, 36)]
    assert labels[0] == "A0" and labels[12].startswith("A12") and labels[15] == "A0′"
    headers = " ".join(str(c.value) for c in book[sheet][4] if c.value)
    assert "滑块速度 v_B" in headers and "√" not in headers and "细网格" not in headers


def test_same_roster_and_seed_give_identical_files(pack, tmp_path):
    roster = tmp_path / "roster.csv"
    write_roster(roster, ROSTER[:3])
    digests = []
    for out in ("a", "b"):
        assert run_cli("assign", "--roster", roster, "--seed", "7", "-o",
                       tmp_path / out).returncode == 0
        digests.append({p.relative_to(tmp_path / out): hashlib.sha256(p.read_bytes()).hexdigest()
                        for p in sorted((tmp_path / out).rglob("*")) if p.is_file()})
    assert digests[0] == digests[1]
    with open(tmp_path / "a" / "manifest.csv", encoding="utf-8-sig") as a, \
            open(pack / "manifest.csv", encoding="utf-8-sig") as b:
        assert list(csv.DictReader(a)) == list(csv.DictReader(b))[:3]


def test_without_a_seed_the_class_gets_a_secret_one_it_can_redraw(tmp_path):
    """A student who knows the seed draws their own key, and a small seed is found by
    trying seeds: the default is a random seed, printed to the teacher and kept in
    the class's settings, that redraws the same tasks when given back; a small one
    given on purpose is warned about."""
    roster = tmp_path / "roster.csv"
    write_roster(roster, ROSTER[:1])
    runs = [run_cli("assign", "--roster", roster, "--lang", "en", "-o", tmp_path / out)
            for out in ("a", "b")]
    seeds = [json.loads((tmp_path / out / "assignment.json").read_text())["seed"]
             for out in ("a", "b")]
    for done, seed in zip(runs, seeds):
        assert done.returncode == 0, done.stderr
        assert f"--seed {seed}" in done.stdout and "warning" not in done.stderr
        assert seed >= 10 ** 17
    assert seeds[0] != seeds[1]
    student = ROSTER[0]
    files = [(tmp_path / out / "students" / f"{student}.xlsx").read_bytes()
             for out in ("a", "b")]
    assert files[0] != files[1]                     # two secrets: two different tasks
    again = run_cli("assign", "--roster", roster, "--seed", seeds[0], "--lang", "en", "-o",
                    tmp_path / "c")
    assert again.returncode == 0 and "warning" not in again.stderr
    assert (tmp_path / "c" / "students" / f"{student}.xlsx").read_bytes() == files[0]
    small = run_cli("assign", "--roster", roster, "--seed", "2026", "--lang", "en", "-o",
                    tmp_path / "d")
    assert small.returncode == 0 and "seed 2026 can be guessed" in small.stderr


@pytest.mark.parametrize("encoding,headers", [
    ("utf-8-sig", ("student_id", "name", "group")),
    ("utf-16", ("学号", "姓名", "班级")),
    ("gb18030", ("ID", "Name", "班")),
])
def test_rosters_as_excel_saves_them(tmp_path, encoding, headers):
    roster = tmp_path / "r.csv"
    write_roster(roster, ["a1", "张三-2"], encoding=encoding, headers=headers)
    if encoding == "utf-16":
        roster.write_text(roster.read_text(encoding="utf-16").replace(",", "\t"),
                          encoding="utf-16")
    done = run_cli("assign", "--roster", roster, "-o", tmp_path / "out")
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "out" / "students" / "张三-2.xlsx").is_file()


def test_an_xlsx_roster(tmp_path):
    book = openpyxl.Workbook()
    book.active.append(["学号", "姓名"])
    book.active.append([20240101, "李四"])
    book.save(tmp_path / "r.xlsx")
    done = run_cli("assign", "--roster", tmp_path / "r.xlsx", "-o", tmp_path / "out")
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "out" / "students" / "20240101.xlsx").is_file()


@pytest.mark.parametrize("roster,expected", [
    ("student_id,name\na1,A\na1,B\n", "row 3: student id 'a1' is also in row 2"),
    ("student_id,name\n,A\n", "row 2: student id '' is empty"),
    ("code,name\na1,A\n", "needs a student_id/学号 column"),
    ("student_id,name\na1,A,extra\n", "row 2: 3 cells but the header has 2 columns"),
    ("student_id,name\n../x,A\n", "starts with '.'"),
    ("student_id,name\na/b,A\n", "holds '/'"),
    ("student_id,name\n-rf,A\n", "starts with '-'"),
    ("student_id,name\n=cmd,A\n", "starts with '='"),
    ("student_id,name\na\x01b,A\n", "holds '\\x01'"),
])
def test_bad_rosters_are_refused(tmp_path, roster, expected):
    path = tmp_path / "r.csv"
    path.write_text(roster)
    done = run_cli("assign", "--roster", path, "-o", tmp_path / "out")
    assert done.returncode == 2 and expected in done.stderr, done.stderr
    assert len(done.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "out").exists()
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]


def test_unknown_preset_and_foreign_directory_are_refused(tmp_path):
    path = tmp_path / "r.csv"
    write_roster(path, ["a1"])
    done = run_cli("assign", "--preset", "nosuch", "--roster", path, "-o", tmp_path / "out")
    assert done.returncode == 2 and "unknown preset" in done.stderr
    (tmp_path / "empty").mkdir()
    done = run_cli("grade", tmp_path / "empty", tmp_path, "-o", tmp_path / "res")
    assert done.returncode == 2 and "not a directory written by 'crankbook assign'" in done.stderr
    assert not (tmp_path / "res").exists()


def test_second_assignment_on_the_engine_workbook(tmp_path):
    roster = tmp_path / "roster.csv"
    write_roster(roster, ["e1", "e2"], encoding="utf-8", headers=("id", "name", "g"))
    assert run_cli("assign", "--preset", "thesis", "--roster", roster, "--lang", "en", "-o",
                   tmp_path / "eng").returncode == 0
    names = named(tmp_path / "eng" / "keys" / "e1.xlsx")
    angles = [30.0, 60.0, 90.0, 135.0, 180.0, 390.0, 450.0]
    grid = names["q_crank_angle"]
    answers = {key: [names[f"q_{key}"][grid.index(a)] for a in angles]
               for key in ("piston_displacement", "piston_velocity", "piston_acceleration",
                           "rod_angle", "inertia_force")}
    fill(tmp_path / "eng" / "students" / "e1.xlsx", tmp_path / "subs" / "e1.xlsx", answers)
    done = run_cli("grade", tmp_path / "eng", tmp_path / "subs", "-o", tmp_path / "res")
    assert done.returncode == 0, done.stderr
    rows, _ = read_gradebook(tmp_path / "res")
    assert float(rows["e1"]["score"]) == 100.0 and rows["e2"]["status"] == "missing"
    feedback = (tmp_path / "res" / "feedback" / "e1.md").read_text(encoding="utf-8")
    assert "Score: **100 / 100**" in feedback


def _rezip(source, target, change):
    with zipfile.ZipFile(source) as archive:
        items = {n: archive.read(n) for n in archive.namelist()}
    change(items)
    with zipfile.ZipFile(target, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, data in items.items():
            archive.writestr(name, data)


def test_hostile_files_are_unreadable_and_the_batch_goes_on(pack, tmp_path):
    student = pack / "students"
    subs = tmp_path / "subs"
    subs.mkdir()
    (subs / "s01.xlsx").write_bytes(b"\xd0\xcf\x11\xe0\xa1\xb1\x1a\xe1" + b"\0" * 4096)
    shutil.copy(student / "s02.xlsx", subs / "s02.xlsm")
    _rezip(student / "s03.xlsx", subs / "s03.xlsx",
           lambda items: items.update({"xl/media/huge.bin": b"\0" * (20 * 2**20)}))
    bomb = ('<?xml version="1.0"?><!DOCTYPE lolz [<!ENTITY lol "lol">'
            '<!ENTITY lol2 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">]>'
            '<lolz>&lol2;</lolz>')
    _rezip(student / "s04.xlsx", subs / "s04.xlsx",
           lambda items: items.update({"docProps/custom.xml": bomb.encode("utf-16")}))
    _rezip(student / "s06.xlsx", subs / "s06.xlsx",
           lambda items: items.update({"xl/macros/code.bin": b"\xd0\xcf\x11\xe0" + b"\0" * 64}))
    fill(student / "s05.xlsx", subs / "s05.xlsx", key_answers(pack, "s05"), formulas=True)
    saved = recalc.convert([subs / "s05.xlsx"], tmp_path / "lo")[0]   # saved through LibreOffice
    shutil.move(saved, subs / "s05.xlsx")
    done = run_cli("grade", pack, subs, "-o", tmp_path / "res")
    assert done.returncode == 0, done.stderr
    rows, _ = read_gradebook(tmp_path / "res")
    # reasons in the class's language (a Chinese class)
    assert rows["s01"]["status"] == "unreadable" and "设了密码" in rows["s01"]["notes"]
    assert rows["s02"]["status"] == "unreadable" and "含宏" in rows["s02"]["notes"]
    assert rows["s03"]["status"] == "unreadable" and "解压后异常巨大" in rows["s03"]["notes"]
    assert rows["s04"]["status"] == "unreadable" and "XML 实体" in rows["s04"]["notes"]
    assert rows["s06"]["status"] == "unreadable" and "含宏" in rows["s06"]["notes"]
    assert rows["s05"]["status"] == "graded" and float(rows["s05"]["score"]) == 100.0


# ---------------------------------------------------------------- defensible grading (issue 22)
def _grade_one(pack, tmp_path, sid, answers, change=None, name="sub"):
    """Grade one student's file (answers typed, then ``change`` applied to the saved
    workbook as a person would edit it); returns (gradebook row, feedback text)."""
    subs = tmp_path / name
    fill(pack / "students" / f"{sid}.xlsx", subs / f"{sid}.xlsx", answers)
    if change:
        change(subs / f"{sid}.xlsx")
    done = run_cli("grade", pack, subs, "-o", tmp_path / f"{name}-results")
    assert done.returncode == 0, done.stderr
    rows, _ = read_gradebook(tmp_path / f"{name}-results")
    feedback = (tmp_path / f"{name}-results" / "feedback" / f"{sid}.md").read_text(encoding="utf-8")
    return rows[sid], feedback


def _item(row, key):
    return float(next(v for c, v in row.items() if c.endswith(f"(a_{key})")))


def test_consequential_credit_follows_the_students_whole_mechanism(pack, tmp_path):
    """A wrong K carried through correctly: θ, r (inside the tolerance) and l (far off)
    are the student's own, and so are the positions A12–A14; every downstream item
    earns at least 90 % of the consequential credit the rubric allows."""
    from crankbook.spec import params
    from crankbook.assignment.grade import manifest_values
    from crankbook.assignment.key import expected, key_results
    spec, _, preset = params.load_preset("course-design")
    with open(pack / "manifest.csv", newline="", encoding="utf-8-sig") as handle:
        row = next(r for r in csv.DictReader(handle) if r["student_id"] == "s03")
    values = manifest_values(spec, row)
    key = key_results(ASSIGNMENT, spec, preset, values)
    H, e, K = values["stroke"] / 1000, values["offset"] / 1000, values["time_ratio"]
    for wrong_k in np.arange(K + 0.005, K + 0.2, 0.005):
        r = mechanism.crank_radius_from_design(H, e, wrong_k) * 1000
        l_ = mechanism.rod_length_from_design(H, e, wrong_k) * 1000
        if abs(r / key.results["crank_radius"] - 1) < 0.009 < abs(l_ / key.results["rod_length"] - 1):
            break
    own = expected(ASSIGNMENT, spec, key, overrides={"crank_radius": r, "rod_length": l_})
    answers = {k: (v["value"].tolist() if k in POSITION_ITEMS else float(v["value"][0]))
               for k, v in own.items()}
    answers["extreme_angle"] = 180 * (wrong_k - 1) / (wrong_k + 1)
    answers.update({k: key_answers(pack, "s03")[k] for k in CAM_ITEMS})
    graded_row, feedback = _grade_one(pack, tmp_path, "s03", answers)
    assert "不是任何位置" not in feedback
    fraction = ASSIGNMENT.rubric["consequential"]["fraction"]
    for item in ASSIGNMENT.items:
        if item.consequential:
            assert _item(graded_row, item.key) >= 0.9 * fraction * item.points - 1e-9, item.key


def test_an_inserted_note_row_and_a_second_revolution_typed_from_zero(pack, tmp_path):
    answers = key_answers(pack, "s01")
    angles = list(answers["pos_crank_angle"])
    answers["pos_crank_angle"] = angles[:15] + [a - 360 for a in angles[15:]]   # A0′… as 0–330

    def insert_note_row(path):
        book = openpyxl.load_workbook(path)
        sheet, ref = next(iter(book.defined_names["a_pos_slider_velocity"].destinations))
        ws = book[sheet]
        ws.insert_rows(12)                                 # inside the table, as Excel does
        ws.cell(row=12, column=1, value="备注：下面是我算的")
        for name in list(book.defined_names):
            found = book.defined_names[name]
            where, block = next(iter(found.destinations))
            if where == sheet and ":" in block:
                top, bottom = block.replace("$", "").split(":")
                found.attr_text = f"'{sheet}'!${top[0]}${top[1:]}:${bottom[0]}${int(bottom[1:]) + 1}"
        book.save(path)
    row, feedback = _grade_one(pack, tmp_path, "s01", answers, insert_note_row)
    assert float(row["score"]) == 100.0, row["notes"]
    assert "rows-edited" in row["flags"] and "positions" in row["flags"]
    assert "第二转" in feedback and "插入或删除了" in feedback


def test_a_column_of_zeros_gets_one_note_per_slip_and_a_readable_lms_text(pack, tmp_path):
    """Zeros typed everywhere: one note for A0 given fifteen times (not fourteen), one
    for the missing positions; the LMS text stays within its limit, cut between
    sentences; a small typed number is shown as typed, not rounded to 0."""
    answers = {k: [0.0] * len(v) if isinstance(v, list) else 0.0
               for k, v in key_answers(pack, "s06").items()}
    answers["pos_balancing_torque"] = [v / 1000 for v in key_answers(pack, "s06")
                                       ["pos_balancing_torque"]]           # in kN·m
    row, feedback = _grade_one(pack, tmp_path, "s06", answers)
    assert feedback.count("填了 15 次") == 2 and "填了两次" not in feedback   # A0 and A0′
    assert feedback.count("缺少位置") == 1
    torque = ASSIGNMENT.item["pos_balancing_torque"]
    small = next(v for v in answers["pos_balancing_torque"]
                 if 0 < abs(v) < 10 ** -(math.ceil(-math.log10(torque.abs_floor)) + 1))
    assert f"{small:.4g}" in feedback
    done = run_cli("grade", pack, tmp_path / "sub", "--lms", "xuexitong", "-o", tmp_path / "x")
    assert done.returncode == 0, done.stderr
    sheet = openpyxl.load_workbook(tmp_path / "x" / "xuexitong-import.xlsx").active
    text = next(r[3] for r in sheet.iter_rows(values_only=True) if r[0] == "s06")
    assert len(text) <= 2000 and text.endswith(" （其余从略）")       # 学习通's limit
    assert text[:-len(" （其余从略）")].endswith(("……", "）"))           # between sentences


def test_a_resubmission_round_loses_nothing(graded, pack, tmp_path):
    second = tmp_path / "round2"
    fill(pack / "students" / "s04.xlsx", second / "s04.xlsx", graded["perfect"]["s04"])
    shutil.copy(pack / "students" / "s05.xlsx", second / "s05.xlsx")     # blank this time
    done = run_cli("grade", pack, second, "-o", tmp_path / "r2", "--previous",
                   graded["results"], "--keep", "best")
    assert done.returncode == 0, done.stderr
    rows, _ = read_gradebook(tmp_path / "r2")
    first = graded["by_id"]
    for sid in ("s01", "s06", "s07", "s13"):          # did not resubmit: the whole row kept
        assert rows[sid]["score"] == first[sid]["score"]
        for column, value in first[sid].items():
            if column.endswith(")") and "(a_" in column:
                assert rows[sid][column] == value, (sid, column)
        assert set(first[sid]["flags"].split(";")) <= set(rows[sid]["flags"].split(";"))
    assert float(rows["s04"]["score"]) == 100.0
    # keep best: s05's better first round whole — its items and its feedback
    assert rows["s05"]["score"] == first["s05"]["score"]
    text = (tmp_path / "r2" / "feedback" / "s05.md").read_text(encoding="utf-8")
    assert "符号相反" in text
    report = openpyxl.load_workbook(tmp_path / "r2" / "class-report.xlsx")
    assert "11/13" in report["各题"]["A1"].value
    # s07 kept round 1's copy flag, and the integrity report still gives its evidence
    integrity = openpyxl.load_workbook(tmp_path / "r2" / "integrity.xlsx").active
    pairs = [[c.value for c in row] for row in integrity.iter_rows(min_row=5)]
    assert any(str(r[0]).startswith("s07") and str(r[1]).startswith("s08") and r[3]
               for r in pairs)


def test_a_gradebook_as_teachers_open_it(tmp_path):
    roster = tmp_path / "roster.csv"
    roster.write_text("学号,姓名,班级\n012301011012,王五,机械2班\n", encoding="gbk")
    done = run_cli("assign", "--roster", roster, "--seed", "3", "-o", tmp_path / "class")
    assert done.returncode == 0, done.stderr
    assert "已写入" in done.stdout                      # the class's language
    subs = tmp_path / "subs"
    fill(tmp_path / "class" / "students" / "012301011012.xlsx", subs / "012301011012.xlsx",
         key_answers(tmp_path / "class", "012301011012"))
    done = run_cli("grade", tmp_path / "class", subs, "-o", tmp_path / "res")
    assert done.returncode == 0 and "已评分 1/1" in done.stdout, done.stdout + done.stderr
    book = openpyxl.load_workbook(tmp_path / "res" / "gradebook.xlsx")
    ws = book.active
    header = [c.value for c in ws[1]]
    row = {h: c.value for h, c in zip(header, ws[2])}
    # the class's words over the columns (issue 40.11); the CSV keeps the fixed names
    assert row["学号"] == "012301011012" and row["班级"] == "机械2班"
    assert row["状态代码"] == "graded" and row["状态"] == "已评分"
    assert row["得分"] == 100 and "student_id" not in header
    raw = (tmp_path / "res" / "gradebook.csv").read_bytes()
    assert raw.startswith(b"\xef\xbb\xbf") and b'\n="012301011012",' in raw
    assert (tmp_path / "res" / "lms-import.csv").read_bytes().startswith(b"\xef\xbb\xbf")
    feedback = (tmp_path / "res" / "feedback" / "012301011012.md").read_text(encoding="utf-8")
    assert "e-1" not in feedback and "| -0 |" not in feedback


def test_every_drawn_variant_passes_every_check():
    """500 students: each key's checks pass (no cam below its own smallest base radius,
    no undercut, no pointed tooth) — what assign writes into the keys."""
    from crankbook.spec import params
    from crankbook.spec.evaluate import evaluate
    from crankbook.assignment.key import given_trace
    from crankbook.assignment.variants import draw_class
    spec, base, preset = params.load_preset("course-design")
    drawn = draw_class(ASSIGNMENT, spec, base, [f"x{i:03d}" for i in range(500)], 2026)
    checks = ASSIGNMENT.constraints["checks"]
    for sid, values in drawn.items():
        values = params.validate(spec, dict(values))
        angle, pressure = given_trace(ASSIGNMENT, spec, values)
        # the key's own quantities (and what they need), as key_results computes them
        key = evaluate(spec, dict(values, pressure_source=1.0),
                       {"trace_crank_angle": angle, "trace_pressure": pressure},
                       keys=[*checks, "min_transmission_angle"])
        for check in checks:
            assert np.all(np.asarray(key[check]) == 1), (sid, check)
        assert key["min_transmission_angle"] >= 45.0
    # the whole valve train varies: gears, laws, angles and timing (issue 27)
    for name in ("gear_teeth", "intake_rise_law", "exhaust_return_law", "intake_rise_angle",
                 "intake_opens", "exhaust_closes"):
        assert len({repr(v[name]) for v in drawn.values()}) > 2, name
    teeth = {tuple(v["gear_teeth"]) for v in drawn.values()}
    assert all(t[-1] == 2 * t[0] for t in teeth)          # the cam turns at half speed


def test_no_cam_row_pays_for_typing_zero():
    """Issue 40.6: the cam was asked at 0, 30, …, 330° — two thirds of the rows in a
    dwell, where 0 was the answer.  For 200 drawn students, a 0 typed in any cam row
    scores nothing (graded by the grader's own score_cell against each key)."""
    from crankbook.assignment.key import expected, key_results
    from crankbook.assignment.variants import draw_class
    from crankbook.spec import params
    spec, base, meta = params.load_preset("course-design")
    drawn = draw_class(ASSIGNMENT, spec, base, [f"z{i:03d}" for i in range(200)], 40)
    angles = ASSIGNMENT.row_angles["cam_angle"]
    rises = set()
    for sid, values in list(drawn.items())[:200]:
        values = params.validate(spec, dict(values))
        rises.add((values["intake_rise_angle"], values["intake_far_dwell"],
                   values["intake_return_angle"]))
        want = expected(ASSIGNMENT, spec, key_results(ASSIGNMENT, spec, meta, values))
        for key in CAM_ITEMS:
            item = ASSIGNMENT.item[key]
            for angle, value in zip(angles, want[key]["value"]):
                result = score_cell("", 0.0, float(value), item, ASSIGNMENT.rubric)
                assert result.fraction == 0.0, (sid, key, angle, float(value))
    assert len(rises) > 10                      # across the drawn rises, dwells and returns


def test_the_student_workbook_gives_the_gear_data(pack):
    book = openpyxl.load_workbook(pack / "students" / "s01.xlsx")
    assert {"p_gear_teeth", "p_gear_shift", "p_gear_module", "p_gear_pressure_angle"} <= \
        set(book.defined_names)
    sheet, ref = next(iter(book.defined_names["a_mesh_contact_ratio"].destinations))
    labels = [book[sheet].cell(row=r, column=1).value for r in range(6, 8)]
    assert labels == ["啮合 1（齿轮 1–2）", "啮合 2（齿轮 2–3）"]
    assert "R07" not in ASSIGNMENT.statement_zh and "R07" not in ASSIGNMENT.statement_en
    assert "|α| ≤ [α]" in ASSIGNMENT.statement_zh


def test_a_near_copy_is_found_and_the_source_is_not_flagged(pack, tmp_path):
    """s02 hands in s01's answers with a few cells changed: they fit s01's parameters,
    not s02's own; s01 did their own work and is not flagged."""
    subs = tmp_path / "subs"
    source = key_answers(pack, "s01")
    copied = {k: (list(v) if isinstance(v, list) else v) for k, v in source.items()}
    for key in ("pos_slider_velocity", "pos_balancing_torque"):
        copied[key][3] = copied[key][3] * 1.3 + 1
    copied["crank_radius"] = source["crank_radius"] * 1.2
    fill(pack / "students" / "s01.xlsx", subs / "s01.xlsx", source)
    fill(pack / "students" / "s02.xlsx", subs / "s02.xlsx", copied)
    done = run_cli("grade", pack, subs, "-o", tmp_path / "res")
    assert done.returncode == 0, done.stderr
    rows, _ = read_gradebook(tmp_path / "res")
    assert "copy-suspect" in rows["s02"]["flags"] and "s01" in rows["s02"]["notes"]
    assert "copy-suspect" not in rows["s01"]["flags"]
    assert "s01" not in (tmp_path / "res" / "feedback" / "s02.md").read_text(encoding="utf-8")
    report = openpyxl.load_workbook(tmp_path / "res" / "integrity.xlsx").active
    rows = [[c.value for c in row] for row in report.iter_rows(min_row=5)]
    assert rows[0][0].startswith("s02") and rows[0][1].startswith("s01")
    assert "%" in rows[0][3]                        # the evidence: how well they fit


# ---------------------------------------------------------------- the teacher's workflow (issue 27)
def test_check_passes_a_complete_file_and_never_tells_a_value(pack, tmp_path):
    answers = key_answers(pack, "s03")
    fill(pack / "students" / "s03.xlsx", tmp_path / "s03.xlsx", answers)
    done = run_cli("check", tmp_path / "s03.xlsx")
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.strip().splitlines()[-1].startswith("可以提交")
    # a slightly wrong answer is not the checker's business: it reads, it does not grade
    wrong = scaled(answers, "rod_length", 1.07)
    fill(pack / "students" / "s03.xlsx", tmp_path / "wrong.xlsx", wrong)
    done = run_cli("check", tmp_path / "wrong.xlsx")
    assert done.returncode == 0 and "连杆长度" not in done.stdout, done.stdout
    for value in (answers["rod_length"], answers["crank_radius"]):
        assert f"{value:.4g}" not in done.stdout


def test_check_lists_what_grading_would_lose(pack, tmp_path):
    answers = key_answers(pack, "s04")
    answers["crank_radius"] = "about sixty"             # text in a number cell
    answers["pos_slider_velocity"] = [None, *answers["pos_slider_velocity"][1:]]
    answers["flywheel_inertia"] = None
    angles = list(answers["pos_crank_angle"])
    angles[5] = 3.5                                       # names no position
    answers["pos_crank_angle"] = angles
    fill(pack / "students" / "s04.xlsx", tmp_path / "s04.xlsx", answers)
    done = run_cli("check", tmp_path / "s04.xlsx")
    assert done.returncode == 1, done.stdout + done.stderr
    out = done.stdout
    assert "曲柄半径 r" in out and "about sixty" in out and "不是数值" in out
    assert "飞轮转动惯量 J_F：未作答" in out
    assert "滑块速度 v_B：1 格未填（A0）" in out
    assert not re.search(r"\d\s*分|/\s*100|得分", out)          # no points, no score
    assert out.strip().splitlines()[-1].startswith("提交前请修改")


def test_check_refuses_hostile_files_in_one_line(pack, tmp_path):
    student = pack / "students"
    (tmp_path / "ole.xlsx").write_bytes(b"\xd0\xcf\x11\xe0\xa1\xb1\x1a\xe1" + b"\0" * 4096)
    _rezip(student / "s06.xlsx", tmp_path / "macro.xlsx",
           lambda items: items.update({"xl/macros/code.bin": b"\xd0\xcf\x11\xe0" + b"\0" * 64}))
    bomb = ('<?xml version="1.0"?><!DOCTYPE lolz [<!ENTITY lol "lol">]><lolz>&lol;</lolz>')
    _rezip(student / "s04.xlsx", tmp_path / "bomb.xlsx",
           lambda items: items.update({"docProps/custom.xml": bomb.encode()}))
    for name, file in (("ole", tmp_path / "ole.xlsx"), ("macro", tmp_path / "macro.xlsx"),
                       ("bomb", tmp_path / "bomb.xlsx"), ("key", pack / "keys" / "s01.xlsx")):
        done = run_cli("check", file)
        assert done.returncode == 1 and "Traceback" not in done.stderr, (name, done.stderr)
        assert len(done.stdout.strip().splitlines()) == 1, (name, done.stdout)
    done = run_cli("check", tmp_path / "nothing.xlsx")
    assert done.returncode == 2 and done.stderr.count("\n") == 1


def test_annotated_returns_colour_the_students_own_cells(pack, tmp_path, soffice):
    subs = tmp_path / "subs"
    answers = key_answers(pack, "s05")
    wrong = scaled(answers, "crank_radius", 1.3)
    wrong["flywheel_inertia"] = "see sheet 3"
    fill(pack / "students" / "s05.xlsx", subs / "s05.xlsx", wrong)
    fill(pack / "students" / "s05.xlsx", subs / "s06.xlsx", answers)     # s06 hands in s05's
    fill(pack / "students" / "s07.xlsx", subs / "s07.xlsx", key_answers(pack, "s07"))
    done = run_cli("grade", pack, subs, "-o", tmp_path / "res", "--return", tmp_path / "back",
                   "--feedback", "hints")
    assert done.returncode == 0, done.stderr
    back = tmp_path / "back"
    book = openpyxl.load_workbook(back / "s05.xlsx")

    def cell(name, index=0):
        sheet, ref = next(iter(book.defined_names[name].destinations))
        block = book[sheet][ref.replace("$", "")]
        cells = [c for row in block for c in row] if isinstance(block, tuple) else [block]
        return cells[index]
    assert cell("a_crank_radius").fill.fgColor.rgb.endswith("FFC7CE")       # wrong: red
    assert cell("a_rod_length").fill.fgColor.rgb.endswith("C6EFCE")         # right: green
    assert cell("a_flywheel_inertia").fill.fgColor.rgb.endswith("D9D2E9")   # unreadable
    assert "不是数值" in cell("a_flywheel_inertia").comment.text
    comment = cell("a_crank_radius").comment.text
    assert "错误" in comment or "0 /" in comment
    expected = key_answers(pack, "s05")["crank_radius"]
    assert f"{expected:.4g}" not in comment                 # hints: no expected value
    first = book.worksheets[0]
    texts = [str(c.value) for row in first.iter_rows() for c in row if c.value is not None]
    assert any(t.startswith("得分") and "/ 100" in t for t in texts)
    # nothing about another student: not s06 (who copied), not in any returned file
    for path in back.iterdir():
        with open(path, "rb") as handle:
            data = handle.read()
        if path.suffix == ".xlsx":
            with zipfile.ZipFile(path) as archive:
                data = b"".join(archive.read(n) for n in archive.namelist())
        own = path.stem
        text = data.decode("utf-8", errors="replace")
        for other in ROSTER:
            if other != own:
                assert not re.search(rf"(?<![A-Za-z0-9]){other}(?![A-Za-z0-9])", text), \
                    (path.name, other)
                assert NAMES[other] not in text, (path.name, other)
    assert (back / "s01.html").is_file() and "未" in (back / "s01.html").read_text("utf-8")
    # same submissions, same bytes: no clock in the returned files
    again = run_cli("grade", pack, subs, "-o", tmp_path / "res2", "--return", tmp_path / "back2",
                    "--feedback", "hints")
    assert again.returncode == 0, again.stderr
    assert {p.name: p.read_bytes() for p in back.iterdir()} == \
        {p.name: p.read_bytes() for p in (tmp_path / "back2").iterdir()}
    # LibreOffice opens the returned workbook and keeps the colours and comments
    saved = recalc.convert([back / "s05.xlsx"], tmp_path / "lo")[0]
    again = openpyxl.load_workbook(saved)
    sheet, ref = next(iter(again.defined_names["a_crank_radius"].destinations))
    assert again[sheet][ref.replace("$", "")].comment is not None


def test_a_returned_copy_keeps_no_trace_of_whom_it_was_copied_from(pack, tmp_path):
    """A copy carries its first owner in the document properties Excel shows under
    File > Info (title, subject, keywords, a custom "owner"); the copier's returned
    file names the copier alone, and is still a crankbook student workbook."""
    from openpyxl.packaging.custom import StringProperty
    subs = tmp_path / "subs"
    fill(pack / "students" / "s05.xlsx", subs / "s06.xlsx", key_answers(pack, "s05"))
    book = openpyxl.load_workbook(subs / "s06.xlsx")
    for field in ("title", "subject", "description", "keywords", "category", "creator"):
        setattr(book.properties, field, f"{NAMES['s05']} s05")
    book.custom_doc_props.append(StringProperty(name="owner", value=f"{NAMES['s05']} s05"))
    book.save(subs / "s06.xlsx")
    done = run_cli("grade", pack, subs, "-o", tmp_path / "res", "--return", tmp_path / "back")
    assert done.returncode == 0, done.stderr
    with zipfile.ZipFile(tmp_path / "back" / "s06.xlsx") as archive:
        text = b"".join(archive.read(n) for n in archive.namelist()).decode("utf-8", "replace")
    assert NAMES["s05"] not in text and not re.search(r"(?<![A-Za-z0-9])s05(?![A-Za-z0-9])", text)
    assert run_cli("check", tmp_path / "back" / "s06.xlsx").returncode == 0


def _round_for_exports(pack, tmp_path):
    subs = tmp_path / "subs"
    for sid in ("s01", "s04"):
        fill(pack / "students" / f"{sid}.xlsx", subs / f"{sid}.xlsx", key_answers(pack, sid))
    fill(pack / "students" / "s02.xlsx", subs / "s02.xlsx",
         scaled(key_answers(pack, "s02"), "flywheel_inertia", 1.5))
    return subs


def test_overrides_leave_a_record_and_apply_the_same_twice(pack, tmp_path):
    subs = _round_for_exports(pack, tmp_path)
    overrides = tmp_path / "overrides.csv"
    overrides.write_text(
        "student,item,action,points,reason,who\n"
        "s02,a_flywheel_inertia,accept,,used the guide's own J_F formula,王老师\n"
        "s04,a_crank_radius,points,2,radius read off the drawing,王老师\n"
        "s01,a_pos_slider_velocity!A3,accept,,,王老师\n", encoding="utf-8")
    done = run_cli("grade", pack, subs, "-o", tmp_path / "r0", "--overrides", overrides)
    assert done.returncode == 2 and "row 4" in done.stderr and "reason" in done.stderr
    overrides.write_text(overrides.read_text("utf-8").replace(",,,王老师", ",,typo in A3,王老师"),
                         encoding="utf-8")
    books = []
    for run in ("r1", "r2"):
        done = run_cli("grade", pack, subs, "-o", tmp_path / run, "--overrides", overrides)
        assert done.returncode == 0, done.stderr
        books.append((tmp_path / run / "gradebook.csv").read_bytes())
    assert books[0] == books[1]
    rows, _ = read_gradebook(tmp_path / "r1")
    assert float(rows["s02"]["score"]) == 100.0 and "王老师" in rows["s02"]["overrides"]
    assert float(rows["s04"]["score"]) == pytest.approx(
        100.0 - ASSIGNMENT.item["crank_radius"].points + 2)
    for sid, row in rows.items():                          # students never see it
        lms = (tmp_path / "r1" / "lms-import.csv").read_text("utf-8-sig")
        assert "王老师" not in lms
    bad = tmp_path / "bad.csv"
    bad.write_text("student,item,action,points,reason,who\ns99,a_crank_radius,accept,,x,y\n",
                   encoding="utf-8")
    done = run_cli("grade", pack, subs, "-o", tmp_path / "r3", "--overrides", bad)
    assert done.returncode == 2 and "s99" in done.stderr and done.stderr.count("\n") == 1


def test_lms_exports_have_the_columns_their_importers_read(pack, tmp_path):
    subs = _round_for_exports(pack, tmp_path)
    done = run_cli("grade", pack, subs, "-o", tmp_path / "canvas", "--lms", "canvas",
                   "--out-of", "20")
    assert done.returncode == 0, done.stderr
    with open(tmp_path / "canvas" / "canvas-gradebook.csv", newline="", encoding="utf-8") as f:
        table = list(csv.reader(f))
    assert table[0][:5] == ["Student", "ID", "SIS User ID", "SIS Login ID", "Section"]
    assert table[1][0] == "Points Possible" and float(table[1][5]) == 20.0
    scores = {r[2]: r[5] for r in table[2:]}
    assert float(scores["s01"]) == 20.0 and scores["s03"] == ""      # missing: no zero
    assert {r[4] for r in table[2:]} == {"机械1班"}
    rows, _ = read_gradebook(tmp_path / "canvas")      # the weight as typed, no float noise
    assert rows["s01"]["max_score"] in ("20", "20.0"), rows["s01"]["max_score"]
    # 学习通: 学号 as text
    done = run_cli("grade", pack, subs, "-o", tmp_path / "xxt", "--lms", "xuexitong")
    assert done.returncode == 0, done.stderr
    sheet = openpyxl.load_workbook(tmp_path / "xxt" / "xuexitong-import.xlsx").active
    assert [c.value for c in sheet[1]] == ["学号", "姓名", "成绩", "评语"]
    assert sheet["A2"].data_type == "s" and sheet["A2"].value == "s01"
    assert sheet["C2"].value == 100
    # Moodle: its own worksheet, filled and kept whole
    worksheet = tmp_path / "moodle.csv"
    worksheet.write_text(
        '"Identifier","Full name","Email address","Status","Grade","Maximum Grade",'
        '"Grade can be changed","Last modified (submission)","Last modified (grade)",'
        '"Feedback comments"\n'
        f'"Participant 8812","{NAMES["s01"]}","","Submitted for grading","","100.00","Yes",'
        '"","",""\n'
        '"Participant 9999","Not In Class","","No submission","","100.00","Yes","","",""\n',
        encoding="utf-8")
    done = run_cli("grade", pack, subs, "-o", tmp_path / "moodle", "--lms", "moodle",
                   "--lms-template", worksheet)
    assert done.returncode == 0, done.stderr
    with open(tmp_path / "moodle" / "moodle-grading-worksheet.csv", newline="",
              encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    assert rows[0]["Identifier"] == "Participant 8812" and float(rows[0]["Grade"]) == 100
    assert rows[0]["Feedback comments"] and rows[1]["Grade"] == ""
    done = run_cli("grade", pack, subs, "-o", tmp_path / "m2", "--lms", "moodle")
    assert done.returncode == 2 and "--lms-template" in done.stderr


def test_part_of_the_pack_and_item_statistics(pack, tmp_path):
    subs = _round_for_exports(pack, tmp_path)
    done = run_cli("grade", pack, subs, "-o", tmp_path / "week1", "--items",
                   "a_crank_radius,a_rod_length,a_flywheel_inertia", "--out-of", "10")
    assert done.returncode == 0, done.stderr
    rows, _ = read_gradebook(tmp_path / "week1")
    assert float(rows["s01"]["max_score"]) == 10.0 and float(rows["s01"]["score"]) == 10.0
    share = ASSIGNMENT.item["flywheel_inertia"].points / sum(
        ASSIGNMENT.item[k].points for k in ("crank_radius", "rod_length", "flywheel_inertia"))
    assert float(rows["s02"]["score"]) == pytest.approx(10.0 * (1 - share), abs=0.01)
    done = run_cli("grade", pack, subs, "-o", tmp_path / "bad", "--items", "a_nothing")
    assert done.returncode == 2 and "nothing is not an item" in done.stderr
    # statistics: the planted hard item (s02's J_F) is the hardest, no slips invented
    from crankbook.assignment.results import item_statistics
    from crankbook.assignment.grade import Grade
    from crankbook.assignment.scoring import CellResult

    def grade_of(sid, fraction):
        g = Grade(student_id=sid, name=sid, status="graded")
        for item in ASSIGNMENT.items:
            f = fraction if item.key == "flywheel_inertia" else 1.0
            g.items[item.key] = (item.points * f, [CellResult("", 1, 1, f, "correct"
                                                              if f == 1 else "wrong", {})])
        return g
    graded = [grade_of(f"x{i}", 1.0 if i % 3 == 0 else 0.0) for i in range(30)]
    stats = {e["item"].key: e for e in item_statistics(ASSIGNMENT, graded)}
    assert min(stats, key=lambda k: stats[k]["difficulty"]) == "flywheel_inertia"
    assert stats["flywheel_inertia"]["difficulty"] == pytest.approx(10 / 30)
    assert stats["flywheel_inertia"]["discrimination"] == pytest.approx(1.0)
    assert stats["crank_radius"]["discrimination"] == 0.0
    report = openpyxl.load_workbook(tmp_path / "week1" / "class-report.xlsx")
    assert "题目分析" in report.sheetnames
    # the chart beside the table stacks the table's slips by kind, one bar an item
    import zipfile
    with zipfile.ZipFile(tmp_path / "week1" / "class-report.xlsx") as z:
        charts = [z.read(n).decode() for n in z.namelist() if n.startswith("xl/charts/chart")]
    slips = [c for c in charts if "各题的失误类型" in c]
    assert len(slips) == 1 and slips[0].count("<c:ser>") == 5          # one series a kind
    for column in "DEFGH":                                 # the three items of --items
        assert f"题目分析!${column}$4:${column}$6<" in slips[0], column


def test_no_chart_of_the_reports_hides_a_cell(pack, tmp_path):
    """The slips chart beside the item table once reached down over the heat map of
    positions × quantities and hid its last column."""
    subs = _round_for_exports(pack, tmp_path)
    assert run_cli("grade", pack, subs, "-o", tmp_path / "r").returncode == 0
    for name in ("class-report", "gradebook", "integrity"):
        assert not cells_under_charts(tmp_path / "r" / f"{name}.xlsx"), name
        assert not texts_cut_by_a_neighbour(tmp_path / "r" / f"{name}.xlsx"), name


def test_groups_share_the_guides_table_and_keep_their_own_valve_trains(tmp_path):
    roster = tmp_path / "roster.csv"
    roster.write_text("学号,姓名,组号\ng01,甲,10\ng02,乙,10\ng03,丙,11\n", encoding="gbk")
    done = run_cli("assign", "--preset", "course-design", "--roster", roster, "--groups",
                   "-o", tmp_path / "class")
    assert done.returncode == 0, done.stderr
    with open(tmp_path / "class" / "manifest.csv", newline="", encoding="utf-8-sig") as f:
        rows = {r["student_id"]: r for r in csv.DictReader(f)}
    # 附表1's own rows: group 10 is H = 360, D = 195, e = 60; group 11 H = 380, D = 200
    assert [float(rows[s]["p_stroke"]) for s in ("g01", "g02", "g03")] == [360, 360, 380]
    assert float(rows["g01"]["p_offset"]) == float(rows["g02"]["p_offset"]) == 60
    assert rows["g01"]["fingerprint"] != rows["g02"]["fingerprint"]      # own valve trains
    teacher = tmp_path / "groups.csv"
    teacher.write_text("组号,stroke,offset\n10,250,30\n11,260,35\n", encoding="gbk")
    done = run_cli("assign", "--preset", "course-design", "--roster", roster, "--groups",
                   teacher, "-o", tmp_path / "own")
    assert done.returncode == 0, done.stderr
    with open(tmp_path / "own" / "manifest.csv", newline="", encoding="utf-8-sig") as f:
        rows = {r["student_id"]: r for r in csv.DictReader(f)}
    assert float(rows["g03"]["p_stroke"]) == 260 and float(rows["g01"]["p_offset"]) == 30
    teacher.write_text("组号,stroke\n10,250\n", encoding="utf-8")
    done = run_cli("assign", "--preset", "course-design", "--roster", roster, "--groups",
                   teacher, "-o", tmp_path / "bad")
    assert done.returncode == 2 and "group 11" in done.stderr and done.stderr.count("\n") == 1
    plain = tmp_path / "plain.csv"
    plain.write_text("student_id,name\na1,A\n", encoding="utf-8")
    done = run_cli("assign", "--preset", "course-design", "--roster", plain, "--groups",
                   "-o", tmp_path / "none")
    assert done.returncode == 2 and "组号" in done.stderr
    assert not (tmp_path / "bad").exists() and not (tmp_path / "none").exists()


def test_every_group_of_the_presets_table_can_be_assigned(tmp_path):
    """A group shares its mechanism: a row whose mechanism breaks a rule of the class
    pack (two positions closer than min_position_separation) could never be drawn for,
    whatever the valve train.  Every row of the preset's table makes a usable one, and
    a teacher's row that does not is refused in one line that says why."""
    from crankbook.spec import params
    from crankbook.assignment.groups import group_table
    from crankbook.assignment.variants import rejection
    spec, base, meta = params.load_preset("course-design")
    assignment = templates.for_preset("course-design")
    table = group_table(spec, meta, "preset")
    assert {number: rejection(assignment, spec, {**base, **row})
            for number, row in table.items()} == {number: None for number in table}
    roster = tmp_path / "roster.csv"
    roster.write_text("学号,姓名,组号\ng01,甲,1\n", encoding="utf-8")
    teacher = tmp_path / "groups.csv"
    teacher.write_text("组号,time_ratio\n1,1.04\n", encoding="utf-8")
    done = run_cli("assign", "--roster", roster, "--groups", teacher, "-o", tmp_path / "c")
    assert done.returncode == 2 and done.stderr.count("\n") == 1, done.stderr
    assert "time_ratio = 1.04" in done.stderr and "min_position_separation" in done.stderr


def test_a_teachers_own_assignment_file(tmp_path):
    from crankbook.support import resources
    text = resources.read_text(templates.ASSIGNMENTS, "course-design.toml")
    text = text.replace("stroke = { min = 200.0, max = 400.0, step = 10.0 }",
                        "stroke = { min = 250.0, max = 250.0, step = 10.0 }")
    own = tmp_path / "my-course.toml"
    own.write_text(text, encoding="utf-8")
    roster = tmp_path / "roster.csv"
    roster.write_text("student_id,name\nt1,A\nt2,B\n", encoding="utf-8")
    done = run_cli("assign", "--roster", roster, "--assignment", own, "-o", tmp_path / "class")
    assert done.returncode == 0, done.stderr
    with open(tmp_path / "class" / "manifest.csv", newline="", encoding="utf-8-sig") as f:
        assert {float(r["p_stroke"]) for r in csv.DictReader(f)} == {250.0}
    assert (tmp_path / "class" / "assignment.toml").read_text("utf-8") == text
    fill(tmp_path / "class" / "students" / "t1.xlsx", tmp_path / "subs" / "t1.xlsx",
         key_answers(tmp_path / "class", "t1"))
    done = run_cli("grade", tmp_path / "class", tmp_path / "subs", "-o", tmp_path / "res")
    assert done.returncode == 0, done.stderr
    assert float(read_gradebook(tmp_path / "res")[0]["t1"]["score"]) == 100.0
    own.write_text("[assignment]\nkey = 'x'\n", encoding="utf-8")
    done = run_cli("assign", "--roster", roster, "--assignment", own, "-o", tmp_path / "bad")
    assert done.returncode == 2 and done.stderr.count("\n") == 1, done.stderr
