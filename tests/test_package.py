"""What a non-editable install gets: one top-level name, every data file, and a tool
that works from any directory.  The wheel is imported straight from its zip, so a
file found through ``__file__`` instead of importlib.resources would fail here.
(.ci/run also installs the wheel into a clean venv and runs every README command.)"""
import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

import crankbook
from crankbook.support import resources

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def wheel(tmp_path_factory):
    out = tmp_path_factory.mktemp("wheel")
    done = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w",
                           str(out), str(ROOT)], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    return next(out.glob("crankbook-*.whl"))


def test_the_wheel_installs_one_name_and_every_data_file(wheel):
    with zipfile.ZipFile(wheel) as archive:
        names = archive.namelist()
        info = next(n for n in names if n.endswith(".dist-info/top_level.txt"))
        assert archive.read(info).decode().split() == ["crankbook"]
        tops = {n.split("/")[0] for n in names if ".dist-info" not in n}
        assert tops == {"crankbook"}
        assert any(n.endswith(".dist-info/licenses/LICENSE") for n in names)
        metadata = archive.read(next(n for n in names if n.endswith("METADATA"))).decode()
        assert f"Version: {crankbook.__version__}" in metadata
    shipped = {n[len("crankbook/templates/"):] for n in names
               if n.startswith("crankbook/templates/") and n.endswith((".toml", ".txt", ".md"))}
    in_source = {str(p.relative_to(ROOT / "templates")) for p in (ROOT / "templates").rglob("*")
                 if p.suffix in (".toml", ".txt", ".md")}
    assert in_source and in_source <= shipped, in_source - shipped


def _run_from_wheel(wheel, cwd, *args):
    env = {**os.environ, "PYTHONPATH": str(wheel)}
    return subprocess.run([sys.executable, *args], capture_output=True, text=True, cwd=cwd,
                          env=env, timeout=600)


def test_the_tool_works_from_the_wheel_in_another_directory(wheel, tmp_path):
    done = _run_from_wheel(wheel, tmp_path, "-c", (
        "import crankbook; assert crankbook.__file__.startswith(%r), crankbook.__file__;"
        "r = crankbook.compute('course-design', group=3); print(r.scalars['crank_radius'])")
        % str(wheel))
    assert done.returncode == 0, done.stderr
    for args in (["presets"], ["parameters", "--preset", "course-design"],
                 ["build", "--preset", "offset-optimization", "-o", "o.xlsx"],
                 ["build", "--step", "10"], ["audit", "offset-piston", "-o", "a.xlsx"]):
        done = _run_from_wheel(wheel, tmp_path, "-m", "crankbook", *args)
        assert done.returncode == 0, (args, done.stderr)
        assert "Traceback" not in done.stderr
    assert (tmp_path / "output" / "thesis.xlsx").is_file()
    assert "course-design" in _run_from_wheel(wheel, tmp_path, "-m", "crankbook",
                                              "presets").stdout


def test_names_are_names_never_paths():
    assert resources.is_safe_name("course-design")
    for bad in ("../presets/thesis", "/etc/passwd", "thesis.toml", "a b", "", "x" * 80):
        assert not resources.is_safe_name(bad)


def _programs_run(path):
    """Names of the external programs a Python file runs: the first word of a literal
    command given to subprocess (or to the tests' run_program)."""
    import ast
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if not isinstance(node, ast.Call) or not node.args:
            continue
        name = getattr(node.func, "attr", getattr(node.func, "id", ""))
        first = node.args[0]
        if name in ("run", "Popen", "check_output", "call", "check_call") and \
                isinstance(first, ast.List) and first.elts and \
                isinstance(first.elts[0], ast.Constant) and isinstance(first.elts[0].value, str):
            found.add(first.elts[0].value)
        elif name == "run_program" and isinstance(first, ast.Constant):
            found.add(first.value)
    return found


def test_dev_installs_every_program_the_code_and_tests_run():
    """A fresh machine has none of them: ./dev test installs each program the package
    or the tests run (its PROGRAMS list), so a test never meets a missing one (the
    rendering tests once ran pdftotext, which only the machine they were written on
    had)."""
    from crankbook.reading import recalc
    from tests.conftest import dev_programs
    ALWAYS_THERE = {"sleep"}                          # coreutils: every Debian machine
    run = {Path(recalc.SOFFICE[0]).name, Path(recalc.SSCONVERT[0]).name}
    for folder in ("workbook", "calc", "tests", "bench"):
        for path in (ROOT / folder).rglob("*.py"):
            run |= _programs_run(path)
    assert "pdftotext" in run and "soffice" in run          # the scan sees what it should
    installed = dev_programs()
    assert not run - ALWAYS_THERE - set(installed), run - ALWAYS_THERE - set(installed)
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    assert "./dev test" in ci                             # CI installs through ./dev
