"""Class packs: a simulated class through assign and grade, with answers made from the
answer keys (read from the key files, not from the grader's recomputation), asserting
the exact scores the rubric gives; no answer leaks; bad input."""
import csv
import hashlib
import io
import shutil
import zipfile

import numpy as np
import openpyxl
import pytest

from crankbook.calc import mechanism
from tests.conftest import run_cli
from crankbook import recalc
from crankbook.assignment import template as templates
from tests.conftest import named

ROSTER = [f"s{n:02d}" for n in range(1, 13)]
ASSIGNMENT = templates.load("course-design")


def write_roster(path, ids):
    path.write_text("student_id,name,group\n" + "".join(f"{i},Student {i},G1\n" for i in ids))


@pytest.fixture(scope="module")
def pack(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("pack")
    roster = tmp / "roster.csv"
    write_roster(roster, ROSTER)
    done = run_cli("assign", "--preset", "course-design", "--roster", roster, "--seed", "7",
                   "-o", tmp / "class")
    assert done.returncode == 0, done.stderr
    return tmp / "class"


def key_values(pack, sid):
    """The answer key's values for every item, read from the key workbook's q_ names."""
    names = named(pack / "keys" / f"{sid}.xlsx")
    return {item.key: names[f"q_{item.key}"] for item in ASSIGNMENT.items}


def fill(source, target, answers, formulas=False, edit_parameters=None):
    book = openpyxl.load_workbook(source)
    for key, value in answers.items():
        sheet, ref = next(iter(book.defined_names[f"a_{key}"].destinations))
        block = book[sheet][ref.replace("$", "")]
        cells = [c for row in block for c in (row if isinstance(row, tuple) else (row,))] \
            if isinstance(block, tuple) else [block]
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


@pytest.fixture(scope="module")
def graded(pack, tmp_path_factory, soffice):
    subs = tmp_path_factory.mktemp("submissions")
    student = pack / "students"
    perfect = {sid: key_values(pack, sid) for sid in ROSTER}
    # s01 perfect; s02 blank; s03 within tolerance; s04 unit slip; s05 sign slip
    fill(student / "s01.xlsx", subs / "lms" / "s01_attempt1" / "course.xlsx", perfect["s01"])
    shutil.copy(student / "s02.xlsx", subs / "s02.xlsx")
    fill(student / "s03.xlsx", subs / "S-s03.xlsx",
         {k: ([x * 1.004 for x in v] if isinstance(v, list) else v * 1.004)
          for k, v in perfect["s03"].items()})
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
    with open(results / "gradebook.csv", newline="", encoding="utf-8") as handle:
        rows = list(csv.DictReader(handle))
    return {"rows": rows, "by_id": {r["student_id"]: r for r in rows if r["student_id"]},
            "results": results, "perfect": perfect}


def consequential_answers(pack, sid):
    """s06's answers: synthesis 10 % off in r and l, the rest recomputed with their own r, l."""
    from crankbook import evaluate, params
    spec, _, _ = params.load_preset("course-design")
    with open(pack / "manifest.csv", newline="", encoding="utf-8") as handle:
        row = next(r for r in csv.DictReader(handle) if r["student_id"] == sid)
    values = params.validate(spec, {p.key: float(row[f"p_{p.key}"]) for p in spec.parameters})
    true = evaluate.evaluate(spec, values, {}, evaluate.crank_angle_grid(spec))
    own = evaluate.evaluate(spec, values, {}, evaluate.crank_angle_grid(spec), overrides={
        "crank_radius": true["crank_radius"] * 1.1, "rod_length": true["rod_length"] * 1.1})
    return {item.key: (own[item.key].tolist() if np.ndim(own[item.key]) else float(own[item.key]))
            for item in ASSIGNMENT.items}


def score(graded, sid):
    return float(graded["by_id"][sid]["score"])


def test_class_statuses(graded):
    by_id = graded["by_id"]
    assert by_id["s10"]["status"] == "unreadable"
    assert by_id["s11"]["status"] == "missing"
    for sid in ("s01", "s02", "s03", "s04", "s05", "s06", "s07", "s08", "s09", "s12"):
        assert by_id[sid]["status"] == "graded", sid
    assert [r for r in graded["rows"] if r["status"] == "unmatched"]


def test_perfect_and_within_tolerance_get_full_marks(graded):
    assert score(graded, "s01") == 100.0
    assert score(graded, "s03") == 100.0
    assert score(graded, "s08") == 100.0


def test_blank_scores_zero_and_is_flagged(graded):
    assert score(graded, "s02") == 0.0
    assert graded["by_id"]["s02"]["flags"] == "blank"


def test_unit_slip_earns_half_of_the_item(graded):
    velocity = np.asarray(graded["perfect"]["s04"]["pos_slider_velocity"])
    item = ASSIGNMENT.item["pos_slider_velocity"]
    # at the highest and lowest positions v = 0, and 0 × 1000 is still right
    still_right = np.sum(np.abs(velocity * 1000 - velocity) <= item.abs_floor)
    expected = item.points * (still_right + 0.5 * (velocity.size - still_right)) / velocity.size
    assert float(graded["by_id"]["s04"]["pos_slider_velocity"]) == pytest.approx(expected,
                                                                                abs=0.01)
    assert score(graded, "s04") == pytest.approx(100 - item.points + expected, abs=0.02)


def test_sign_slip_earns_half_of_the_item(graded):
    torque = np.asarray(graded["perfect"]["s05"]["pos_balancing_torque"])
    # cells whose expected value is within the item's floor stay right when negated
    item = ASSIGNMENT.item["pos_balancing_torque"]
    tiny = np.sum(np.abs(torque) <= item.abs_floor)
    expected = item.points * (tiny + 0.5 * (torque.size - tiny)) / torque.size
    assert float(graded["by_id"]["s05"]["pos_balancing_torque"]) == pytest.approx(expected,
                                                                                  abs=0.01)


def test_consequential_errors_earn_the_rubric_fraction(graded, pack):
    row = graded["by_id"]["s06"]
    assert float(row["crank_radius"]) == 0 and float(row["rod_length"]) == 0
    assert float(row["extreme_angle"]) == 3.0                 # θ does not depend on r, l
    own = consequential_answers(pack, "s06")
    true = graded["perfect"]["s06"]
    for item in ASSIGNMENT.items:
        if item.key in ("crank_radius", "rod_length", "extreme_angle"):
            continue
        theirs = np.atleast_1d(own[item.key])
        right = np.atleast_1d(np.asarray(true[item.key], dtype=float))
        fractions = []
        for i, value in enumerate(theirs):
            ok = abs(value - right[i]) <= max(item.tolerance * abs(right[i]), item.abs_floor)
            fractions.append(1.0 if ok else 0.8)
        expected = item.points * np.mean(fractions)
        if item.key != "flywheel_inertia":
            assert float(row[item.key]) == pytest.approx(expected, abs=0.01), item.key
    assert 50 < score(graded, "s06") < 90


def test_another_students_file_is_flagged(graded):
    row = graded["by_id"]["s07"]
    flags = row["flags"].split(";")
    assert {"wrong-student", "parameters-changed", "duplicate"} <= set(flags)
    assert "s08" in row["notes"] and "s07" in graded["by_id"]["s08"]["notes"]
    assert "duplicate" in graded["by_id"]["s08"]["flags"].split(";")
    assert score(graded, "s07") < 50


def test_edited_parameter_is_flagged_but_graded_against_the_assignment(graded):
    row = graded["by_id"]["s09"]
    assert row["flags"] == "parameters-changed" and "stroke" in row["notes"]
    assert score(graded, "s09") == 100.0


def test_formulas_saved_without_values_are_recalculated(graded):
    assert score(graded, "s12") == 100.0


def test_csv_outputs_cannot_execute(graded):
    for name in ("gradebook.csv", "lms-import.csv"):
        text = (graded["results"] / name).read_text(encoding="utf-8")
        for row in csv.reader(io.StringIO(text)):
            for field in row:
                assert not field.startswith(("=", "+", "-", "@")), (name, field)


def test_feedback_and_class_report(graded):
    feedback = (graded["results"] / "feedback" / "s04.md").read_text(encoding="utf-8")
    assert "unit slip" in feedback and "a_pos_slider_velocity" in feedback
    book = openpyxl.load_workbook(graded["results"] / "class-report.xlsx")
    assert {"Items", "Totals", "Students"} <= set(book.sheetnames)
    assert book["Items"]._charts and book["Totals"]._charts
    lms = list(csv.DictReader(io.StringIO((graded["results"] / "lms-import.csv")
                                          .read_text(encoding="utf-8"))))
    assert [r["identifier"] for r in lms] == ROSTER


def test_synthesis_key_matches_an_independent_synthesis(pack):
    with open(pack / "manifest.csv", newline="", encoding="utf-8") as handle:
        rows = list(csv.DictReader(handle))
    for row in rows:
        values = key_values(pack, row["student_id"])
        H, e, K = (float(row[f"p_{k}"]) / s for k, s in
                   (("stroke", 1000), ("offset", 1000), ("time_ratio", 1)))
        assert values["crank_radius"] == pytest.approx(
            mechanism.crank_radius_from_design(H, e, K) * 1000, rel=1e-12)
        assert values["rod_length"] == pytest.approx(
            mechanism.rod_length_from_design(H, e, K) * 1000, rel=1e-12)


def test_variants_are_distinct_valid_and_printable(pack):
    with open(pack / "manifest.csv", newline="", encoding="utf-8") as handle:
        rows = list(csv.DictReader(handle))
    assert [r["student_id"] for r in rows] == ROSTER and rows[0]["group"] == "G1"
    assert len({r["fingerprint"] for r in rows}) == len(rows)
    for row in rows:
        assert float(row["p_stroke"]) % 10 == 0 and float(row["p_offset"]).is_integer()
        assert round(float(row["p_time_ratio"]), 2) == float(row["p_time_ratio"])
        names = named(pack / "keys" / f"{row['student_id']}.xlsx")
        assert names["q_min_transmission_angle"] >= 45.0
        raw = np.sort(np.asarray(names["q_raw_crank_angle"]) % 360)
        assert np.diff(np.concatenate([raw, [raw[0] + 360]])).min() >= 4.0


def test_no_answer_leaks_into_student_files(pack):
    for sid in ROSTER:
        with zipfile.ZipFile(pack / "students" / f"{sid}.xlsx") as archive:
            blob = b"".join(archive.read(n) for n in archive.namelist())
        assert b"<f>" not in blob, "student files carry no formulas"
        values = key_values(pack, sid)
        secrets = [values["crank_radius"], values["rod_length"], values["extreme_angle"],
                   values["flywheel_inertia"], values["pos_resisting_torque"],
                   *values["pos_balancing_torque"][1:6], *values["pos_slider_velocity"][1:6]]
        for secret in secrets:
            for text in (repr(float(secret)), f"{secret:.10g}", f"{secret:.8g}"):
                assert text.encode() not in blob, (sid, text)
        book = openpyxl.load_workbook(pack / "students" / f"{sid}.xlsx")
        assert all(n.startswith(("p_", "a_", "s_")) for n in book.defined_names)
        assert all(ws.sheet_state == "visible" for ws in book.worksheets)


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
    # and the same students get the same parameters as in the full class
    with open(tmp_path / "a" / "manifest.csv", encoding="utf-8") as a, \
            open(pack / "manifest.csv", encoding="utf-8") as b:
        assert list(csv.DictReader(a)) == list(csv.DictReader(b))[:3]


@pytest.mark.parametrize("roster,expected", [
    ("student_id,name\na1,A\na1,B\n", "duplicate student_id 'a1'"),
    ("student_id,name\n,A\n", "empty student_id"),
    ("id,name\na1,A\n", "needs a 'student_id' column"),
])
def test_bad_rosters_are_refused(tmp_path, roster, expected):
    path = tmp_path / "r.csv"
    path.write_text(roster)
    done = run_cli("assign", "--roster", path, "-o", tmp_path / "out")
    assert done.returncode == 2 and expected in done.stderr, done.stderr
    assert len(done.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "out").exists()


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
    write_roster(roster, ["e1", "e2"])
    assert run_cli("assign", "--preset", "thesis", "--roster", roster, "-o",
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
    rows = {r["student_id"]: r for r in csv.DictReader(open(tmp_path / "res" / "gradebook.csv",
                                                            encoding="utf-8"))}
    assert float(rows["e1"]["score"]) == 100.0 and rows["e2"]["status"] == "missing"


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
            '<lolz>&lol2;</lolz>').encode()
    _rezip(student / "s04.xlsx", subs / "s04.xlsx",
           lambda items: items.update({"docProps/custom.xml": bomb}))
    fill(student / "s05.xlsx", subs / "s05.xlsx", key_values(pack, "s05"), formulas=True)
    saved = recalc.convert([subs / "s05.xlsx"], tmp_path / "lo")[0]   # saved through LibreOffice
    shutil.move(saved, subs / "s05.xlsx")
    done = run_cli("grade", pack, subs, "-o", tmp_path / "res")
    assert done.returncode == 0, done.stderr
    rows = {r["student_id"]: r for r in csv.DictReader(
        open(tmp_path / "res" / "gradebook.csv", encoding="utf-8")) if r["student_id"]}
    assert rows["s01"]["status"] == "unreadable" and "password-protected" in rows["s01"]["notes"]
    assert rows["s02"]["status"] == "unreadable" and "macro" in rows["s02"]["notes"]
    assert rows["s03"]["status"] == "unreadable" and "zip bomb" in rows["s03"]["notes"]
    assert rows["s04"]["status"] == "unreadable" and "entit" in rows["s04"]["notes"]
    assert rows["s05"]["status"] == "graded" and float(rows["s05"]["score"]) == 100.0
