"""`crankbook grade`: score returned workbooks against the assigned parameters.

Expected values come from the manifest's parameters through calc (never from cells
a student could edit).  Per item and cell the rubric gives full credit within the
tolerance, partial credit for a unit slip, a sign slip or a consequential error
(an answer right for the student's own wrong crank radius and rod length).
"""
import csv
import hashlib
import json
import math
import re
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from openpyxl.utils.cell import range_boundaries

from crankbook import evaluate, params, recalc
from crankbook.assignment import template as templates
from crankbook.assignment.assign import MANIFEST, RUBRIC, SETTINGS, expected_grid
from crankbook.assignment.results import write_results
from crankbook.safe_read import Unreadable, open_untrusted
from crankbook.errors import AssignmentDirError, RecalculationError

UNIT_FACTORS = {1e3: "×1000", 1e-3: "÷1000", 60 / (2 * math.pi): "rad/s ↔ rpm",
                2 * math.pi / 60: "rpm ↔ rad/s", 180 / math.pi: "rad ↔ °", math.pi / 180: "° ↔ rad"}


@dataclass
class Submission:
    path: Path
    relative: str
    student_id: str | None = None         # the roster student it belongs to
    inside_id: str | None = None          # s_student_id in the file
    answers: dict = field(default_factory=dict)
    parameters: dict = field(default_factory=dict)
    problem: str | None = None            # why it is unreadable
    needs_recalc: bool = False
    digest: str = ""


@dataclass
class CellResult:
    value: object
    expected: float
    fraction: float
    reason: str


@dataclass
class Grade:
    student_id: str
    name: str
    status: str = "missing"
    items: dict = field(default_factory=dict)       # item key -> (points, [CellResult])
    flags: list = field(default_factory=list)     # tokens: wrong-student, duplicate, …
    details: list = field(default_factory=list)   # what each flag is about, in words
    files: list = field(default_factory=list)
    problem: str = ""

    @property
    def score(self):
        return sum(points for points, _ in self.items.values())


def load_directory(directory):
    directory = Path(directory)
    if not (directory / MANIFEST).is_file() or not (directory / SETTINGS).is_file():
        raise AssignmentDirError(f"{directory}: not a directory written by 'crankbook assign' "
                                 f"(no {MANIFEST} or {SETTINGS})")
    settings = json.loads((directory / SETTINGS).read_text(encoding="utf-8"))
    assignment = templates.load(settings["assignment"], directory / RUBRIC)
    with open(directory / MANIFEST, newline="", encoding="utf-8") as handle:
        roster = list(csv.DictReader(handle))
    return settings, assignment, roster


def _number(value):
    if isinstance(value, bool) or value is None:
        return None
    if isinstance(value, (int, float)):
        return float(value) if math.isfinite(value) else None
    try:
        return float(str(value).strip().replace(",", "."))
    except ValueError:
        return None


def _named(book, prefix):
    out = {}
    for name, defined in book.defined_names.items():
        if not name.startswith(prefix):
            continue
        try:
            sheet, ref = next(iter(defined.destinations))
            min_col, min_row, max_col, max_row = range_boundaries(ref.replace("$", ""))
            ws = book[sheet]
        except (StopIteration, KeyError, ValueError, TypeError):
            continue
        cells = [ws.cell(row=r, column=c) for r in range(min_row, max_row + 1)
                 for c in range(min_col, max_col + 1)]
        out[name[len(prefix):]] = cells
    return out


def read_submission(sub):
    try:
        book = open_untrusted(sub.path, data_only=True)
    except Unreadable as reason:
        sub.problem = str(reason)
        return
    answers = _named(book, "a_")
    if not answers:
        sub.problem = "no a_ answer blocks: not a crankbook student workbook"
        return
    sub.answers = {k: [c.value for c in cells] for k, cells in answers.items()}
    sub.parameters = {k: cells[0].value for k, cells in _named(book, "p_").items()
                      if len(cells) == 1}
    ident = _named(book, "s_").get("student_id")
    sub.inside_id = str(ident[0].value).strip() if ident and ident[0].value is not None else None
    if any(v is None for values in sub.answers.values() for v in values):
        formulas = open_untrusted(sub.path, data_only=False)
        for key, cells in _named(formulas, "a_").items():
            if any(isinstance(c.value, str) and c.value.startswith("=") and
                   sub.answers[key][i] is None for i, c in enumerate(cells)):
                sub.needs_recalc = True
                break


def match(paths, root, roster_ids):
    patterns = sorted(((re.compile(rf"(?<![A-Za-z0-9]){re.escape(i)}(?![A-Za-z0-9])"), i)
                       for i in roster_ids), key=lambda p: -len(p[1]))
    out = []
    for path in paths:
        relative = str(path.relative_to(root))
        sub = Submission(path=path, relative=relative,
                         digest=hashlib.sha256(path.read_bytes()).hexdigest())
        sub.student_id = next((i for pattern, i in patterns if pattern.search(relative)), None)
        out.append(sub)
    return out


def _within(value, expected, tolerance, floor):
    return abs(value - expected) <= max(tolerance * abs(expected), floor)


def score_cell(value, expected, item, rubric, alternatives=(), consequential=None):
    number = _number(value)
    if number is None:
        return CellResult(value, expected, 0.0, "no answer" if value in (None, "") else
                          "not a number")
    if not np.isfinite(expected):
        return CellResult(value, expected, 0.0, "no expected value")
    tol, floor = item.tolerance, item.abs_floor
    if _within(number, expected, tol, floor) or any(_within(number, a, tol, floor)
                                                    for a in alternatives if np.isfinite(a)):
        return CellResult(value, expected, 1.0, "correct")
    for factor, words in UNIT_FACTORS.items():
        if _within(number, expected * factor, tol, floor * factor):
            rule = rubric["unit_slip"]
            return CellResult(value, expected, rule["fraction"], f"unit slip ({words}): "
                              + rule["note"])
    if abs(expected) > floor and _within(number, -expected, tol, floor):
        rule = rubric["sign_slip"]
        return CellResult(value, expected, rule["fraction"], "sign slip: " + rule["note"])
    if consequential is not None and np.isfinite(consequential) and \
            _within(number, consequential, tol, floor):
        rule = rubric["consequential"]
        return CellResult(value, expected, rule["fraction"], "consequential: " + rule["note"])
    return CellResult(value, expected, 0.0, "wrong")


def grade_submission(sub, manifest_row, assignment, spec, grid):
    values = {p.key: float(manifest_row[f"p_{p.key}"]) for p in spec.parameters}
    values = params.validate(spec, values)
    expected = evaluate.evaluate(spec, values, {}, grid)
    rubric = assignment.rubric
    upstream = {}
    for key in rubric.get("upstream", []):
        answer = sub.answers.get(key, [None])
        number = _number(answer[0]) if answer else None
        item = assignment.item.get(key)
        if number is not None and item and not _within(number, expected[key], item.tolerance,
                                                       item.abs_floor):
            upstream[key] = number
    own = None
    if upstream:
        try:
            with np.errstate(all="ignore"):
                own = evaluate.evaluate(spec, values, {}, grid, overrides=upstream)
        except Exception:                      # their own values may make no mechanism
            own = None
    items = {}
    for item in assignment.items:
        want = np.atleast_1d(np.asarray(expected[item.key], dtype=float))
        alternatives = [np.atleast_1d(np.asarray(expected[a], dtype=float))
                        for a in item.alternatives]
        theirs = own if (own is not None and item.consequential) else None
        cons = np.atleast_1d(np.asarray(theirs[item.key], dtype=float)) if theirs else None
        given = sub.answers.get(item.key, [])
        cells = []
        for i in range(want.size):
            value = given[i] if i < len(given) else None
            cells.append(score_cell(value, want[i], item, rubric,
                                    [a[i] for a in alternatives if i < a.size],
                                    cons[i] if cons is not None and i < cons.size else None))
        points = item.points * float(np.mean([c.fraction for c in cells]))
        items[item.key] = (points, cells)
    return items


def _recalculate(subs, progress):
    pending = [s for s in subs if s.needs_recalc and not s.problem]
    if not pending:
        return
    if progress:
        print(f"grade: recalculating {len(pending)} file(s) saved without values in LibreOffice",
              file=sys.stderr)
    with tempfile.TemporaryDirectory(prefix="crankbook-grade-") as tmp:
        staged = []
        for n, sub in enumerate(pending):
            target = Path(tmp) / "in" / f"{n:05d}.xlsx"
            target.parent.mkdir(exist_ok=True)
            target.write_bytes(sub.path.read_bytes())
            staged.append(target)
        try:
            converted = recalc.convert(staged, Path(tmp) / "out")
        except RecalculationError as error:
            for sub in pending:
                sub.problem = f"saved without values and LibreOffice failed: {error}"
            return
        for sub, path in zip(pending, converted):
            original = sub.path
            sub.path = path
            read_submission(sub)
            sub.path = original


def grade(directory, submissions, output=None, progress=True):
    settings, assignment, roster = load_directory(directory)
    spec, _, _ = params.load_preset(settings["preset"])
    root = Path(submissions)
    if not root.is_dir():
        raise AssignmentDirError(f"{root}: not a directory of submissions")
    output = Path(output) if output else Path(directory) / "results"
    ids = [r["student_id"] for r in roster]
    by_id = {r["student_id"]: r for r in roster}
    files = sorted(p for p in root.rglob("*") if p.is_file() and
                   p.suffix.lower() in (".xlsx", ".xlsm", ".xls") and not p.name.startswith("~$"))
    subs = match(files, root, ids)
    for n, sub in enumerate(subs, start=1):
        read_submission(sub)
        if sub.student_id is None and sub.inside_id in by_id:
            sub.student_id = sub.inside_id
        if progress:
            print(f"\rgrade: read {n}/{len(subs)} files", end="", file=sys.stderr, flush=True)
    if progress and subs:
        print(file=sys.stderr)
    _recalculate(subs, progress)
    grid = expected_grid(assignment, spec)
    grades = {sid: Grade(student_id=sid, name=by_id[sid]["name"]) for sid in ids}
    fingerprints = {r["fingerprint"]: r["student_id"] for r in roster}
    chosen = {}
    for sub in subs:
        if sub.student_id in grades:
            grades[sub.student_id].files.append(sub.relative)
            chosen[sub.student_id] = sub                  # the last in path order wins
    for n, (sid, sub) in enumerate(sorted(chosen.items()), start=1):
        g = grades[sid]
        if len(g.files) > 1:
            g.flags.append("multiple-submissions")
            g.details.append(f"graded {sub.relative} of {len(g.files)} files")
        if sub.problem:
            g.status, g.problem = "unreadable", sub.problem
            continue
        g.items = grade_submission(sub, by_id[sid], assignment, spec, grid)
        g.status = "graded"
        _flag(g, sub, by_id, fingerprints, spec)
        if progress:
            print(f"\rgrade: scored {n}/{len(chosen)} students", end="", file=sys.stderr,
                  flush=True)
    if progress and chosen:
        print(file=sys.stderr)
    _flag_duplicates(grades, chosen)
    unmatched = [s for s in subs if s.student_id not in grades]
    write_results(output, assignment, spec, list(grades.values()), unmatched)
    return {"graded": sum(g.status == "graded" for g in grades.values()),
            "missing": sum(g.status == "missing" for g in grades.values()),
            "unreadable": sum(g.status == "unreadable" for g in grades.values()),
            "roster": len(grades), "unmatched": len(unmatched), "output": str(output)}


def _flag(g, sub, by_id, fingerprints, spec):
    assigned = by_id[g.student_id]
    if sub.inside_id and sub.inside_id != g.student_id and sub.inside_id in by_id:
        _add(g, "wrong-student", f"the file is {sub.inside_id}'s workbook")
    changed = []
    for parameter in spec.parameters:
        if parameter.key not in sub.parameters:
            continue
        have = _number(sub.parameters[parameter.key])
        want = float(assigned[f"p_{parameter.key}"])
        if have is None or abs(have - want) > 1e-9 * max(1.0, abs(want)):
            changed.append(parameter.key)
    if changed:
        _add(g, "parameters-changed", "changed: " + ", ".join(changed))
        # whose parameters are these?
        for sid, row in by_id.items():
            if sid != g.student_id and all(
                    _number(sub.parameters.get(p.key)) is not None and
                    abs(_number(sub.parameters[p.key]) - float(row[f"p_{p.key}"])) <= 1e-9 *
                    max(1.0, abs(float(row[f"p_{p.key}"]))) for p in spec.parameters
                    if p.key in sub.parameters):
                _add(g, "wrong-student", f"the parameters are {sid}'s")
                break
    if all(c.reason == "no answer" for _, cells in g.items.values() for c in cells):
        _add(g, "blank", "no answer at all")


def _add(g, flag, detail):
    if flag not in g.flags:
        g.flags.append(flag)
    if detail not in g.details:
        g.details.append(detail)


def _flag_duplicates(grades, chosen):
    seen = {}
    for sid, sub in sorted(chosen.items()):
        if sub.problem:
            continue
        values = [v for key in sorted(sub.answers) for v in sub.answers[key]]
        if all(v in (None, "") for v in values):
            continue
        for mark in (("file", sub.digest), ("answers", json.dumps(values, default=str))):
            other = seen.get(mark)
            if other and other != sid:
                for a, b in ((sid, other), (other, sid)):
                    _add(grades[a], "duplicate", f"same {mark[0]} as {b}")
            seen.setdefault(mark, sid)
