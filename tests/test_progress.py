"""Progress where a user waits: on a terminal (what, n of N, elapsed), never in a pipe
or with --quiet; the API's ``progress=`` flag."""
import os
import pty
import select
import subprocess
import sys

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
