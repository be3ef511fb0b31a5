"""Hostile and damaged input through grade, audit, build --pressure and assign.

A seeded corpus (tests/mutations.py) made from the project's own outputs.  Each run
goes through the command line's own entry point, so an exception that escapes is a
failure here; the assertions are the documented outcomes: exit code 0/1/2, one
line on exit 2, every valid file in a mixed batch graded exactly as in a clean run,
nothing written outside the output, nothing half-written.
"""
import hashlib
import os
import shutil
from pathlib import Path

import numpy as np
import pytest
import xlsxwriter

from crankbook import cli
from tests.mutations import corpus
from tests.test_assignment import fill, key_answers, read_gradebook, write_roster

VALID = ["s01", "s02", "s03"]
TARGET = "s04"                    # the student every damaged file claims to be


def run(capsys, *args):
    """crankbook ARGS in this process: (exit code, stderr)."""
    capsys.readouterr()
    code = cli.main([str(a) for a in args])
    return code, capsys.readouterr().err


def peak_memory(*args, timeout=900):
    """(exit code, stderr, peak resident MB of crankbook ARGS and its children)."""
    import json
    import subprocess
    import sys
    probe = ("import json, resource, subprocess, sys; "
             "done = subprocess.run([sys.executable, '-m', 'crankbook', *sys.argv[1:]], "
             "capture_output=True, text=True); "
             "print(json.dumps([done.returncode, done.stderr, "
             "resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024]))")
    done = subprocess.run([sys.executable, "-c", probe, *map(str, args)], capture_output=True,
                          text=True, timeout=timeout)
    return tuple(json.loads(done.stdout))


def tree(path):
    """{relative path: sha256} of every file under ``path``."""
    path = Path(path)
    return {str(p.relative_to(path)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(path.rglob("*")) if p.is_file()}


def leftovers(path):
    return [p.name for p in Path(path).rglob("*") if ".crankbook-" in p.name]


@pytest.fixture(scope="module")
def pack(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("fuzz-pack")
    write_roster(tmp / "roster.csv", VALID + [TARGET])
    assert cli.main(["assign", "--roster", str(tmp / "roster.csv"), "--seed", "3",
                     "-o", str(tmp / "class")]) == 0
    return tmp / "class"


def test_damaged_submissions_never_cost_the_valid_ones(pack, tmp_path, capsys, soffice):
    clean, mixed = tmp_path / "clean", tmp_path / "mixed"
    for sid in VALID:
        fill(pack / "students" / f"{sid}.xlsx", clean / f"{sid}.xlsx",
             key_answers(pack, sid))
    # s03 typed formulas and saved without values: LibreOffice recalculates it
    fill(pack / "students" / "s03.xlsx", clean / "s03.xlsx", key_answers(pack, "s03"),
         formulas=True)
    shutil.copytree(clean, mixed)
    damaged_source = tmp_path / "target.xlsx"
    fill(pack / "students" / f"{TARGET}.xlsx", damaged_source, key_answers(pack, TARGET))
    for number, (kind, data) in enumerate(corpus(damaged_source.read_bytes(), 160, seed=11)):
        folder = mixed / "lms" / f"{TARGET}_{number:03d}"
        folder.mkdir(parents=True)
        (folder / f"{kind}.xlsx").write_bytes(data)
    # one formula file LibreOffice refuses, in the same recalculation batch as s03
    refused = mixed / f"{TARGET}_refused.xlsx"
    fill(pack / "students" / f"{TARGET}.xlsx", refused, key_answers(pack, TARGET),
         formulas=True)
    refused.write_bytes(refused.read_bytes() + os.urandom(4096))
    # a file name that is not UTF-8 (a Windows zip unpacked on Linux)
    os.rename(mixed / "s02.xlsx", os.path.join(os.fsencode(mixed),
                                               "s02_\xd7\xf7\xd2\xb5".encode("latin-1") +
                                               b".xlsx"))
    before = tree(mixed)

    code, err = run(capsys, "grade", pack, clean, "-o", tmp_path / "clean-results",
                    "--return", tmp_path / "clean-back")
    assert code == 0, err
    # the mixed batch as a user runs it: its own process, a time limit (no hang) and
    # the peak memory of it and its LibreOffice measured
    code, err, peak = peak_memory("grade", pack, mixed, "-o", tmp_path / "mixed-results",
                                  "--return", tmp_path / "mixed-back")
    assert code == 0, err
    assert "Traceback" not in err
    assert peak < 1500, f"{peak:.0f} MB"
    assert tree(mixed) == before, "grade changed the submissions"

    clean_book, _ = read_gradebook(tmp_path / "clean-results")
    mixed_book, rows = read_gradebook(tmp_path / "mixed-results")
    for sid in VALID:
        assert clean_book[sid]["status"] == "graded"
        assert float(clean_book[sid]["score"]) == float(clean_book[sid]["max_score"])
        fields = ("status", "score", *[k for k in clean_book[sid] if k.endswith(")")])
        assert {k: mixed_book[sid][k] for k in fields} == \
               {k: clean_book[sid][k] for k in fields}, sid
        # the valid students' returns are the same bytes whatever else was handed in
        assert tree(tmp_path / "mixed-back")[f"{sid}.xlsx"] == \
            tree(tmp_path / "clean-back")[f"{sid}.xlsx"], sid
    assert mixed_book[TARGET]["status"] in ("graded", "unreadable")
    # the return of whatever file was graded for the target carries none of its parts
    returned = tmp_path / "mixed-back" / f"{TARGET}.xlsx"
    if mixed_book[TARGET]["status"] == "graded":
        assert returned.is_file() or "no-return" in mixed_book[TARGET]["flags"]
    if returned.is_file():
        import zipfile
        with zipfile.ZipFile(returned) as archive:
            names = archive.namelist()
            text = b"".join(archive.read(n) for n in names)
        assert not any("externalLink" in n for n in names)
        assert b"<hyperlink" not in text and b"veryHidden" not in text
    assert "multiple-submissions" in mixed_book[TARGET]["flags"]
    assert not leftovers(tmp_path)


@pytest.fixture(scope="module")
def engine_book(tmp_path_factory):
    path = tmp_path_factory.mktemp("fuzz-engine") / "engine.xlsx"
    assert cli.main(["build", "--step", "12", "-o", str(path)]) == 0      # small: 30 audits
    return path


def test_damaged_workbooks_get_one_line_from_audit(engine_book, tmp_path, capsys):
    outcomes = {}
    # two of each of the 15 kinds of damage (tests/mutations.py)
    for number, (kind, data) in enumerate(corpus(engine_book.read_bytes(), 30, seed=12)):
        path = tmp_path / f"{number:03d}_{kind}.xlsx"
        path.write_bytes(data)
        code, err = run(capsys, "audit", path)
        assert code in (0, 1, 2), (path.name, err)
        if code == 2:
            lines = [line for line in err.splitlines() if line.startswith("crankbook: error")]
            assert len(lines) == 1 and "Traceback" not in err, (path.name, err)
        outcomes.setdefault(kind, set()).add(code)
    # what must never pass as an untouched workbook
    for kind in ("entity_declaration", "macro_part", "not_a_workbook", "truncate"):
        assert outcomes[kind] == {2}, (kind, outcomes[kind])
    assert outcomes["shrink_name"] == {1}, "a shortened result name passed as agreeing"
    assert not leftovers(tmp_path)


def _trace_xlsx(path):
    book = xlsxwriter.Workbook(path)
    sheet = book.add_worksheet()
    sheet.write_row(0, 0, ["crank angle", "pressure"])
    for row, angle in enumerate(np.arange(0.0, 721.0, 5.0), start=1):
        sheet.write_row(row, 0, [angle, 0.1 + 4.0 * np.exp(-((angle - 372.0) / 30.0) ** 2)])
    book.close()


CSV_CASES = [
    b"", b"\xff\xfe\x00\x00", b"angle,p\n0,0.1\n", "０,0.1\n720,0.1\n".encode(),
    b"0,0.1\n360,1_0\n720,0.1\n", b"0;0,1\n720;0,1\n", b"a,b,c\n1,2,3\n",
    b"0,0.1\n" * 300000, b"0,nan\n720,0.1\n", b"0,1e400\n720,0.1\n",
    "0,0.1\n٣٦٠,2\n720,0.1\n".encode(),
]


def test_damaged_pressure_traces_build_or_get_one_line(tmp_path, capsys):
    good = tmp_path / "trace.xlsx"
    _trace_xlsx(good)
    files = [good]
    for number, (kind, data) in enumerate(corpus(good.read_bytes(), 40, seed=13)):
        files.append(tmp_path / f"{number:03d}_{kind}.xlsx")
        files[-1].write_bytes(data)
    for number, data in enumerate(CSV_CASES):
        files.append(tmp_path / f"case{number:02d}.csv")
        files[-1].write_bytes(data)
    out = tmp_path / "out" / "engine.xlsx"
    codes = []
    for path in files:
        out.unlink(missing_ok=True)
        code, err = run(capsys, "build", "--step", "30", "--pressure", path, "-o", out)
        assert code in (0, 2), (path.name, err)
        assert out.exists() == (code == 0), path.name
        if code == 2:
            assert err.count("\n") == 1 and err.startswith("crankbook: error: pressure file"), \
                (path.name, err)
        codes.append(code)
    assert codes[0] == 0 and all(c == 2 for c in codes[-len(CSV_CASES):])
    assert not leftovers(tmp_path)


ROSTERS = [
    b"", b"\x00\x01\x02", "学号,姓名\n1,张\n1,李\n".encode(), b"student_id,name\n,Ada\n",
    b"student_id,name\n../x,Ada\n", b"student_id,name\n=cmd,Ada\n", b"student_id,name\n-rf,A\n",
    b"student_id,name\na/b,Ada\n", b"student_id,name\nx\x01,Ada\n", b"name\nAda\n",
    b"student_id,name\ns1,Ada,extra\n", "学号,姓名\n".encode("utf-16"),
    b"PK\x03\x04junk",
]


@pytest.mark.parametrize("number", range(len(ROSTERS)))
def test_bad_rosters_get_one_line_and_no_directory(tmp_path, capsys, number):
    roster = tmp_path / ("roster.xlsx" if ROSTERS[number].startswith(b"PK") else "roster.csv")
    roster.write_bytes(ROSTERS[number])
    code, err = run(capsys, "assign", "--roster", roster, "-o", tmp_path / "class")
    assert code == 2 and err.startswith("crankbook: error: roster") and err.count("\n") == 1, err
    assert sorted(p.name for p in tmp_path.iterdir()) == [roster.name]
