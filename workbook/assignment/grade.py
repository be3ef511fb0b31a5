"""`crankbook grade`: score returned workbooks against the assigned parameters.

Expected values come from the manifest's parameters through calc (never from cells
a student could edit).  Each submission is read on its own (a bad one is
`unreadable` and costs nobody else); of several files of one student the latest
readable one counts (by modification time, then path) and the notes list the
others.  The results are built in a hidden directory and renamed into place.
"""
import csv
import json
import math
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from crankbook import params
from crankbook.evaluate import axis_sizes
from crankbook.assignment import template as templates
from crankbook.assignment.assign import MANIFEST, RUBRIC, SETTINGS
from crankbook.assignment.key import answer_rows, expected, key_results
from crankbook.assignment.results import FEEDBACK_MODES, write_results
from crankbook.assignment.scoring import answer_number, pair_positions, score_item
from crankbook.assignment.submissions import discover, prepare, read, recalculate
from crankbook.errors import AssignmentDirError, CrankbookError
from crankbook.workspace import staged_directory

KEEP = ("latest", "best")


@dataclass
class Grade:
    student_id: str
    name: str
    status: str = "missing"                 # graded, missing, unreadable
    items: dict = field(default_factory=dict)     # item key -> (points, [CellResult])
    flags: list = field(default_factory=list)     # tokens: wrong-student, duplicate, …
    notes: list = field(default_factory=list)     # (word, fields) explaining them
    files: list = field(default_factory=list)
    problem: str = ""
    kept: tuple | None = None                     # (earlier score, rule) when kept

    @property
    def score(self):
        if self.kept is not None:
            return self.kept[0]
        return sum(points for points, _ in self.items.values())

    def note(self, flag, word, **fields):
        if flag and flag not in self.flags:
            self.flags.append(flag)
        if (word, fields) not in self.notes:
            self.notes.append((word, fields))


def _listed(names, shown=10):
    """At most ``shown`` names, then how many more."""
    more = f", … (+{len(names) - shown})" if len(names) > shown else ""
    return ", ".join(names[:shown]) + more


def load_directory(directory):
    directory = Path(directory)
    if not (directory / MANIFEST).is_file() or not (directory / SETTINGS).is_file():
        raise AssignmentDirError(f"{directory}: not a directory written by 'crankbook assign' "
                                 f"(no {MANIFEST} or {SETTINGS})")
    try:
        settings = json.loads((directory / SETTINGS).read_text(encoding="utf-8"))
        assignment = templates.load(settings["assignment"], directory / RUBRIC)
        with open(directory / MANIFEST, newline="", encoding="utf-8") as handle:
            roster = list(csv.DictReader(handle))
    except (OSError, ValueError, KeyError) as error:
        raise AssignmentDirError(f"{directory}: its {SETTINGS}, {RUBRIC} or {MANIFEST} is "
                                 f"damaged ({type(error).__name__})") from None
    return settings, assignment, roster


def answer_shapes(assignment, lang, spec, values=None):
    """a_ key -> number of cells each answer name must have (``values``: a student's
    parameters, for rows that are items of an axis)."""
    rows = {"positions": len(assignment.positions.labels(lang)) if assignment.positions else 0,
            "crank_angle": len(assignment.grid_angles or ())}
    rows.update({grid: len(angles) for grid, angles in assignment.row_angles.items()})
    if values is not None:
        rows.update(axis_sizes(spec, values))
    else:
        rows.update({axis.key: axis.max for axis in spec.axes})   # the bound, before values
    return {key: 1 if sheet.rows == "scalar" else rows[sheet.rows]
            for sheet in assignment.sheets for key in sheet.items}


def manifest_values(spec, row):
    values = {}
    for p in spec.parameters:
        text = row[f"p_{p.key}"]
        values[p.key] = [float(v) for v in text.strip("[]").split(",")] if p.axis \
            else float(text)
    return params.validate(spec, values)


def grade_submission(sub, manifest_row, assignment, spec, preset, lang):
    """(items, problems) of one readable submission."""
    values = manifest_values(spec, manifest_row)
    key = key_results(assignment, spec, preset, values)
    want = expected(assignment, spec, key)
    rubric = assignment.rubric
    upstream = {}
    for name in rubric.get("upstream", []):
        answer = sub.answers.get(name, [None])
        number = answer_number(answer[0]) if answer else None
        item = assignment.item.get(name)
        if number is not None and item and not math.isclose(
                number, float(want[name]["value"][0]), rel_tol=item.tolerance,
                abs_tol=item.abs_floor):
            upstream[name] = number
    own = expected(assignment, spec, key, overrides=upstream) if upstream else None
    labels = answer_rows(assignment, lang, key.results, spec)
    pairing, problems = None, []
    if assignment.positions is not None:
        positions = assignment.positions
        key_angles = want[positions.angle_item]["value"]
        pairing, problems = pair_positions(sub.answers.get(positions.angle_item, []), key_angles,
                                           labels["positions"], positions.match_tolerance)
    items = {}
    for sheet in assignment.sheets:
        row_labels = labels.get(sheet.rows) if sheet.rows != "scalar" else None
        for name in sheet.items:
            item = assignment.item[name]
            consequential = own[name]["value"] if own is not None and item.consequential \
                else None
            items[name] = score_item(item, rubric, sub.answers.get(name, []), want[name],
                                     [str(x) for x in row_labels] if row_labels else None,
                                     pairing if sheet.rows == "positions" else None,
                                     consequential)
    return items, problems


def choose(subs):
    """The latest readable submission of a student (by modification time, then path),
    or the latest of all when none is readable."""
    readable = [s for s in subs if not s.problem]
    pool = readable or subs
    return max(pool, key=lambda s: (s.mtime, s.relative))


def grade(directory, submissions, output=None, feedback="full", previous=None, keep="latest",
          missing_as_zero=False, progress=True):
    if feedback not in FEEDBACK_MODES:
        raise CrankbookError(f"--feedback {feedback!r}: choose {', '.join(FEEDBACK_MODES)}")
    if keep not in KEEP:
        raise CrankbookError(f"--keep {keep!r}: choose {', '.join(KEEP)}")
    settings, assignment, roster = load_directory(directory)
    lang = settings.get("lang", "zh")
    spec, _, preset = params.load_preset(settings["preset"])
    root = Path(submissions)
    if not root.is_dir():
        raise CrankbookError(f"{root}: no such folder of submissions")
    output = Path(output) if output else Path(directory) / "results"
    say = (lambda text: print(text, file=sys.stderr, flush=True)) if progress else \
        (lambda text: None)
    earlier = _previous_scores(previous) if previous else {}

    shapes = answer_shapes(assignment, lang, spec)
    subs = prepare(discover(root), root)
    for number, sub in enumerate(subs, start=1):
        if not sub.problem:
            read(sub, shapes)
        if progress and number % 10 == 0:
            print(f"\rgrade: read {number}/{len(subs)} files", end="", file=sys.stderr,
                  flush=True)
    if progress and subs:
        print(file=sys.stderr)
    recalculate(subs, shapes, say)

    by_id = {row["student_id"]: row for row in roster}
    _match(subs, by_id)
    grades = {sid: Grade(student_id=sid, name=row["name"]) for sid, row in by_id.items()}
    mine = {}
    for sub in subs:
        if sub.student_id in grades:
            mine.setdefault(sub.student_id, []).append(sub)
    chosen = {}
    for sid, files in mine.items():
        g = grades[sid]
        g.files = [s.relative for s in files]
        sub = chosen[sid] = choose(files)
        if len(files) > 1:
            g.note("multiple-submissions", "multiple", count=len(files), chosen=sub.relative,
                   others=_listed([s.relative for s in files if s is not sub]))
        if sub.problem:
            g.status, g.problem = "unreadable", sub.problem
            continue
        try:
            g.items, problems = grade_submission(sub, by_id[sid], assignment, spec, preset, lang)
        except Exception as error:          # one student's file must not stop the class
            g.status, g.problem = "unreadable", f"could not be graded ({type(error).__name__})"
            continue
        g.status = "graded"
        for word, fields in problems:
            g.note("positions", word, **fields)
        _flag(g, sub, by_id, spec)
    _flag_duplicates(grades, chosen)
    for sid, g in grades.items():
        _keep(g, earlier.get(sid), keep)
    unmatched = [s for s in subs if s.student_id not in grades]
    with staged_directory(output, replace=True) as staging:
        write_results(staging, assignment, spec, lang, list(grades.values()), unmatched,
                      feedback=feedback, missing_as_zero=missing_as_zero)
    return {"graded": sum(g.status == "graded" for g in grades.values()),
            "missing": sum(g.status == "missing" for g in grades.values()),
            "unreadable": sum(g.status == "unreadable" for g in grades.values()),
            "roster": len(grades), "unmatched": len(unmatched), "output": str(output)}


def _match(subs, by_id):
    """The roster student of each file: the id its path contains, else the id inside."""
    import re
    patterns = sorted(((re.compile(rf"(?<![A-Za-z0-9]){re.escape(i)}(?![A-Za-z0-9])"), i)
                       for i in by_id), key=lambda p: -len(p[1]))
    for sub in subs:
        sub.student_id = next((i for pattern, i in patterns if pattern.search(sub.relative)),
                              None)
        if sub.student_id is None and sub.inside_id in by_id:
            sub.student_id = sub.inside_id


def _flag(g, sub, by_id, spec):
    assigned = by_id[g.student_id]
    if sub.inside_id and sub.inside_id != g.student_id and sub.inside_id in by_id:
        g.note("wrong-student", "wrong_student", other=sub.inside_id)
    changed = []
    for parameter in spec.scalar_parameters():
        if parameter.key not in sub.parameters:
            continue
        try:                                  # a choice's word, or a number
            have = params.coerce(parameter, sub.parameters[parameter.key])
        except CrankbookError:
            have = answer_number(sub.parameters[parameter.key])
        want = float(assigned[f"p_{parameter.key}"])
        if have is None or abs(have - want) > 1e-9 * max(1.0, abs(want)):
            changed.append(parameter.key)
    if changed:
        g.note("parameters-changed", "parameters_changed", keys=", ".join(changed))
        for sid, row in by_id.items():
            if sid != g.student_id and all(
                    answer_number(sub.parameters.get(p.key)) is not None and
                    abs(answer_number(sub.parameters[p.key]) - float(row[f"p_{p.key}"])) <=
                    1e-9 * max(1.0, abs(float(row[f"p_{p.key}"])))
                    for p in spec.scalar_parameters() if p.key in sub.parameters):
                g.note("wrong-student", "parameters_of", other=sid)
                break
    if all(c.reason == "no_answer" for _, cells in g.items.values() for c in cells):
        g.note("blank", "blank")


def _flag_duplicates(grades, chosen):
    seen = {}
    for sid, sub in sorted(chosen.items()):
        if sub.problem:
            continue
        values = [v for key in sorted(sub.answers) for v in sub.answers[key]]
        if all(v in (None, "") for v in values):
            continue
        for what, mark in (("duplicate_file", sub.digest),
                           ("duplicate_answers", json.dumps(values, default=str))):
            other = seen.get((what, mark))
            if other and other != sid:
                for a, b in ((sid, other), (other, sid)):
                    grades[a].note("duplicate", "duplicate", what=what, other=b)
            seen.setdefault((what, mark), sid)


def _previous_scores(previous):
    """student_id -> score of an earlier round's gradebook (graded students only)."""
    path = Path(previous) / "gradebook.csv"
    if not path.is_file():
        raise CrankbookError(f"--previous {previous}: has no gradebook.csv of an earlier round")
    with open(path, newline="", encoding="utf-8-sig") as handle:
        return {row["student_id"]: float(row["score"]) for row in csv.DictReader(handle)
                if row.get("status") == "graded" and row.get("score") not in (None, "")}


def _keep(g, earlier, keep):
    """A resubmission round: keep the earlier score where the rule says so."""
    if earlier is None:
        return
    if g.status != "graded":
        g.kept = (earlier, "kept_no_new")
        g.status = "graded"
    elif keep == "best" and earlier > g.score:
        g.kept = (earlier, "kept_best")
    if g.kept is not None:
        g.note(None, "kept_previous", score=f"{earlier:g}", rule=g.kept[1])
