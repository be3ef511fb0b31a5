"""What the README and docs/ state is what crankbook does: the numbers they print,
the names they list and the commands they show."""
import math
from pathlib import Path

import crankbook

ROOT = Path(__file__).resolve().parent.parent


def test_the_series_against_exact_table_is_what_the_presets_give():
    text = (ROOT / "docs" / "engineer.md").read_text(encoding="utf-8")
    series = crankbook.compute("thesis").scalars
    exact = crankbook.compute("thesis", exact_kinematics=1).scalars
    rows = {
        "peak acceleration, at TDC (`q_piston_acceleration_max`)":
            ("piston_acceleration_max", "m/s²", "{:.0f}"),
        "largest deceleration (`q_piston_acceleration_min`: near α = 139° and 221°, not "
        "at BDC, since λ > 1/4)": ("piston_acceleration_min", "m/s²", "{:.0f}"),
        "peak side force (`q_side_force_max`)": ("side_force_max", "N", "{:.0f}"),
        "mean torque (`q_mean_torque`)": ("mean_torque", "N·m", "{:.2f}"),
    }
    # the row says where: for λ > 1/4 the series' deceleration peaks at cos α = −1/(4λ)
    angle = series["piston_acceleration_min_angle"] % 360
    lam = series["crank_rod_ratio"]
    assert round(min(angle, 360 - angle)) == round(math.degrees(math.acos(-1 / (4 * lam)))) \
        == 139, angle
    for words, (key, unit, shown) in rows.items():
        a, b = series[key], exact[key]
        cells = f"| {words} | {shown.format(a).replace('-', '−')} {unit} | " \
                f"{shown.format(b).replace('-', '−')} {unit} |"
        assert cells in text, cells
        change = (a - b) / abs(b) * 100
        if abs(change) > 0.005:
            assert f"{cells} {change:+.2f} %".replace("-", "−") in text, (words, change)


def test_the_stroke_study_numbers_in_the_readme():
    text = (ROOT / "docs" / "engineer.md").read_text(encoding="utf-8")
    s = crankbook.compute("thesis").scalars
    for key in ("peak_inertia_force", "peak_side_force", "indicated_power"):
        assert f"{s[f'stroke_study_{key}_change']:.2f} %".replace("-", "−") in text, key


# ------------------------------------------------------------------ names and commands
import re  # noqa: E402
import shutil  # noqa: E402

import pytest  # noqa: E402

from crankbook.support import resources  # noqa: E402

DOCS = [ROOT / "README.md"] + sorted((ROOT / "docs").glob("*.md"))
NAME = re.compile(r"(?<![\w/.])([pqa])_([a-z][a-z0-9_]*[a-z0-9])")


def _defined_names():
    """Every p_/q_ name some workbook defines; an a_ name answers a q_ name."""
    from crankbook.spec.loader import load, template_names
    from crankbook.assignment.student_book import GIVEN_KEYS
    names = {"q_inputs_valid", "q_input_status"} | {f"p_given_{k}" for k in GIVEN_KEYS}
    for template in template_names():
        spec = load(template)
        names |= {f"p_{p.key}" for p in spec.parameters}
        names |= {f"q_{q.key}" for q in spec.quantities()}
        names |= {f"q_check_{r.key}" for r in spec.rules}
        names |= {f"p_{c}" for c in spec.table_column}      # input tables (a pasted trace)
    return names | {"a_" + n[2:] for n in names if n.startswith("q_")}


def _listed_names(text):
    """The p_/q_/a_ names a page lists: in `code` (a symbol such as p_in in a sentence
    is physics, not a name); a pattern (q_<key>_max, q_pos_*) and the template
    language's generic p_key are not names."""
    for span in re.findall(r"`([^`\n]+)`", text):
        for match in NAME.finditer(span):
            rest = span[match.end():match.end() + 2]
            if rest[:1] in ("<", "*") or rest in ("_*", "_<") or match.group(2) == "key" \
                    or span[:match.start()].endswith("{"):
                continue
            yield match.group(0)


def test_every_name_the_docs_list_exists():
    """A p_, q_ or a_ name in the README or a guide is one some workbook defines."""
    defined = _defined_names()
    unknown = sorted({f"{path.relative_to(ROOT)}: {name}" for path in DOCS
                      for name in _listed_names(path.read_text(encoding="utf-8"))
                      if name not in defined})
    assert not unknown, "\n".join(unknown)


def test_the_name_check_can_fail():
    assert "q_torque" in _defined_names() and "q_torqe" not in _defined_names()
    assert list(_listed_names("the `q_torqe` column, `q_pos_*`, p_in")) == ["q_torqe"]


def _commands(path):
    """The crankbook commands of a page's ``sh`` blocks, in order (continued lines
    joined, comments dropped); ``text`` blocks are synopses and are not run."""
    out, block, pending = [], False, ""
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("```"):
            block = line.strip() == "```sh"
            continue
        if not block:
            continue
        line = pending + line.split("  #")[0].rstrip()
        if line.endswith("\\"):
            pending = line[:-1] + " "
            continue
        pending = ""
        if line.strip().startswith("crankbook "):
            out.append(line.strip().split()[1:])
    return out


def _roster(path):
    import openpyxl
    book = openpyxl.Workbook()
    sheet = book.active
    for row in (["学号", "姓名", "组号"], ["2026001", "张三", 10], ["2026002", "李四", 11]):
        sheet.append(row)
    book.save(path)


def _students(tmp):
    """The newest class pack's students' files (what they hand back)."""
    packs = sorted(tmp.glob("*/students"), key=lambda p: p.stat().st_mtime)
    return sorted(packs[-1].glob("*.xlsx"))


def _handed_in(tmp, target):
    target.mkdir()
    for file in _students(tmp):
        shutil.copy(file, target / file.name)


# the files the pages' commands name, made as a user would have them
FIXTURES = {
    "measured.csv": lambda tmp, path: path.write_text(
        "angle,p\n" + "\n".join(f"{a},{0.1 + 4 * 2.718 ** (-((a - 372) / 30) ** 2):.6f}"
                                for a in range(0, 721, 2)) + "\n"),
    "名单.xlsx": lambda tmp, path: _roster(path),
    "returned/": _handed_in, "resubmitted/": _handed_in, "week3/": _handed_in,
    "我的作业.xlsx": lambda tmp, path: shutil.copy(_students(tmp)[0], path),
    "returned.xlsx": lambda tmp, path: crankbook.compute("thesis", step=3.0).to_excel(path),
    "overrides.csv": lambda tmp, path: path.write_text(
        "student,item,action,points,reason,who\n"
        "2026001,a_crank_radius,accept,,agreed in class,teacher\n", encoding="utf-8"),
    "我的分组.csv": lambda tmp, path: path.write_text(
        "组号,stroke,offset\n10,300,50\n11,320,45\n", encoding="utf-8"),
    "my-course.toml": lambda tmp, path: path.write_text(
        resources.read_text("assignments", "course-design.toml"), encoding="utf-8"),
}
DOCUMENTED_EXIT = {"check": 1}      # check: 1 when something would be lost (blank answers)


@pytest.mark.libreoffice
@pytest.mark.parametrize("page", [p.name for p in DOCS], ids=str)
def test_every_command_shown_runs(page, tmp_path, soffice):
    """Each page's commands, in order, in a scratch directory holding the files they
    name: every one ends with 0 (or its documented code) and no traceback."""
    from tests.conftest import run_cli
    path = next(p for p in DOCS if p.name == page)
    for args in _commands(path):
        for name, make in FIXTURES.items():
            target = tmp_path / name.rstrip("/")
            if any(a.rstrip("/") == name.rstrip("/") for a in args) and not target.exists():
                make(tmp_path, target)
        done = run_cli(*args, cwd=tmp_path, timeout=600)
        allowed = {0, DOCUMENTED_EXIT.get(args[0], 0)}
        assert done.returncode in allowed and "Traceback" not in done.stderr, \
            f"{page}: crankbook {' '.join(args)} → {done.returncode}\n{done.stderr[-2000:]}"


def test_the_pages_have_commands_and_the_readme_stays_short():
    assert len((ROOT / "README.md").read_text(encoding="utf-8").splitlines()) <= 250
    counted = {p.name: len(_commands(p)) for p in DOCS}
    assert counted["README.md"] >= 10 and counted["teacher.md"] >= 10, counted
    for link in re.findall(r"\]\((docs/[\w.-]+)\)", (ROOT / "README.md").read_text(
            encoding="utf-8")):
        assert (ROOT / link).is_file(), link


PYTHON_WRITES = {"README.md": "output/i6.xlsx", "engineer.md": "output/thesis-3000.xlsx"}


@pytest.mark.libreoffice
@pytest.mark.parametrize("page", sorted(PYTHON_WRITES))
def test_every_python_example_runs_as_printed(page, tmp_path, soffice):
    """The pages' ``python`` blocks, run as a user pastes them, in a fresh directory."""
    import subprocess
    import sys
    text = next(p for p in DOCS if p.name == page).read_text(encoding="utf-8")
    blocks = re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)
    assert blocks, page
    for code in blocks:
        done = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True,
                              text=True, timeout=600)
        assert done.returncode == 0, done.stderr[-2000:]
    assert (tmp_path / PYTHON_WRITES[page]).is_file()
    others = [p.name for p in DOCS if "```python" in p.read_text(encoding="utf-8")]
    assert sorted(others) == sorted(PYTHON_WRITES)          # no page's example left out
