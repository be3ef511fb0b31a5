"""Scoring answers as a careful human grader would.

Per cell: full credit within the item's tolerance (relative ``tolerance``, absolute
``abs_floor``) of the key or an accepted alternative; partial credit for

* a unit slip — the value in another unit of the item's own dimension (mm ↔ m,
  ° ↔ rad, rpm ↔ rad/s, N·m ↔ kN·m, …), judged on the value with the floor not
  scaled, and only where the expected value is clearly not zero;
* a sign slip — only where the expected value is clearly not zero;
* a consequential error — right for the student's own wrong r and l;

as far as the item's ``slips`` allow.  Per-position answers are paired with the
key's positions through the student's own crank angles, so a table in any order
scores the same; a position given twice or missing is reported.
"""
import math
import re
from dataclasses import dataclass

import numpy as np

from crankbook import units

PLAIN = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?\Z")
COMMA_DECIMAL = re.compile(r"[+-]?[0-9]+,[0-9]+\Z")
CLEARLY_NOT_ZERO = 3.0            # × the absolute floor


@dataclass
class CellResult:
    label: str
    value: object
    expected: float
    fraction: float
    reason: str                   # a word of templates/words/grading.toml
    detail: dict


def answer_number(value):
    """A typed answer as a float: a number, or plain ASCII decimal text (a decimal
    comma is accepted); None for anything else (full-width digits, 1_000, words)."""
    if isinstance(value, bool) or value is None:
        return None
    if isinstance(value, (int, float)):
        return float(value) if math.isfinite(value) else None
    text = str(value).strip()
    if PLAIN.match(text):
        return float(text)
    if COMMA_DECIMAL.match(text):
        return float(text.replace(",", "."))
    return None


def _within(value, expected, tolerance, floor):
    return abs(value - expected) <= max(tolerance * abs(expected), floor)


def unit_slips(unit):
    """(other unit, factor) pairs: the expected value in ``unit`` is factor × in other."""
    dimension = units.dimension(unit)
    if dimension in ("ratio", "count", "percent"):
        return []
    out = []
    for other in units.units_of(dimension):
        factor = units.si_factor(unit) / units.si_factor(other)
        if other != unit and not math.isclose(factor, 1.0):
            out.append((other, factor))
    return out


def score_cell(label, value, expected, item, rubric, alternatives=(), consequential=None):
    number = answer_number(value)
    if number is None:
        reason = "no_answer" if value is None or value == "" else "not_a_number"
        return CellResult(label, value, expected, 0.0, reason, {})
    if not np.isfinite(expected):
        return CellResult(label, value, expected, 0.0, "no_expected", {})
    tol, floor = item.tolerance, item.abs_floor
    if _within(number, expected, tol, floor):
        return CellResult(label, value, expected, 1.0, "correct", {})
    if any(np.isfinite(a) and _within(number, a, tol, floor) for a in alternatives):
        return CellResult(label, value, expected, 1.0, "alternative", {})
    clearly = abs(expected) > CLEARLY_NOT_ZERO * floor
    if "unit" in item.slips and clearly:
        for other, factor in unit_slips(item.unit):
            if _within(number, expected * factor, tol, floor):
                return CellResult(label, value, expected, rubric["unit_slip"]["fraction"],
                                  "unit_slip", {"unit": other})
    if "sign" in item.slips and clearly and _within(number, -expected, tol, floor):
        return CellResult(label, value, expected, rubric["sign_slip"]["fraction"],
                          "sign_slip", {})
    if item.consequential and consequential is not None and np.isfinite(consequential) and \
            _within(number, consequential, tol, floor):
        return CellResult(label, value, expected, rubric["consequential"]["fraction"],
                          "consequential", {})
    return CellResult(label, value, expected, 0.0, "wrong", {})


def pair_positions(angles, key_angles, labels, tolerance):
    """Each answer row's key position: ([position index or None per row], problems).

    A row whose crank angle is within ``tolerance`` of a position names it; a row
    without a usable angle takes the position of its own row (the statement's order)
    when that is free.  Problems are (word, fields) for the feedback.
    """
    rows = len(labels)
    chosen = [None] * rows
    taken, problems = {}, []
    numbers = [answer_number(a) for a in angles] + [None] * (rows - len(angles))
    unplaced = []
    for i in range(rows):
        a = numbers[i]
        distance = np.abs(np.asarray(key_angles, float) - a) if a is not None else None
        if distance is not None and distance.min() <= tolerance:
            position = int(np.argmin(distance))
            if position in taken:
                problems.append(("position_twice", {"label": labels[position],
                                                    "first": taken[position] + 1,
                                                    "second": i + 1}))
                continue
            chosen[i], taken[position] = position, i
        else:
            unplaced.append(i)
    for i in unplaced:
        if i not in taken and i < len(key_angles):
            chosen[i], taken[i] = i, i
            if numbers[i] is not None:
                problems.append(("position_by_row", {"row": i + 1, "angle": f"{numbers[i]:g}",
                                                     "label": labels[i]}))
    for position, label in enumerate(labels):
        if position not in taken:
            problems.append(("position_missing", {"label": label}))
    return chosen, problems


def score_item(item, rubric, answers, expected, labels, pairing=None, consequential=None):
    """(points, [CellResult]) of one item; ``pairing`` maps answer rows to key rows."""
    want = expected["value"]
    alternatives = expected["alternatives"]
    cells = []
    if pairing is None:
        given = {i: answers[i] if i < len(answers) else None for i in range(want.size)}
    else:
        given = {}
        for row, position in enumerate(pairing):
            if position is not None and row < len(answers):
                given[position] = answers[row]
    for i in range(want.size):
        cells.append(score_cell(labels[i] if labels else "", given.get(i), float(want[i]), item,
                                rubric, [float(a[i]) for a in alternatives if i < a.size],
                                float(consequential[i]) if consequential is not None
                                and i < consequential.size else None))
    points = item.points * float(np.mean([c.fraction for c in cells])) if cells else 0.0
    return points, cells
