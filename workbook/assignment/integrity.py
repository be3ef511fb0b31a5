"""Academic integrity, for the teacher's eyes only: who may have copied from whom.

Every graded file is held against every student's key: answers that fit another
student's parameters better than the author's own are a copy suspicion, and so are
files or answer sets that are identical.  Where the evidence allows, the student
copied from (whose answers fit their own parameters) is told apart from the copier;
that student gets no flag.  The findings go to the teacher-only ``integrity.xlsx``
and the gradebook's ``flags`` — never to a student's feedback or the LMS import.
"""
import json
from dataclasses import dataclass, field

import numpy as np

from crankbook.assignment.scoring import answer_in

FIT = 0.6                 # share of a student's answered cells right for another key
MARGIN = 0.25             # … and this much better than for their own key
ANSWERED = 5              # cells a file must answer before its fit means anything
SECTION_ANSWERED = 3      # … and a section (one answer sheet: a table, the valve train)


@dataclass
class Suspicion:
    """One finding: ``who`` is suspected; ``whom`` the other student, if any."""
    who: str
    whom: str | None
    kinds: list           # same_file, same_answers, fits_other, wrong_student_file, …
    evidence: dict = field(default_factory=dict)
    source_known: bool = False   # whom is established as the one copied from


def numeric_answers(sub, assignment):
    """item key -> array of the answers in the item's unit (NaN where blank or text)."""
    out = {}
    for item in assignment.items:
        values = [answer_in(v, item.unit) for v in sub.answers.get(item.key, [])]
        out[item.key] = np.array([np.nan if v is None else v for v in values], dtype=float)
    return out


def fit(answers, want, assignment, only=None):
    """(right, answered): how many of the answered cells meet this key, positions paired
    by the nearest of its crank angles, the other rows by order (vectorised: a class
    is held against every key); ``only``: the item keys of one section."""
    rubric_rows = {s.rows for s in assignment.sheets}
    positions = assignment.positions
    order = None
    if positions is not None and "positions" in rubric_rows:
        given = answers.get(positions.angle_item, np.array([]))
        key_angles = want[positions.angle_item]["value"]
        if given.size and key_angles.size:
            distance = np.abs(given[:, None] - key_angles[None, :])
            order = np.where(np.nanmin(np.where(np.isnan(distance), np.inf, distance), axis=1)
                             <= positions.match_tolerance,
                             np.argmin(np.where(np.isnan(distance), np.inf, distance), axis=1),
                             -1)
    position_items = {k for s in assignment.sheets if s.rows == "positions" for k in s.items}
    right = answered = 0
    for item in assignment.items:
        if only is not None and item.key not in only:
            continue
        mine = answers.get(item.key, np.array([]))
        target = want[item.key]["value"]
        if item.key in position_items and order is not None:
            rows = np.arange(min(mine.size, order.size))
            keep = order[rows] >= 0
            mine, target = mine[rows][keep], target[order[rows][keep]]
        else:
            size = min(mine.size, target.size)
            mine, target = mine[:size], target[:size]
        present = ~np.isnan(mine)
        answered += int(present.sum())
        ok = np.abs(mine - target) <= np.maximum(item.tolerance * np.abs(target), item.abs_floor)
        right += int((ok & present).sum())
    return right, answered


def find(grades, chosen, answers, keys, assignment):
    """Suspicions of a graded class.  ``chosen``: student -> the submission graded;
    ``answers``: student -> numeric answers; ``keys``: student -> their expected
    values."""
    out = []
    ids = [sid for sid in sorted(chosen) if grades[sid].status == "graded"]
    fits = {}
    for i in ids:
        for j in keys:
            right, answered = fit(answers[i], keys[j], assignment)
            fits[i, j] = right / answered if answered >= ANSWERED else None
    by_pair = {}

    def add(who, whom, kind, source_known, **evidence):
        key = (who, whom)
        if key in by_pair:
            found = by_pair[key]
            found.kinds.append(kind)
            found.evidence.update({k: v for k, v in evidence.items() if v is not None})
            found.source_known |= source_known
            return
        by_pair[key] = Suspicion(who, whom, [kind], evidence, source_known)

    for i in ids:                            # answers that fit someone else's task
        own = fits.get((i, i))
        for j in ids:
            other = fits.get((i, j))
            if j == i or other is None:
                continue
            if other >= FIT and other >= (own or 0.0) + MARGIN:
                add(i, j, "fits_other", (fits.get((j, j)) or 0.0) >= FIT,
                    fit_own=own, fit_other=other, fit_of_other=fits.get((j, j)))
    # a copied section (one table, the valve train) in an otherwise own file: the same
    # test on each answer sheet's cells alone
    for section in assignment.sheets:
        only = set(section.items)
        share = {}
        for i in ids:
            for j in ids:
                right, answered = fit(answers[i], keys[j], assignment, only)
                share[i, j] = right / answered if answered >= SECTION_ANSWERED else None
        for i in ids:
            own = share.get((i, i))
            fitting = [j for j in ids if j != i and share.get((i, j)) is not None and
                       (i, j) not in by_pair and share[i, j] >= FIT and
                       share[i, j] >= (own or 0.0) + MARGIN]
            if not fitting:
                continue
            # several classmates may share that section's data (a gear train drawn from
            # a few): one suspicion, against the best fit, with how many share it
            j = max(fitting, key=lambda k: (share[i, k], share.get((k, k)) or 0.0))
            add(i, j, "fits_other_section", (share.get((j, j)) or 0.0) >= FIT,
                section=section.key, fit_own=own, fit_other=share[i, j],
                fit_of_other=share.get((j, j)),
                shared_by=len(fitting) if len(fitting) > 1 else None)
    for what, mark in (("same_file", lambda s: s.digest),
                       ("same_answers", lambda s: json.dumps(
                           [v for k in sorted(s.answers) for v in s.answers[k]], default=str))):
        seen = {}
        for sid in ids:
            sub = chosen[sid]
            if all(v in (None, "") for values in sub.answers.values() for v in values):
                continue
            seen.setdefault(mark(sub), []).append(sid)
        for group in seen.values():
            for a in group:
                for b in group:
                    if a == b:
                        continue
                    fit_a, fit_b = fits.get((a, a)) or 0.0, fits.get((b, b)) or 0.0
                    if fit_b >= FIT and fit_a < FIT:          # b's own work, a's copy
                        add(a, b, what, True, fit_own=fit_a, fit_of_other=fit_b)
                    elif not (fit_a >= FIT and fit_b < FIT):  # no telling: both suspected
                        add(a, b, what, False, fit_own=fit_a, fit_of_other=fit_b,
                            earlier=_earlier(chosen[a], chosen[b]))
    for sid in ids:                          # a file that says it is someone else's
        inside = chosen[sid].inside_id
        if inside and inside != sid and inside in grades:
            add(sid, inside, "wrong_student_file", (fits.get((sid, inside)) or 0) >= FIT,
                fit_other=fits.get((sid, inside)))
    out = list(by_pair.values())
    for suspicion in out:
        for who in (suspicion.who, suspicion.whom):
            if who in chosen:
                suspicion.evidence.setdefault("files", {})[who] = _file_facts(chosen[who])
    return sorted(out, key=lambda s: (s.who, s.whom or ""))


def _file_facts(sub):
    facts = {"file": sub.relative, "sha256": sub.digest[:12]}
    facts.update({k: v for k, v in sub.metadata.items() if v})
    return facts


def _earlier(a, b):
    """The student whose file was made first, by the documents' own creation time, then
    by the files' modification time; None when they cannot be told apart."""
    created = (a.metadata.get("created"), b.metadata.get("created"))
    if all(created) and created[0] != created[1]:
        return a.student_id if created[0] < created[1] else b.student_id
    if a.mtime != b.mtime:
        return a.student_id if a.mtime < b.mtime else b.student_id
    return None
