"""Progress where a user waits: on a terminal (what, n of N, elapsed), never in a pipe
or with --quiet; the API's ``progress=`` flag."""
import os
import pty
import select
import subprocess
import sys
import time

import crankbook
from tests.conftest import ROOT, run_cli


def _roster(path, count=4):
    path.write_text("student_id,name\n" + "".join(f"p{i:02d},S{i}\n" for i in range(count)),
                    encoding="utf-8")
    return path


def _on_a_terminal(*args, cwd):
    """stderr of ``python -m crankbook args`` written to a pseudo-terminal."""
    main, child = pty.openpty()
    process = subprocess.Popen([sys.executable, "-m", "crankbook", *map(str, args)],
                               cwd=cwd, stdout=subprocess.DEVNULL, stderr=child,
                               stdin=subprocess.DEVNULL)
    os.close(child)
    seen = b""
    while True:
        ready, _, _ = select.select([main], [], [], 120)
        if not ready:
            break
        try:
            chunk = os.read(main, 4096)
        except OSError:               # the child closed the terminal
            break
        if not chunk:
            break
        seen += chunk
    os.close(main)
    assert process.wait(timeout=120) == 0, seen.decode(errors="replace")
    return seen.decode("utf-8", errors="replace")


def test_assign_shows_n_of_n_on_a_terminal(tmp_path):
    roster = _roster(tmp_path / "roster.csv")
    seen = _on_a_terminal("assign", "--preset", "course-design", "--roster", roster,
                          "--lang", "en", "-o", tmp_path / "class", cwd=ROOT)
    assert "/4 [" in seen and "\r" in seen, seen         # n of N, redrawn in place
    assert "00:0" in seen                                 # elapsed


def test_quiet_and_pipes_stay_silent(tmp_path):
    roster = _roster(tmp_path / "roster.csv")
    seen = _on_a_terminal("assign", "--preset", "course-design", "--roster", roster,
                          "--lang", "en", "-o", tmp_path / "quiet", "--quiet", cwd=ROOT)
    assert "/4" not in seen and "\r" not in seen.replace("\r\n", ""), seen
    piped = run_cli("assign", "--preset", "course-design", "--roster", roster, "--lang", "en",
                    "-o", tmp_path / "piped")
    assert piped.returncode == 0 and "/4" not in piped.stderr and "\r" not in piped.stderr


def test_the_api_takes_a_progress_flag(tmp_path, capsys):
    paths = [crankbook.compute("thesis", step=30.0, speed=speed).to_excel(
        tmp_path / f"t{speed}.xlsx") for speed in (2000, 3000)]
    capsys.readouterr()
    crankbook.read(paths, progress=False)
    assert capsys.readouterr().err == ""
    results = crankbook.read(paths, progress=True)
    assert "read:" in capsys.readouterr().err
    assert [r["speed"] for r in results] == [2000, 3000]


def test_giving_up_while_the_engine_runs_ends_the_engine(tmp_path, monkeypatch):
    """verify reads the workbook while the engine recalculates it in another thread.
    When the reading fails (or Ctrl-C comes) the engine, which runs in a session of
    its own out of the terminal's reach, is killed at once rather than waited for:
    here a one-minute stand-in for it ends by SIGKILL, not by itself."""
    from crankbook.errors import RecalculationError, WorkbookReadError
    from crankbook.reading import recalc, verification
    path = tmp_path / "offset.xlsx"
    crankbook.compute("offset-optimization").to_excel(path)
    ended = {}

    def engine_stand_in(paths, outdir, engine="libreoffice", cancel=None, **_):
        try:
            ended["how"] = recalc._run(["sleep", "60"], 120, str(tmp_path), cancel)[0]
        except RecalculationError:
            ended["how"] = "not started"
        return []

    def no_q_names(*args):
        time.sleep(0.5)           # the engine has started by now, as with a real workbook
        return {}

    monkeypatch.setattr(recalc, "require_engine", lambda engine: "sleep")
    monkeypatch.setattr(recalc, "computed_values", engine_stand_in)
    monkeypatch.setattr(verification, "read_results", no_q_names)
    try:
        verification.verify_workbooks([path], progress=False)
    except WorkbookReadError as error:
        assert "has no q_ names" in str(error)
    else:
        raise AssertionError("a workbook without q_ names was verified")
    assert ended["how"] in (-9, "not started"), ended
