"""Resubmission rounds: every round's grades saved whole, so the next round loses
nothing.

``grades.json`` in a results directory (teacher-side) holds each student's status,
items with every cell's result, flags and notes, and the round's copy suspicions.
``grade --previous DIR`` reads it: a student who did not resubmit keeps the earlier
round's row — items, flags and feedback, not only the total, and the suspicion
behind a flag, so the integrity report still gives its evidence — and ``--keep
best`` takes the better round whole.
Results written before grades.json existed are read from their gradebook.csv
(totals and per-item points).
"""
import csv
import dataclasses
import json
import math
from pathlib import Path

from crankbook.assignment.integrity import Suspicion
from crankbook.assignment.scoring import CellResult
from crankbook.errors import CrankbookError
from crankbook.support.csv_safety import as_typed

FILE = "grades.json"
MAX_BYTES = 50 * 1024 * 1024


def save(path, grades, assignment, suspicions=()):
    """Write every grade and suspicion of this round to ``path`` (JSON)."""
    students = []
    for g in grades:
        students.append({
            "student_id": g.student_id, "name": g.name, "extra": g.extra, "status": g.status,
            "problem": g.problem, "flags": g.flags, "round": g.round, "files": g.files,
            "notes": [[word, fields, private] for word, fields, private in g.notes],
            "items": {key: [points, [[c.label, _plain(c.value), _plain(c.expected),
                                      c.fraction, c.reason, c.detail] for c in cells]]
                      for key, (points, cells) in g.items.items()}})
    text = json.dumps({"assignment": assignment.key, "max_score": assignment.max_score,
                       "students": students,
                       "suspicions": [dataclasses.asdict(s) for s in suspicions]},
                      ensure_ascii=False, indent=0, default=float)   # numpy shares
    Path(path).write_text(text + "\n", encoding="utf-8")


def _plain(value):
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value if isinstance(value, (int, float, str)) or value is None else str(value)


def load(previous, assignment):
    """(student_id -> Grade of an earlier round (graded students only), that round's
    suspicions)."""
    folder = Path(previous)
    path = folder / FILE
    if not path.is_file():
        return _legacy(folder, assignment), []
    try:
        if path.stat().st_size > MAX_BYTES:
            raise ValueError("too large")
        data = json.loads(path.read_text(encoding="utf-8"), parse_constant=_no_constant)
        if data.get("assignment") != assignment.key:
            raise CrankbookError(f"--previous {previous}: graded another assignment "
                                 f"({str(data.get('assignment'))[:40]!r})")
        grades = {g.student_id: _checked(g, assignment) for g in map(_grade, data["students"])
                  if g.status == "graded"}
        return grades, [_suspicion(entry) for entry in data.get("suspicions", [])]
    except CrankbookError:
        raise
    except (OSError, ValueError, KeyError, TypeError, AttributeError, RecursionError) as error:
        raise CrankbookError(f"--previous {previous}: its {FILE} is damaged "
                             f"({type(error).__name__})") from None


def _no_constant(word):
    """NaN, Infinity and -Infinity are not JSON: a grades.json holding them is damaged."""
    raise ValueError(f"{word} is not a number of a grade")


def _checked(g, assignment):
    """A grade read back, refused (ValueError) where it could not have been written:
    an item the assignment lacks, points outside [0, the item's], a fraction outside
    [0, 1], a note whose words crankbook does not have."""
    from crankbook.assignment.results import words
    known = words("en")
    for key, (points, cells) in g.items.items():
        item = assignment.item.get(key)
        if item is None:
            raise ValueError(f"unknown item {key[:40]!r}")
        if not (math.isfinite(points) and -1e-9 <= points <= item.points + 1e-9):
            raise ValueError(f"points {points!r} of {key!r}")
        if any(not 0 <= c.fraction <= 1 for c in cells):
            raise ValueError(f"a fraction of {key!r}")
    if any(word not in known for word, _, _ in g.notes):
        raise ValueError("a note crankbook does not write")
    return g


def _grade(entry):
    from crankbook.assignment.grade import Grade
    g = Grade(student_id=str(entry["student_id"]), name=str(entry["name"]),
              extra=dict(entry.get("extra", {})), status=str(entry["status"]),
              problem=str(entry.get("problem", "")), round=int(entry.get("round", 1)))
    g.flags = [str(f) for f in entry.get("flags", [])]
    g.files = [str(f) for f in entry.get("files", [])]
    # whether a workbook went back is that run's news, not the grade's
    g.notes = [(str(w), dict(f), bool(p)) for w, f, p in entry.get("notes", [])
               if w != "return_missing"]
    g.flags = [f for f in g.flags if f != "no-return"]
    for key, (points, cells) in entry.get("items", {}).items():
        g.items[str(key)] = (float(points), [
            CellResult(str(label), value, float("nan") if expected is None else float(expected),
                       float(fraction), str(reason), dict(detail))
            for label, value, expected, fraction, reason, detail in cells])
    return g


def _suspicion(entry):
    return Suspicion(who=str(entry["who"]), whom=None if entry["whom"] is None else
                     str(entry["whom"]), kinds=[str(k) for k in entry["kinds"]],
                     evidence=dict(entry.get("evidence", {})),
                     source_known=bool(entry.get("source_known", False)))


def kept_suspicions(grades, now, earlier, suspicions, earlier_suspicions):
    """The suspicions behind the grades kept — this round's for a student graded on
    this round's file, the earlier round's for one whose earlier grade was kept — and
    every earlier round's suspicion besides, marked with its round: a copy flagged in
    round 1 stays in the teacher's record when the student resubmits."""
    kept = []
    for found, round_grades in ((suspicions, now), (earlier_suspicions, earlier)):
        kept += [s for s in found if s.who in grades and
                 grades[s.who] is round_grades.get(s.who)]
    for s in earlier_suspicions:
        if s.who in grades and not any(s is k for k in kept):
            s.evidence.setdefault("from_round", earlier[s.who].round
                                  if s.who in earlier else 1)
            kept.append(s)
    return kept


def _legacy(folder, assignment):
    """An earlier round written before grades.json: totals and per-item points."""
    from crankbook.assignment.grade import Grade
    path = folder / "gradebook.csv"
    if not path.is_file():
        raise CrankbookError(f"--previous {folder}: has neither {FILE} nor gradebook.csv of an "
                             f"earlier round")
    out, number = {}, 1
    try:
        with open(path, newline="", encoding="utf-8-sig") as handle:
            for number, row in enumerate(csv.DictReader(handle), start=2):
                if row.get("status") != "graded":
                    continue
                g = Grade(student_id=as_typed(row["student_id"]), name=row.get("name", ""),
                          status="graded")
                for item in assignment.items:
                    column = next((c for c in row if c and c.endswith(f"(a_{item.key})")), None)
                    if column and row[column] not in ("", None):
                        g.items[item.key] = (float(row[column]), [])
                out[g.student_id] = g
    except (OSError, UnicodeDecodeError, csv.Error, KeyError, ValueError) as error:
        raise CrankbookError(f"--previous {folder}: its gradebook.csv cannot be read "
                             f"(row {number}: {type(error).__name__})") from None
    return out


def keep(new, old, rule):
    """The grade a student keeps in a resubmission round: the new one, or the earlier
    round's whole (items, flags, feedback) where the student did not resubmit or, with
    ``rule`` best, where it scored higher."""
    if old is None:
        return new
    new.round = old.round + 1
    if new.status != "graded":
        kept = old
        kept.note(None, "kept_round_no_new", round=old.round, score=f"{old.score:g}")
        return kept
    if rule == "best" and old.score > new.score:
        # which round's work stands, and why: this round's own score beside it
        old.note(None, "kept_round_best", round=old.round, score=f"{old.score:g}",
                 new=f"{new.score:g}")
        return old
    return new
