"""Hostile input, second pass (issue 25): ownership that cannot be forged, only regular
files read, memory bounded by the file, nothing left behind, one line for every
teacher-side mistake, no machine details in feedback."""
import csv
import os
import re
import signal
import subprocess
import sys
import time
import zipfile
from pathlib import Path

import openpyxl
import pytest

from crankbook import cli
from crankbook.support.workspace import sweep_temporary
from tests.conftest import run_cli
from tests.test_assignment import fill, key_answers, write_roster

ROSTER = ["m001", "s001", "s002"]


def run(capsys, *args):
    capsys.readouterr()
    code = cli.main([str(a) for a in args])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def gradebook(results):
    with open(results / "gradebook.csv", newline="", encoding="utf-8-sig") as handle:
        return {r["student_id"]: r for r in csv.DictReader(handle) if r["student_id"]}


@pytest.fixture(scope="module")
def pack(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("hostile-pack")
    write_roster(tmp / "roster.csv", ROSTER)
    assert cli.main(["assign", "--roster", str(tmp / "roster.csv"), "--seed", "5",
                     "-o", str(tmp / "class")]) == 0
    return tmp / "class"


# ------------------------------------------------------------------ ownership
def test_an_upload_named_for_another_student_stays_its_owners(pack, tmp_path, capsys):
    subs = tmp_path / "subs"
    fill(pack / "students" / "s002.xlsx", subs / "s002" / "s002.xlsx", key_answers(pack, "s002"))
    # m001 uploads a blank task named for s002, into m001's own LMS folder
    (subs / "m001_attempt_1").mkdir(parents=True)
    (subs / "m001_attempt_1" / "s002.xlsx").write_bytes(
        (pack / "students" / "m001.xlsx").read_bytes())
    # a file that says it is s002's (s_student_id), in s001's folder
    book = openpyxl.load_workbook(pack / "students" / "s001.xlsx")
    sheet, ref = next(iter(book.defined_names["s_student_id"].destinations))
    book[sheet][ref.replace("$", "")] = "s002"
    (subs / "s001").mkdir()
    book.save(subs / "s001" / "task.xlsx")
    os.utime(subs / "m001_attempt_1" / "s002.xlsx", (time.time() + 60, time.time() + 60))
    code, out, err = run(capsys, "grade", pack, subs, "-o", tmp_path / "results")
    assert code == 0, err
    rows = gradebook(tmp_path / "results")
    assert rows["s002"]["status"] == "graded" and float(rows["s002"]["score"]) == 100
    assert "multiple" not in rows["s002"]["flags"]
    assert rows["m001"]["status"] == "graded" and "path-names-other" in rows["m001"]["flags"]
    assert rows["s001"]["status"] == "graded"
    feedback = (tmp_path / "results" / "feedback" / "m001.md").read_text(encoding="utf-8")
    assert "s002" not in feedback                         # the flag is the teacher's


def test_a_folder_naming_two_students_matches_neither(pack, tmp_path, capsys):
    subs = tmp_path / "subs"
    (subs / "s001-s002").mkdir(parents=True)
    (subs / "s001-s002" / "x.xlsx").write_bytes((pack / "students" / "s001.xlsx").read_bytes())
    code, _, err = run(capsys, "grade", pack, subs, "-o", tmp_path / "results")
    assert code == 0, err
    rows = gradebook(tmp_path / "results")
    assert rows["s001"]["status"] == rows["s002"]["status"] == "missing"


# -------------------------------------------------------- only regular files
def test_pipes_devices_and_links_out_cannot_stop_the_batch(pack, tmp_path):
    subs = tmp_path / "subs"
    subs.mkdir()
    os.mkfifo(subs / "s001.xlsx")                             # reading it would wait forever
    os.symlink("/dev/zero", subs / "s002.xlsx")               # endless bytes, size 0
    (subs / "m001.xlsx").write_bytes((pack / "students" / "m001.xlsx").read_bytes())
    done = run_cli("grade", pack, subs, "-o", tmp_path / "results", timeout=120)
    assert done.returncode == 0, done.stderr
    rows = gradebook(tmp_path / "results")
    assert rows["m001"]["status"] == "graded"
    assert rows["s001"]["status"] == rows["s002"]["status"] == "unreadable"
    assert "命名管道" in rows["s001"]["status_text"] + rows["s001"].get("notes", "")
    assert "提交文件夹以外" in rows["s002"]["status_text"] + rows["s002"].get("notes", "")


def test_why_a_file_was_not_read_is_said_in_chinese(tmp_path):
    """A Chinese class reads every reason in Chinese: the refusals of non-regular files
    (as the reader words them) and of the bounded reader's limits."""
    from crankbook.assignment.results import reason_text
    from crankbook.assignment.submissions import _not_regular
    os.mkfifo(tmp_path / "pipe.xlsx")
    os.symlink("/etc/hostname", tmp_path / "out.xlsx")
    reasons = [_not_regular(tmp_path / name, tmp_path) for name in ("pipe.xlsx", "out.xlsx")]
    reasons += ["more than 2,000,000 XML elements: not a workbook crankbook wrote",
                "1900 sheets, more than 255: not a workbook a student would hand in",
                "name a_flywheel_inertia: refers to another file"]
    for reason in reasons:
        assert re.search(r"[\u4e00-\u9fff]", reason_text(reason, "zh")), reason


# ---------------------------------------------------------- bounded memory
def _limited(*args, megabytes=700, timeout=300):
    """crankbook ARGS under an address-space limit (a hostile file must fit in it)."""
    def limit():
        import resource
        resource.setrlimit(resource.RLIMIT_AS, (megabytes * 2**20, megabytes * 2**20))
    return subprocess.run([sys.executable, "-m", "crankbook", *map(str, args)],
                          capture_output=True, text=True, timeout=timeout, preexec_fn=limit)


def _add_names(path, target, names, before=None):
    """Add ``names`` defined names (name -> reference) to an .xlsx, before the first
    existing one when ``before``."""
    with zipfile.ZipFile(path) as archive:
        items = {n: archive.read(n) for n in archive.namelist()}
    xml = items["xl/workbook.xml"].decode()
    extra = "".join(f'<definedName name="{n}">{r}</definedName>' for n, r in names.items())
    if "<definedNames>" in xml:
        xml = xml.replace("<definedNames>", "<definedNames>" + extra, 1)
    else:
        xml = xml.replace("</sheets>", f"</sheets><definedNames>{extra}</definedNames>", 1)
    items["xl/workbook.xml"] = xml.encode()
    with zipfile.ZipFile(target, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, data in items.items():
            archive.writestr(name, data)


def test_thousands_of_extra_answer_names_cost_nothing(pack, tmp_path):
    subs = tmp_path / "subs"
    subs.mkdir()
    book = openpyxl.load_workbook(pack / "students" / "s001.xlsx")
    sheet = book.sheetnames[0]
    names = {f"a_extra_{i}": f"'{sheet}'!$A$1:$CV$100" for i in range(2000)}
    _add_names(pack / "students" / "s001.xlsx", subs / "s001.xlsx", names)
    assert (subs / "s001.xlsx").stat().st_size < 200_000
    done = _limited("grade", pack, subs, "-o", tmp_path / "results")
    assert done.returncode == 0, done.stderr[-500:]
    assert gradebook(tmp_path / "results")["s001"]["status"] == "graded"


def test_audit_ignores_names_the_template_does_not_have(tmp_path):
    built = tmp_path / "e.xlsx"
    assert run_cli("build", "--step", "10", "-o", built).returncode == 0
    names = {f"q_bogus_{i}": "'参数'!$A$1:$Z$5000" for i in range(300)}
    _add_names(built, tmp_path / "bomb.xlsx", names)
    started = time.monotonic()
    done = _limited("audit", tmp_path / "bomb.xlsx", timeout=120)
    assert done.returncode == 0, done.stdout + done.stderr
    assert time.monotonic() - started < 60


def test_a_stream_of_tiny_elements_is_refused_within_memory(tmp_path):
    built = tmp_path / "e.xlsx"
    assert run_cli("build", "--step", "10", "-o", built).returncode == 0
    with zipfile.ZipFile(built) as archive:
        items = {n: archive.read(n) for n in archive.namelist()}
    sheet = "xl/worksheets/sheet1.xml"
    xml = items[sheet].decode()
    items[sheet] = xml.replace("</sheetData>", "<x/>" * 3_000_000 + "</sheetData>").encode()
    with zipfile.ZipFile(tmp_path / "tiny.xlsx", "w", zipfile.ZIP_DEFLATED) as archive:
        for name, data in items.items():
            archive.writestr(name, data)
    done = _limited("audit", tmp_path / "tiny.xlsx", timeout=120)
    assert done.returncode in (1, 2) and "Traceback" not in done.stderr
    assert "MemoryError" not in done.stderr


# ------------------------------------------------------- nothing left behind
def _gone_pid():
    gone = subprocess.Popen([sys.executable, "-c", "pass"])
    gone.wait()
    return gone.pid


def _engine_on(folder):
    """A stand-in engine started on ``folder`` (its path in the command line, as
    LibreOffice's profile is), in its own process group."""
    return subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)", str(folder)],
                            start_new_session=True)


def test_the_next_run_removes_a_killed_runs_engine_and_copies(tmp_path):
    scratch = tmp_path / f"crankbook-grade-{_gone_pid()}-abc"
    scratch.mkdir(mode=0o700)
    (scratch / "00001.xlsx").write_bytes(b"a student's workbook")
    engine = _engine_on(scratch)
    (scratch / "engine.pgid").write_text(str(engine.pid))
    time.sleep(0.3)                                # its command line is in /proc
    assert sweep_temporary(tmp_path) == 1
    assert not scratch.exists()
    assert engine.wait(timeout=10) == -signal.SIGKILL


def test_a_planted_record_kills_nothing_and_hangs_nothing(tmp_path):
    """Anyone could write a scratch folder's engine record in a shared temp folder: a
    record naming a process group that is not an engine started on that folder (a
    teacher's editor, another user's run) is not signalled; a FIFO, a link or a huge
    file in its place is passed over; a folder open to others is not touched; and
    crankbook's own scratch folders live in a private folder of the user's."""
    from crankbook.support.workspace import scratch_root
    bystander = subprocess.Popen(["sleep", "60"], start_new_session=True)
    try:
        planted = []
        for how in ("names", "fifo", "link", "huge"):
            scratch = tmp_path / f"crankbook-lo-{_gone_pid()}-{how}"
            scratch.mkdir(mode=0o700)
            record = scratch / "engine.pgid"
            if how == "names":
                record.write_text(str(bystander.pid))
            elif how == "fifo":
                os.mkfifo(record)
            elif how == "link":
                (tmp_path / "elsewhere").write_text(str(bystander.pid))
                record.symlink_to(tmp_path / "elsewhere")
            else:
                record.write_text(str(bystander.pid) + " " * 10_000_000)
            planted.append(scratch)
        shared = tmp_path / f"crankbook-lo-{_gone_pid()}-open"
        shared.mkdir(mode=0o777)
        os.chmod(shared, 0o777)
        assert sweep_temporary(tmp_path) == len(planted)
        assert bystander.poll() is None                      # alive: never signalled
        assert shared.exists()                               # not ours to remove
        root = scratch_root()
        assert root.stat().st_mode & 0o777 == 0o700 and root.stat().st_uid == os.getuid()
    finally:
        bystander.kill()


def test_a_second_run_into_the_same_output_is_refused(tmp_path):
    target = tmp_path / "same.xlsx"
    holder = subprocess.Popen(["sleep", "30"])
    (tmp_path / ".same.xlsx.crankbook.lock").write_text(str(holder.pid))
    try:
        done = run_cli("build", "--step", "30", "-o", target)
        assert done.returncode == 2 and "another crankbook run" in done.stderr
        assert len(done.stderr.strip().splitlines()) == 1 and not target.exists()
    finally:
        holder.kill()


def test_a_build_never_replaces_the_pressure_file_it_reads(tmp_path):
    """`build --pressure trace.xlsx -o trace.xlsx` would have replaced the engineer's
    measurement (perhaps the only copy) with the workbook: refused in one line before
    anything is written, by its own name, another spelling of it or a hard link; the
    Python API the same.  Another name builds."""
    import numpy as np
    import pandas as pd
    import crankbook
    from crankbook.errors import OutputPathError
    angle = np.arange(0.0, 720.0, 2.0)
    trace = tmp_path / "trace.xlsx"
    pd.DataFrame({"angle": angle, "p": 0.1 + 4 * np.exp(-((angle - 372) / 30) ** 2)}) \
        .to_excel(trace, index=False)
    measured = trace.read_bytes()
    os.link(trace, tmp_path / "linked.xlsx")
    for output in (trace, tmp_path / "sub" / ".." / "trace.xlsx", tmp_path / "linked.xlsx"):
        done = run_cli("build", "--pressure", trace, "--step", "30", "-o", output)
        assert done.returncode == 2, done.stdout
        lines = done.stderr.strip().splitlines()
        assert len(lines) == 1 and "measured-pressure file" in lines[0], lines
        assert trace.read_bytes() == measured
    with pytest.raises(OutputPathError, match="--pressure"):
        crankbook.compute("thesis", pressure=trace, step=30.0).to_excel(trace)
    assert trace.read_bytes() == measured
    done = run_cli("build", "--pressure", trace, "--step", "30", "-o", tmp_path / "built.xlsx")
    assert done.returncode == 0 and (tmp_path / "built.xlsx").is_file(), done.stderr


# --------------------------------------------- one line for teacher mistakes
@pytest.mark.parametrize("args,words", [
    (["assign", "--roster", "{roster}", "-o", "x" * 300], "the path is too long"),
    (["assign", "--roster", "{roster}", "-o", ""], "give an output directory"),
    (["grade", "{pack}", "{subs}", "-o", "y" * 300], "the path is too long"),
    (["build", "--nosuch"], "unrecognized arguments"),
    (["build", "--set", "bore=2000.0000001"], "2000.0000001: must be"),
    (["build", "--set", "bore=" + "9" * 400], "…"),
    # option numbers take --set's syntax: what Python's float() would take is refused
    (["build", "--step", "1_0"], "not a plain decimal number"),
    (["build", "--step", "nan"], "not a plain decimal number"),
    (["build", "--cam-step", "１"], "not a plain decimal number"),
    (["assign", "--roster", "{roster}", "--seed", "１２", "-o", "c"], "not a whole number"),
    (["assign", "--roster", "{roster}", "--seed", "-5", "-o", "c"], "not a whole number"),
    (["grade", "{pack}", "{subs}", "--out-of", "inf"], "not a plain decimal number"),
    (["grade", "{pack}", "{subs}", "--out-of", "-20"], "must be a number > 0"),
])
def test_teacher_side_mistakes_get_one_line(pack, tmp_path, args, words):
    roster = tmp_path / "roster.csv"
    write_roster(roster, ["s1"])
    subs = tmp_path / "subs"
    subs.mkdir()
    args = [a.format(roster=roster, pack=pack, subs=subs) for a in args]
    done = run_cli(*args, cwd=tmp_path)
    assert done.returncode == 2, done.stderr
    assert len(done.stderr.strip().splitlines()) == 1 and "Traceback" not in done.stderr
    assert words in done.stderr and len(done.stderr) < 700


@pytest.mark.parametrize("ids,words", [(["S1", "s1"], "differs only in case"),
                                       (["CON", "s2"], "reserves for a device")])
def test_ids_that_collide_as_file_names_are_refused(tmp_path, ids, words):
    write_roster(tmp_path / "roster.csv", ids)
    done = run_cli("assign", "--roster", tmp_path / "roster.csv", "-o", tmp_path / "cls")
    assert done.returncode == 2 and words in done.stderr
    assert not (tmp_path / "cls").exists()


def test_damaged_teacher_files_get_one_line(pack, tmp_path):
    import shutil
    copy = tmp_path / "class"
    shutil.copytree(pack, copy)
    with open(copy / "manifest.csv", "ab") as handle:
        handle.write("张三,1\n".encode("gbk"))                # Excel appended GBK bytes
    subs = tmp_path / "subs"
    subs.mkdir()
    done = run_cli("grade", copy, subs, "-o", tmp_path / "results")
    assert done.returncode == 2 and "manifest.csv" in done.stderr
    assert len(done.stderr.strip().splitlines()) == 1
    trace = tmp_path / "trace.csv"
    trace.write_text("angle,pressure\n0," + "1" * 200_000 + "\n720,0.1\n")
    done = run_cli("build", "--pressure", trace, "-o", tmp_path / "t.xlsx")
    assert done.returncode == 2 and "not a readable CSV" in done.stderr
    assert len(done.stderr.strip().splitlines()) == 1
    european = tmp_path / "european.csv"                      # ';' and decimal commas
    european.write_text("angle;pressure\n0;0,1013\n360;4,5\n720;0,1\n", encoding="utf-8")
    done = run_cli("build", "--pressure", european, "-o", tmp_path / "e.xlsx")
    assert done.returncode == 2 and "a decimal comma" in done.stderr
    assert len(done.stderr.strip().splitlines()) == 1 and not (tmp_path / "e.xlsx").exists()


@pytest.mark.parametrize("points,words", [("1_000", "not a plain decimal number"),
                                          ("２", "not a plain decimal number"),
                                          ("nan", "not a plain decimal number"),
                                          ("-1", "must lie in [0,"),
                                          ("1000", "must lie in [0,")])
def test_an_override_cannot_give_what_the_item_does_not_have(pack, tmp_path, points, words):
    from crankbook.assignment.grade import load_directory
    _, assignment, _ = load_directory(pack)
    key = assignment.items[0].key
    table = tmp_path / "overrides.csv"
    table.write_text("student,item,action,points,reason,who\n"
                     f"s001,a_{key},points,{points},agreed,teacher\n", encoding="utf-8")
    subs = tmp_path / "subs"
    subs.mkdir()
    done = run_cli("grade", pack, subs, "-o", tmp_path / "r", "--overrides", table)
    assert done.returncode == 2 and words in done.stderr and "row 2" in done.stderr, done.stderr
    assert len(done.stderr.strip().splitlines()) == 1


@pytest.mark.parametrize("damage", ["nan", "infinity", "deep", "word", "points"])
def test_a_damaged_earlier_round_is_refused_in_one_line(pack, tmp_path, damage):
    import json
    subs = tmp_path / "subs"
    fill(pack / "students" / "s001.xlsx", subs / "s001.xlsx", key_answers(pack, "s001"))
    assert run_cli("grade", pack, subs, "-o", tmp_path / "r1").returncode == 0
    path = tmp_path / "r1" / "grades.json"
    data = json.loads(path.read_text(encoding="utf-8"))
    graded = next(s for s in data["students"] if s["status"] == "graded")
    key = next(iter(graded["items"]))
    if damage == "nan":
        text = json.dumps(data).replace(json.dumps(graded["items"][key][0]), "NaN", 1)
    elif damage == "infinity":
        graded["items"][key][0] = 1e400
        text = json.dumps(data)
    elif damage == "deep":
        text = json.dumps(data)[:-1] + ', "x": ' + "[" * 100_000 + "]" * 100_000 + "}"
    elif damage == "word":
        graded["notes"].append(["import os", {}, False])
        text = json.dumps(data)
    else:
        graded["items"][key][0] = 1e6
        text = json.dumps(data)
    path.write_text(text, encoding="utf-8")
    done = run_cli("grade", pack, subs, "-o", tmp_path / "r2", "--previous", tmp_path / "r1")
    assert done.returncode == 2 and "is damaged" in done.stderr, done.stderr
    assert len(done.stderr.strip().splitlines()) == 1 and "Traceback" not in done.stderr


# ------------------------------------------------- no machine in feedback
def _machine_book(pack, target):
    """s001's task with its scalar answers computed, in order: CELL directly, through
    a helper cell, through a defined name, through a local name, from another file
    ([1]), by INDIRECT where the book asks the machine, from a cell of an array
    formula's area — and one honest formula (=2*3) last."""
    from openpyxl.workbook.defined_name import DefinedName
    from openpyxl.worksheet.formula import ArrayFormula
    answers = key_answers(pack, "s001")
    scalars = [k for k, v in answers.items() if not isinstance(v, list)][:8]
    fill(pack / "students" / "s001.xlsx", target, answers)
    book = openpyxl.load_workbook(target)
    helper = book.worksheets[0]
    helper["Z1"] = '=CELL("filename")'
    helper["Z2"] = "=Z1"
    helper["Z3"] = ArrayFormula("Z3:Z4", '=INFO("system")&{1;2}')
    book.defined_names["where"] = DefinedName("where", attr_text='INFO("directory")')
    helper.defined_names["here"] = DefinedName("here", attr_text='CELL("filename")')
    title = helper.title.replace("'", "''")
    chains = ['=CELL("filename")', f"='{title}'!Z2&\"\"", "=where", "=here",
              "=[1]Sheet1!A1", '=INDIRECT("Z"&1)', f"='{title}'!Z4", "=2*3"]
    for key, formula in zip(scalars, chains):
        sheet, ref = next(iter(book.defined_names[f"a_{key}"].destinations))
        book[sheet][ref.replace("$", "")] = formula
    book.save(target)
    return scalars


def test_an_answer_depending_on_the_machine_down_any_chain_is_refused(pack, tmp_path):
    """Issue 39.6: a helper cell, a name, a local name, another file, INDIRECT or an
    array formula between the answer and CELL/INFO still make the answer the
    grading machine's: refused, its own formula kept as text; the honest formula
    is left to be calculated."""
    from crankbook.assignment.grade import answer_shapes
    from crankbook.assignment.submissions import Submission, read
    from crankbook.assignment import template
    from crankbook.spec import params
    scalars = _machine_book(pack, tmp_path / "s001.xlsx")
    spec, _, _ = params.load_preset("course-design")
    shapes = answer_shapes(template.for_preset("course-design"), "zh", spec)
    sub = Submission(path=tmp_path / "s001.xlsx", relative="s001.xlsx")
    read(sub, shapes)
    assert sub.problem is None, sub.problem
    refused = [getattr(sub.answers[k][0], "machine_dependent", False) for k in scalars]
    assert refused == [True] * 7 + [False], refused
    assert sub.answers[scalars[0]][0] == '=CELL("filename")'
    assert sub.needs_recalc                           # =2*3 is still calculated


@pytest.mark.parametrize("text, rows, cols, moved", [
    ("A1+$B$2", 1, 1, "B2+$B$2"),
    ("SUM(A1:A3)*$C1", 2, 0, "SUM(A3:A5)*$C3"),
    ("'My sheet'!B:B", 0, 1, "'My sheet'!C:C"),
    ('"A1"&A1', 1, 0, '"A1"&A2'),                   # a string never moves
    ("Z$9", 0, 2, "AB$9"),
])
def test_a_shared_formula_follower_reads_its_master_moved(text, rows, cols, moved):
    from crankbook.reading.dependencies import moved as move
    assert move(text, rows, cols) == moved


@pytest.mark.parametrize("text, ranges, names", [
    ("A1+Sheet2!B2", [("S", 1, 1, 1, 1), ("Sheet2", 2, 2, 2, 2)], []),
    ("SUM('a b'!A1:C3)+rate", [("a b", 1, 1, 3, 3)], ["rate"]),
    ('CONCAT("B5", x_1)', [], ["x_1"]),
    ("3:4", [("S", 3, 1, 4, 16384)], []),
    ("TRUE+LOG10(2)", [], []),
])
def test_references_are_the_cells_ranges_and_names_a_formula_reads(text, ranges, names):
    from crankbook.reading.dependencies import references
    assert references(text, "S") == (ranges, names)


@pytest.mark.libreoffice
def test_environment_functions_in_answers_are_shown_as_typed(pack, tmp_path, soffice):
    subs = tmp_path / "subs"
    _machine_book(pack, subs / "s001.xlsx")       # saved without values: LibreOffice runs
    done = run_cli("grade", pack, subs, "-o", tmp_path / "results")
    assert done.returncode == 0, done.stderr
    feedback = (tmp_path / "results" / "feedback" / "s001.md").read_text(encoding="utf-8")
    assert "crankbook-" not in feedback and "/tmp" not in feedback and "file:" not in feedback
    assert not re.search(r"\b(Linux|LINUX|pcdos|mac)\b", feedback)
    assert 'CELL("filename")' in feedback and feedback.count("拒绝") == 7


# ---------------------------------------------- no folder crankbook did not write
def _refused(code, err, *words):
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err, err
    for word in words:
        assert word in err, err


def test_grade_replaces_only_a_folder_it_wrote(pack, tmp_path, capsys):
    """`grade -o` replaced whatever folder it was given: the class folder with its keys
    and seed, a teacher's own notes.  An existing folder is replaced only when it
    carries the marker of an earlier grade into it; an input is never an output."""
    subs = tmp_path / "subs"
    fill(pack / "students" / "s001.xlsx", subs / "s001.xlsx", key_answers(pack, "s001"))
    notes = tmp_path / "notes"
    notes.mkdir()
    (notes / "mine.txt").write_text("the teacher's own file")
    code, _, err = run(capsys, "grade", pack, subs, "-o", notes)
    _refused(code, err, "was not written by crankbook grade")
    assert (notes / "mine.txt").read_text() == "the teacher's own file"
    for target, words in ((pack, "an input of this run"), (subs, "an input of this run"),
                          (pack / "keys", "an input of this run"),
                          (tmp_path, "an input of this run"),        # contains the inputs
                          (subs / "results", "an input of this run"),
                          (".", "current folder"), ("..", "current folder"),
                          ("/", "current folder")):
        code, _, err = run(capsys, "grade", pack, subs, "-o", target)
        _refused(code, err, *([words] if words else []))
    code, _, err = run(capsys, "grade", pack, subs, "-o", tmp_path / "r", "--return", subs / "back")
    _refused(code, err, "--return", "an input of this run")
    assert sorted(p.name for p in (pack / "keys").iterdir())          # the keys stand
    umask = os.umask(0)
    os.umask(umask)
    for _ in range(2):                  # its own earlier output: replaced, with the umask
        code, _, err = run(capsys, "grade", pack, subs, "-o", tmp_path / "r")
        assert code == 0, err
        assert (tmp_path / "r" / ".crankbook").read_text().strip() == "grade"
        assert (tmp_path / "r").stat().st_mode & 0o777 == 0o777 & ~umask
    code, _, err = run(capsys, "grade", pack, subs, "-o", tmp_path / "b", "--return",
                       tmp_path / "r")
    _refused(code, err, "--return", "not written by crankbook grade --return")


def test_export_replaces_only_its_own_folder(tmp_path, capsys):
    import crankbook
    path = crankbook.compute("inline-4", step=30.0).to_excel(tmp_path / "i4.xlsx")
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "keep.csv").write_text("x")
    code, _, err = run(capsys, "export", "torsion", path, "-o", mine)
    _refused(code, err, "was not written by crankbook export torsion")
    assert (mine / "keep.csv").read_text() == "x"
    code, _, err = run(capsys, "export", "torsion", path, "-o", tmp_path)
    _refused(code, err, "an input of this run")
    for _ in range(2):
        code, _, err = run(capsys, "export", "torsion", path, "-o", tmp_path / "tv")
        assert code == 0, err


# ------------------------------------------------------- student text is inert
def test_student_text_is_inert_in_feedback_and_stored_as_typed(tmp_path, capsys):
    """A roster name and a typed answer are shown as typed and do nothing: no HTML tag,
    link or image reaches the Markdown feedback live; a name starting with '=' is kept
    as the student wrote it in grades.json and escaped only in the CSV files."""
    import json
    roster = tmp_path / "roster.csv"
    roster.write_text("学号,姓名\ns1,=HYPERLINK(\"http://x\")\ns2,<img src=x onerror=alert(1)>\n",
                      encoding="utf-8")
    code, _, err = run(capsys, "assign", "--roster", roster, "--seed", "3", "-o",
                       tmp_path / "class")
    assert code == 0, err
    pack = tmp_path / "class"
    subs = tmp_path / "subs"
    for sid in ("s1", "s2"):
        answers = key_answers(pack, sid)
        first = next(iter(answers))
        typed = dict(answers)
        typed[first] = "![p](http://evil/x.png) [go](http://evil/)" if not isinstance(
            answers[first], list) else ["![p](http://evil/x.png)"] + list(answers[first][1:])
        fill(pack / "students" / f"{sid}.xlsx", subs / f"{sid}.xlsx", typed)
    code, _, err = run(capsys, "grade", pack, subs, "-o", tmp_path / "r")
    assert code == 0, err
    for sid in ("s1", "s2"):
        text = (tmp_path / "r" / "feedback" / f"{sid}.md").read_text(encoding="utf-8")
        assert "<img" not in text and "&lt;img" in text or sid == "s1", text[:300]
        assert not re.search(r"(?<!\\)\]\(|(?<!\\)!(?<!\\)\[", text), text[:600]
        assert "\\!\\[p\\](http://evil/x.png)" in text        # shown as typed
    stored = json.loads((tmp_path / "r" / "grades.json").read_text(encoding="utf-8"))
    assert {s["name"] for s in stored["students"]} == {'=HYPERLINK("http://x")',
                                                       "<img src=x onerror=alert(1)>"}
    with open(tmp_path / "r" / "gradebook.csv", encoding="utf-8-sig") as handle:
        assert '"=HYPERLINK' not in handle.read()             # no live formula in the CSV


# --------------------------------------------- ownership by name is unambiguous
def test_a_part_naming_two_students_or_a_shared_name_is_nobodys(tmp_path, capsys):
    """'s1-2' names s1 and s1-2: it was given to the longer id, so s1-2's classmate s1
    could be graded by a folder name.  A Moodle download folder is matched by the
    participant's full name (its number is Moodle's, not an id); a name two roster
    students share matches neither; either way the file is listed for the teacher."""
    roster = tmp_path / "roster.csv"
    roster.write_text("学号,姓名\ns1,张伟\ns1-2,张伟\ns3,李娜\n", encoding="utf-8")
    code, _, err = run(capsys, "assign", "--roster", roster, "--seed", "4", "-o",
                       tmp_path / "class")
    assert code == 0, err
    pack, subs = tmp_path / "class", tmp_path / "subs"
    fill(pack / "students" / "s3.xlsx", subs / "s1-2" / "task.xlsx", key_answers(pack, "s3"))
    fill(pack / "students" / "s3.xlsx",
         subs / "李娜_8812345_assignsubmission_file_" / "s1.xlsx", key_answers(pack, "s3"))
    fill(pack / "students" / "s1.xlsx",
         subs / "张伟_8812346_assignsubmission_file_" / "task.xlsx", key_answers(pack, "s1"))
    code, _, err = run(capsys, "grade", pack, subs, "-o", tmp_path / "r")
    assert code == 0, err
    book = gradebook(tmp_path / "r")
    assert book["s3"]["status"] == "graded"                       # by her Moodle name
    assert book["s1"]["status"] != "graded" and book["s1-2"]["status"] != "graded"
    unmatched = (tmp_path / "r" / "gradebook.csv").read_text(encoding="utf-8-sig")
    assert "s1-2/task.xlsx" in unmatched and "张伟_8812346" in unmatched


def test_a_run_writing_the_returns_is_refused_before_the_grading(pack, tmp_path, capsys):
    """Two teachers grading into other results but the same --return folder: the second
    was refused only after its whole grading, its results already replaced."""
    subs = tmp_path / "subs"
    fill(pack / "students" / "s001.xlsx", subs / "s001.xlsx", key_answers(pack, "s001"))
    holder = subprocess.Popen(["sleep", "30"])
    (tmp_path / ".back.crankbook.lock").write_text(str(holder.pid))
    try:
        code, _, err = run(capsys, "grade", pack, subs, "-o", tmp_path / "r", "--return",
                           tmp_path / "back")
        _refused(code, err, "another crankbook run")
        assert not (tmp_path / "r").exists()                # no work done, nothing written
    finally:
        holder.kill()


# ------------------------------------------------- a return is written, not passed on
def _parts_text(path):
    with zipfile.ZipFile(path) as archive:
        return {n: archive.read(n).decode("utf-8", "replace") for n in archive.namelist()}


def test_a_returned_workbook_carries_only_the_students_answers(pack, tmp_path, capsys):
    """Issue 39.4: the return is the assigned workbook with the student's answer values
    and the grader's marks.  s001 hands in a file carrying an external link, a
    hyperlink, a HYPERLINK formula, hidden and very hidden sheets, a comment, a
    header, a validation prompt and names of its own; s002 hands in a copy of s001's
    returned workbook (its score box and all).  Neither return carries any of it."""
    from openpyxl.comments import Comment
    from openpyxl.workbook.defined_name import DefinedName
    from openpyxl.worksheet.datavalidation import DataValidation
    subs = tmp_path / "subs"
    answers = key_answers(pack, "s001")
    fill(pack / "students" / "s001.xlsx", subs / "s001.xlsx", answers)
    book = openpyxl.load_workbook(subs / "s001.xlsx")
    first = book.worksheets[0]
    first["Z1"].hyperlink = "https://PLANTED.example/phish"
    first["Z2"] = '=HYPERLINK("https://PLANTED.example","PLANTED")'
    first["Z3"].comment = Comment("PLANTED comment", "PLANTED author")
    first.oddHeader.center.text = "PLANTED header"
    rule = DataValidation(type="whole", prompt="PLANTED prompt", showInputMessage=True)
    first.add_data_validation(rule)
    rule.add("Z4")
    hidden = book.create_sheet("PLANTED hidden")
    hidden.sheet_state = "hidden"
    hidden["A1"] = "PLANTED"
    very = book.create_sheet("PLANTED veryhidden")
    very.sheet_state = "veryHidden"
    book.defined_names["PLANTED_name"] = DefinedName("PLANTED_name", attr_text="'PLANTED hidden'!$A$1")
    book.save(subs / "s001.xlsx")
    with zipfile.ZipFile(subs / "s001.xlsx", "a") as archive:       # an external link part
        archive.writestr("xl/externalLinks/externalLink1.xml",
                         '<externalLink xmlns="http://schemas.openxmlformats.org/'
                         'spreadsheetml/2006/main"><externalBook r:id="rId1" xmlns:r="PLANTED"/>'
                         '</externalLink>')
    code, _, err = run(capsys, "grade", pack, subs, "-o", tmp_path / "r1", "--return",
                       tmp_path / "back1")
    assert code == 0, err
    returned = tmp_path / "back1" / "s001.xlsx"
    # s002 hands in s001's returned workbook as their own
    (subs / "s002.xlsx").write_bytes(returned.read_bytes())
    code, _, err = run(capsys, "grade", pack, subs, "-o", tmp_path / "r2", "--return",
                       tmp_path / "back2")
    assert code == 0, err
    assigned = {sid: openpyxl.load_workbook(pack / "students" / f"{sid}.xlsx")
                for sid in ("s001", "s002")}
    for sid in ("s001", "s002"):
        path = tmp_path / "back2" / f"{sid}.xlsx"
        parts = _parts_text(path)
        assert not any("PLANTED" in text for text in parts.values()), sid
        assert not any(n.startswith("xl/externalLinks") for n in parts), sid
        assert not any("<hyperlink" in t or "HYPERLINK(" in t for t in parts.values()), sid
        back = openpyxl.load_workbook(path)
        assert back.sheetnames[1:] == assigned[sid].sheetnames
        assert all(ws.sheet_state == "visible" for ws in back.worksheets)
        assert set(back.defined_names) == set(assigned[sid].defined_names)
        text = " ".join(parts.values())
        assert "学生1号" not in text if sid == "s002" else True      # not s001's score box
        assert len([t for t in back.worksheets[0].iter_rows(values_only=True)
                    if t[0] and str(t[0]).startswith("得分")]) == 1
        # the student's answer values stand in the assigned cells
        sheet, ref = next(iter(back.defined_names["a_crank_radius"].destinations))
        assert back[sheet][ref.replace("$", "")].value == pytest.approx(answers["crank_radius"])
    rows = gradebook(tmp_path / "r2")
    assert rows["s002"]["status"] == "graded"


def test_a_return_is_never_silently_missing(pack, tmp_path, capsys, monkeypatch):
    """Issue 39.5: a graded student whose workbook cannot go back — the assigned file
    gone from the class folder, memory running out while writing it — is told why,
    in the gradebook's notes, the feedback and the page that goes back."""
    import shutil
    import crankbook.assignment.annotate as annotate
    klass = tmp_path / "class"
    shutil.copytree(pack, klass)
    subs = tmp_path / "subs"
    for sid in ROSTER:
        fill(pack / "students" / f"{sid}.xlsx", subs / f"{sid}.xlsx", key_answers(pack, sid))
    (klass / "students" / "s001.xlsx").unlink()
    real = annotate.openpyxl.load_workbook

    def short_of_memory(path, *args, **kwargs):
        if Path(path).stem == "s002":
            raise MemoryError
        return real(path, *args, **kwargs)
    monkeypatch.setattr(annotate.openpyxl, "load_workbook", short_of_memory)
    code, _, err = run(capsys, "grade", klass, subs, "-o", tmp_path / "r", "--return",
                       tmp_path / "back")
    assert code == 0, err
    rows = gradebook(tmp_path / "r")
    assert sorted(p.name for p in (tmp_path / "back").glob("*.xlsx")) == ["m001.xlsx"]
    for sid, why in (("s001", "班级文件夹里没有"), ("s002", "MemoryError")):
        assert rows[sid]["status"] == "graded" and "no-return" in rows[sid]["flags"]
        for text in ((tmp_path / "r" / "feedback" / f"{sid}.md").read_text("utf-8"),
                     (tmp_path / "back" / f"{sid}.html").read_text("utf-8")):
            assert "没有发回批改后的工作簿" in text and why in text, sid
    assert "no-return" not in rows["m001"]["flags"]


# ------------------------------------------------- rosters in other encodings
BIG5 = "學號,姓名\nt01,陳大文\nt02,張學友\nt03,黃家駒\nt04,林憶蓮\n"
SHIFT_JIS = "学籍番号,氏名\nj01,山田太郎\nj02,佐藤はなこ\nj03,すずき一郎\n".replace(
    "学籍番号", "student_id").replace("氏名", "name")
GBK_RARE = "学号,姓名\ng01,王堃\ng02,李喆\ng03,张伟\ng04,刘洋\ng05,陈静\n"


@pytest.mark.parametrize("text, encoding, words", [
    (BIG5, "big5", "Big5"),
    (SHIFT_JIS, "shift_jis", "Shift-JIS"),
])
def test_a_roster_in_big5_or_shift_jis_gets_one_line(tmp_path, text, encoding, words):
    """Issue 39.9: GB18030 decodes almost any bytes, so a Taiwanese or Japanese Excel
    roster came out as other characters' names without a word."""
    path = tmp_path / "roster.csv"
    path.write_bytes(text.encode(encoding))
    done = run_cli("assign", "--roster", path, "-o", tmp_path / "out")
    assert done.returncode == 2 and words in done.stderr and "CSV UTF-8" in done.stderr, \
        done.stderr
    assert len(done.stderr.strip().splitlines()) == 1 and not (tmp_path / "out").exists()


def test_a_gbk_roster_with_rare_name_characters_is_read(tmp_path):
    from crankbook.assignment.roster import read_roster
    path = tmp_path / "roster.csv"
    path.write_bytes(GBK_RARE.encode("gbk"))
    rows, _ = read_roster(path)
    assert [r["name"] for r in rows] == ["王堃", "李喆", "张伟", "刘洋", "陈静"]


def test_a_formula_in_a_roster_name_cell_gets_one_line(tmp_path):
    book = openpyxl.Workbook()
    book.active.append(["班级名单"])
    book.active.append(["学号", "姓名"])
    book.active.append(["20240101", "李四"])
    book.active.append(["20240102", '=HYPERLINK("http://x","王五")'])
    book.save(tmp_path / "r.xlsx")
    done = run_cli("assign", "--roster", tmp_path / "r.xlsx", "-o", tmp_path / "out")
    assert done.returncode == 2, done.stderr
    assert "row 4: the name cell holds a formula" in done.stderr   # below a title row
    book.active.delete_rows(1)
    book.save(tmp_path / "r.xlsx")
    done = run_cli("assign", "--roster", tmp_path / "r.xlsx", "-o", tmp_path / "out")
    assert done.returncode == 2 and "row 3: the name cell holds a formula" in done.stderr, \
        done.stderr
    assert len(done.stderr.strip().splitlines()) == 1 and not (tmp_path / "out").exists()


def test_a_full_disk_while_writing_results_is_one_line_and_keeps_the_old(pack, tmp_path,
                                                                          capsys, monkeypatch):
    """Issue 39.5: the disk filling up while a run writes its folder was a traceback."""
    import errno
    import crankbook.assignment.grade as grade_module
    subs = tmp_path / "subs"
    fill(pack / "students" / "s001.xlsx", subs / "s001.xlsx", key_answers(pack, "s001"))
    code, _, err = run(capsys, "grade", pack, subs, "-o", tmp_path / "r")
    assert code == 0, err
    before = (tmp_path / "r" / "gradebook.csv").read_bytes()

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")
    monkeypatch.setattr(grade_module, "write_results", full)
    code, _, err = run(capsys, "grade", pack, subs, "-o", tmp_path / "r")
    _refused(code, err, "No space left on device", "as it was")
    assert (tmp_path / "r" / "gradebook.csv").read_bytes() == before
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]


# ------------------------------------------------- LMS rows matched by a unique key
MOODLE_HEAD = ('"Identifier","Full name","Email address","ID number","Status","Grade",'
               '"Maximum Grade","Grade can be changed","Last modified (submission)",'
               '"Last modified (grade)","Feedback comments"\n')


def _moodle_row(participant, name, email="", id_number=""):
    return (f'"Participant {participant}","{name}","{email}","{id_number}","Submitted",'
            f'"","100.00","Yes","","",""\n')


def test_two_students_of_one_name_never_get_each_others_moodle_grade(tmp_path, capsys):
    """Issue 40.1: the Moodle worksheet was matched by name, so of two 张伟 the one
    listed last took both rows — the other's grade and feedback included."""
    roster = tmp_path / "roster.csv"
    roster.write_text("学号,姓名\nz001,张伟\nz002,张伟\nz003,李娜\n", encoding="utf-8")
    code, _, err = run(capsys, "assign", "--roster", roster, "--seed", "5", "-o",
                       tmp_path / "class")
    assert code == 0, err
    klass = tmp_path / "class"
    subs = tmp_path / "subs"
    fill(klass / "students" / "z001.xlsx", subs / "z001.xlsx", key_answers(klass, "z001"))
    worksheet = tmp_path / "moodle.csv"
    worksheet.write_text(MOODLE_HEAD + _moodle_row(11, "张伟") + _moodle_row(12, "张伟") +
                         _moodle_row(13, "李娜"), encoding="utf-8")
    code, _, err = run(capsys, "grade", klass, subs, "-o", tmp_path / "r", "--lms", "moodle",
                       "--lms-template", worksheet)
    _refused(code, err, "row 2", "z001, z002", "email")
    assert not (tmp_path / "r").exists()                  # refused before any work
    # the LMS's own email (the id as its local part) or ID number tells them apart
    worksheet.write_text(MOODLE_HEAD + _moodle_row(11, "张伟", "z002@school.edu.cn") +
                         _moodle_row(12, "张伟", id_number="z001") + _moodle_row(13, "李娜"),
                         encoding="utf-8")
    code, _, err = run(capsys, "grade", klass, subs, "-o", tmp_path / "r", "--lms", "moodle",
                       "--lms-template", worksheet)
    assert code == 0, err
    with open(tmp_path / "r" / "moodle-grading-worksheet.csv", newline="",
              encoding="utf-8") as handle:
        rows = {r["Identifier"]: r for r in csv.DictReader(handle)}
    assert float(rows["Participant 12"]["Grade"]) == 100           # z001 handed in
    assert rows["Participant 11"]["Grade"] == ""                    # z002 did not
    assert "未提交" in rows["Participant 11"]["Feedback comments"]
    assert rows["Participant 13"]["Grade"] == ""


# ------------------------------------------------- every file a student hands in is seen
@pytest.mark.libreoffice
def test_every_file_a_student_hands_in_is_seen(tmp_path, capsys, soffice):
    """Issue 40.2: .ods, .xls, a zipped .xlsx, "作业.XLSX " (an upper-case suffix and a
    trailing space) were dropped without a word and their students marked 未提交; a
    .pdf alone made a student "missing"."""
    from crankbook.reading import recalc
    ids = ["f01", "f02", "f03", "f04", "f05", "f06"]
    roster = tmp_path / "roster.csv"
    roster.write_text("学号,姓名\n" + "".join(f"{i},学生{i}\n" for i in ids), encoding="utf-8")
    code, _, err = run(capsys, "assign", "--roster", roster, "--seed", "5", "-o",
                       tmp_path / "class")
    assert code == 0, err
    klass, subs, work = tmp_path / "class", tmp_path / "subs", tmp_path / "work"
    for sid in ids:
        fill(klass / "students" / f"{sid}.xlsx", work / f"{sid}.xlsx", key_answers(klass, sid))
    (subs / "f01").mkdir(parents=True)
    recalc.convert([work / "f01.xlsx"], work / "ods", target="ods")
    (work / "ods" / "f01.ods").rename(subs / "f01" / "作业.ods")
    recalc.convert([work / "f02.xlsx"], work / "xls", target="xls")
    (work / "xls" / "f02.xls").rename(subs / "f02.xls")
    with zipfile.ZipFile(subs / "f03.zip", "w") as archive:
        archive.write(work / "f03.xlsx", "作业/f03.xlsx")
        archive.writestr("__MACOSX/._f03.xlsx", b"resource fork")
    (subs / "f04").mkdir()
    (work / "f04.xlsx").rename(subs / "f04" / "作业.XLSX ")
    (subs / "f05_report.pdf").write_bytes(b"%PDF-1.4 a report, not the task")
    (subs / "notes.txt").write_text("nobody's")
    (subs / "Thumbs.db").write_bytes(b"\0")
    code, _, err = run(capsys, "grade", klass, subs, "-o", tmp_path / "r")
    assert code == 0, err
    rows = gradebook(tmp_path / "r")
    for sid in ("f01", "f02", "f03", "f04"):
        assert rows[sid]["status"] == "graded" and float(rows[sid]["score"]) == 100, \
            (sid, rows[sid])
    assert rows["f05"]["status"] == "unreadable" and ".pdf" in rows["f05"]["notes"]
    assert rows["f06"]["status"] == "missing"
    with open(tmp_path / "r" / "gradebook.csv", newline="", encoding="utf-8-sig") as handle:
        unmatched = [r["notes"] for r in csv.DictReader(handle) if not r["student_id"]]
    assert any("notes.txt" in n for n in unmatched), unmatched
    assert not any("Thumbs" in n or "MACOSX" in n for n in unmatched), unmatched


# ------------------------------------------------- ids stay text
def test_ids_stay_text_in_the_gradebook_and_rosters_say_when_they_were_not(tmp_path, capsys):
    """Issue 40.10: a 12-digit 学号 opened from gradebook.csv in Excel read 2.31E+11 and
    lost its leading zero; a roster with a merged title row above the header was
    refused; ids stored as numbers passed without a word."""
    book = openpyxl.Workbook()
    sheet = book.active
    sheet.append(["2023级机械1班 名单"])
    sheet.merge_cells("A1:C1")
    sheet.append(["学号", "姓名", "班级"])
    sheet.append(["023105010004", "王一", "机械1班"])
    sheet.append([23105010005, "王二", "机械1班"])           # typed as a number
    book.save(tmp_path / "roster.xlsx")
    code, _, err = run(capsys, "assign", "--roster", tmp_path / "roster.xlsx", "--seed", "5",
                       "-o", tmp_path / "class")
    assert code == 0, err
    assert "stored as numbers" in err and "row 4" in err and "11 and 12" in err, err
    klass = tmp_path / "class"
    subs = tmp_path / "subs"
    fill(klass / "students" / "023105010004.xlsx", subs / "023105010004.xlsx",
         key_answers(klass, "023105010004"))
    code, _, err = run(capsys, "grade", klass, subs, "-o", tmp_path / "r")
    assert code == 0, err
    text = (tmp_path / "r" / "gradebook.csv").read_text(encoding="utf-8-sig")
    # ="023105010004", unquoted: Excel's own way to keep an id text in a CSV
    assert '\n="023105010004",' in text and '\n="23105010005",' in text, text[:300]
    assert '\n"王' not in text                             # names stay quoted text
    sheet = openpyxl.load_workbook(tmp_path / "r" / "gradebook.xlsx").active
    ids = [c.value for c in sheet["A"]]
    assert "023105010004" in ids and "23105010005" in ids, ids
    # lms-import.csv is for the LMS: the id exactly as it knows it
    assert "\n\"023105010004\"," in (tmp_path / "r" / "lms-import.csv").read_text("utf-8-sig")
    # a second round reads the first one's ids back
    code, _, err = run(capsys, "grade", klass, subs, "-o", tmp_path / "r2", "--previous",
                       tmp_path / "r")
    assert code == 0, err


def test_a_ragged_roster_row_is_refused(tmp_path, capsys):
    roster = tmp_path / "roster.csv"
    roster.write_text("学号,姓名,班级\nr01,甲,1班\nr02,乙\n", encoding="utf-8")
    code, _, err = run(capsys, "assign", "--roster", roster, "-o", tmp_path / "class")
    _refused(code, err, "row 3", "2 cells but the header has 3 columns")


# ------------------------------------------------- a copied section
def test_a_copied_section_is_flagged_for_the_teacher(pack, tmp_path, capsys):
    """Issue 40.9: a student who did the mechanism alone but copied a classmate's
    valve train fitted their own key overall and went unflagged."""
    from crankbook.assignment import template
    assignment = template.for_preset("course-design")
    valve = next(s for s in assignment.sheets if s.key == "valve_train")
    subs = tmp_path / "subs"
    own, theirs = key_answers(pack, "s001"), key_answers(pack, "s002")
    copied = {k: (theirs[k] if k in valve.items else v) for k, v in own.items()}
    assert any(copied[k] != own[k] for k in valve.items)      # the valve trains differ
    fill(pack / "students" / "s001.xlsx", subs / "s001.xlsx", copied)
    fill(pack / "students" / "s002.xlsx", subs / "s002.xlsx", theirs)
    code, _, err = run(capsys, "grade", pack, subs, "-o", tmp_path / "r")
    assert code == 0, err
    rows = gradebook(tmp_path / "r")
    assert "copy-suspect" in rows["s001"]["flags"], rows["s001"]
    assert "copy-suspect" not in rows["s002"]["flags"]
    sheet = openpyxl.load_workbook(tmp_path / "r" / "integrity.xlsx").active
    text = " ".join(str(c.value) for row in sheet.iter_rows() for c in row if c.value)
    assert "某一部分的答案符合他人的参数" in text and valve.zh in text, text
    assert "creator" not in text and "sha256" not in text          # labels in Chinese
    feedback = (tmp_path / "r" / "feedback" / "s001.md").read_text(encoding="utf-8")
    assert "s002" not in feedback
    report = openpyxl.load_workbook(tmp_path / "r" / "class-report.xlsx")
    shown = " ".join(str(c.value) for ws in report.worksheets for row in ws.iter_rows()
                     for c in row if c.value)
    assert "抄" not in shown and "吻合" not in shown, shown          # no suspicion shown


# ------------------------------------------------- all Chinese for a Chinese class
def test_a_chinese_class_reads_chinese(pack, tmp_path, capsys):
    """Issue 40.11: cam laws, changed parameters, check on a key and the kept round
    were in English (or key names) in a zh class."""
    book = openpyxl.load_workbook(pack / "students" / "s001.xlsx")
    task = " ".join(str(c.value) for row in book.worksheets[0].iter_rows() for c in row
                    if c.value is not None)
    assert "运动规律：" in task and any(law in task for law in (
        "等速运动规律", "等加速等减速运动规律", "余弦加速度（简谐）运动规律",
        "正弦加速度（摆线）运动规律", "3-4-5 多项式运动规律"))
    code, out, err = run(capsys, "check", pack / "keys" / "s001.xlsx")
    assert code == 1 and "这是一份答案" in out, out + err
    subs1, subs2 = tmp_path / "round1", tmp_path / "round2"
    answers = key_answers(pack, "s001")
    fill(pack / "students" / "s001.xlsx", subs1 / "s001.xlsx", answers)
    worse = dict(answers, crank_radius=answers["crank_radius"] * 1.5)
    sheet, ref = next(iter(book.defined_names["p_stroke"].destinations))
    fill(pack / "students" / "s001.xlsx", subs2 / "s001.xlsx", worse,
         edit_parameters={"stroke": book[sheet][ref.replace("$", "")].value * 1.1})
    assert run(capsys, "grade", pack, subs1, "-o", tmp_path / "r1")[0] == 0
    code, _, err = run(capsys, "grade", pack, subs2, "-o", tmp_path / "r2", "--previous",
                       tmp_path / "r1", "--keep", "best")
    assert code == 0, err
    feedback = (tmp_path / "r2" / "feedback" / "s001.md").read_text(encoding="utf-8")
    assert "沿用第 1 轮的成绩 100 分" in feedback and "本轮得" in feedback, feedback[:600]
    code, _, err = run(capsys, "grade", pack, subs2, "-o", tmp_path / "r3")
    notes = gradebook(tmp_path / "r3")["s001"]["notes"]
    assert "参数被修改：" in notes and "（p_stroke）" in notes, notes


def test_the_exhaust_mounting_angle_earns_consequential_credit(pack, tmp_path, capsys):
    """Issue 40.8: the valve events are crank angles from TDC, which a student's own
    wrong r moves; a mounting angle right for the student's own mechanism earned 0."""
    from crankbook.assignment.grade import load_directory, manifest_values
    from crankbook.assignment.key import expected, key_results
    from crankbook.spec import params
    settings, assignment, roster = load_directory(pack)
    spec, _, meta = params.load_preset(settings["preset"])
    row = next(r for r in roster if r["student_id"] == "s001")
    key = key_results(assignment, spec, meta, params.validate(spec, manifest_values(spec, row)))
    answers = key_answers(pack, "s001")
    wrong_r = answers["crank_radius"] * 1.6
    own = expected(assignment, spec, key, overrides={"crank_radius": wrong_r,
                                                    "rod_length": answers["rod_length"]})
    mine = float(own["exhaust_cam_mounting_angle"]["value"][0])
    assert abs(mine - answers["exhaust_cam_mounting_angle"]) > 1.0     # visibly different
    fill(pack / "students" / "s001.xlsx", tmp_path / "subs" / "s001.xlsx",
         dict(answers, crank_radius=wrong_r, exhaust_cam_mounting_angle=mine))
    code, _, err = run(capsys, "grade", pack, tmp_path / "subs", "-o", tmp_path / "r")
    assert code == 0, err
    row = gradebook(tmp_path / "r")["s001"]
    column = next(c for c in row if c.endswith("(a_exhaust_cam_mounting_angle)"))
    points = assignment.item["exhaust_cam_mounting_angle"].points
    assert float(row[column]) == pytest.approx(0.8 * points), row[column]


@pytest.mark.parametrize("lang", ["zh", "en"])
def test_a_handed_in_answer_key_is_reported_as_a_leaked_key(tmp_path, capsys, lang):
    """Issue 40.9: a student who handed in an answer key was "unreadable" like any
    damaged file; the teacher hears of a leaked key (whose), the student does not."""
    roster = tmp_path / "roster.csv"
    roster.write_text("学号,姓名\nk001,甲\nk002,乙\n", encoding="utf-8")
    code, _, err = run(capsys, "assign", "--roster", roster, "--seed", "5", "--lang", lang,
                       "-o", tmp_path / "class")
    assert code == 0, err
    (tmp_path / "subs").mkdir()
    (tmp_path / "subs" / "k001.xlsx").write_bytes(
        (tmp_path / "class" / "keys" / "k002.xlsx").read_bytes())
    code, _, err = run(capsys, "grade", tmp_path / "class", tmp_path / "subs", "-o",
                       tmp_path / "r")
    assert code == 0, err
    row = gradebook(tmp_path / "r")["k001"]
    assert row["status"] == "unreadable" and "leaked-key" in row["flags"]
    words = {"zh": "答案可能外泄", "en": "the keys may have leaked"}[lang]
    assert words in row["notes"] and "k002" in row["notes"], row["notes"]
    sheet = openpyxl.load_workbook(tmp_path / "r" / "integrity.xlsx").active
    assert any(words in str(c.value) for r in sheet.iter_rows() for c in r)
    feedback = (tmp_path / "r" / "feedback" / "k001.md").read_text(encoding="utf-8")
    assert "k002" not in feedback and words not in feedback


def test_a_round_one_copy_flag_stays_in_round_two(pack, tmp_path, capsys):
    """Issue 40.9: a copier who resubmitted their own work in round 2 left no trace of
    round 1's suspicion in round 2's integrity report."""
    r1, r2 = tmp_path / "subs1", tmp_path / "subs2"
    fill(pack / "students" / "s002.xlsx", r1 / "s002.xlsx", key_answers(pack, "s002"))
    fill(pack / "students" / "s001.xlsx", r1 / "s001.xlsx", key_answers(pack, "s002"))
    fill(pack / "students" / "s001.xlsx", r2 / "s001.xlsx", key_answers(pack, "s001"))
    assert run(capsys, "grade", pack, r1, "-o", tmp_path / "g1")[0] == 0
    assert "copy-suspect" in gradebook(tmp_path / "g1")["s001"]["flags"]
    code, _, err = run(capsys, "grade", pack, r2, "-o", tmp_path / "g2", "--previous",
                       tmp_path / "g1")
    assert code == 0, err
    row = gradebook(tmp_path / "g2")["s001"]
    assert float(row["score"]) == 100 and "copy-suspect" in row["flags"]
    assert "第 1 轮曾被怀疑抄袭" in row["notes"]
    sheet = openpyxl.load_workbook(tmp_path / "g2" / "integrity.xlsx").active
    text = " ".join(str(c.value) for r in sheet.iter_rows() for c in r if c.value)
    assert "第 1 轮发现" in text and "s002" in text
    feedback = (tmp_path / "g2" / "feedback" / "s001.md").read_text(encoding="utf-8")
    assert "s002" not in feedback and "抄" not in feedback


def test_a_section_shared_by_several_classmates_is_one_suspicion():
    """A gear train drawn from a few choices is the same for many: a student whose
    meshes fit that shared train was flagged against every classmate who has it (88
    pairs in a 30-student trial); it is one suspicion, against the best fit, saying
    how many share the data."""
    from types import SimpleNamespace

    import numpy as np

    from crankbook.assignment import integrity
    from crankbook.assignment.grade import Grade
    from crankbook.assignment.submissions import Submission
    from crankbook.assignment.template import AnswerSheet, Item
    items = [Item(key=k, points=1, tolerance=0.01, zh=k, en=k, unit="mm")
             for k in ("a", "b", "c", "m1", "m2", "m3")]
    assignment = SimpleNamespace(items=items, positions=None, sheets=[
        AnswerSheet(key="mech", zh="机构", en="mech", rows="scalar", items=("a", "b", "c")),
        AnswerSheet(key="mesh", zh="啮合", en="mesh", rows="scalar", items=("m1", "m2", "m3"))])
    ids = ["x1", "x2", "x3", "x4", "x5"]
    own = {sid: {"a": 10.0 + n, "b": 20.0 + n, "c": 30.0 + n} for n, sid in enumerate(ids)}
    shared = {"m1": 1.0, "m2": 2.0, "m3": 3.0}          # x2…x5 share one gear train
    keys = {sid: {k: {"value": np.array([v])} for k, v in
                  {**own[sid], **(shared if sid != "x1" else
                                  {"m1": 7.0, "m2": 8.0, "m3": 9.0})}.items()}
            for sid in ids}
    answers = {sid: {k: keys[sid][k]["value"].copy() for k in keys[sid]} for sid in ids}
    answers["x1"].update({k: np.array([v]) for k, v in shared.items()})   # x1 copied them
    grades = {sid: Grade(student_id=sid, name=sid, status="graded") for sid in ids}
    chosen = {sid: Submission(path=Path(f"{sid}.xlsx"), relative=f"{sid}.xlsx",
                              digest=sid, answers={k: [float(v[0])] for k, v in
                                                   answers[sid].items()}) for sid in ids}
    found = integrity.find(grades, chosen, answers, keys, assignment)
    mine = [s for s in found if s.who == "x1"]
    assert len(mine) == 1 and mine[0].kinds == ["fits_other_section"], found
    assert mine[0].evidence["shared_by"] == 4 and mine[0].evidence["section"] == "mesh"
    assert not [s for s in found if s.who != "x1"]
