"""Scoring answers as a careful human grader would.

Per cell: full credit within the item's tolerance (relative ``tolerance``, absolute
``abs_floor``) of the key or an accepted alternative; partial credit for

* a unit slip — the value in another unit of the item's own dimension (mm ↔ m,
  ° ↔ rad, rpm ↔ rad/s, N·m ↔ N·mm ↔ kN·m, kg·m² ↔ kg·mm², …), converted back
  and judged in the item's unit with its tolerance and floor; never for an answer
  that is zero, and only where the expected value is clearly not zero;
* a sign slip — never for zero, at any magnitude the floor tells from zero;

an angle (crank angle φ, pressure, mounting and transmission angles) is judged in
degrees: within the rubric's ``angle_tolerance`` (0.5° unless an item says
otherwise), modulo 360° where the item's ``modulo`` says the statement allows it;
an answer typed in a unit that is the asked one under another name (N·m for a
J item, units.toml ``[answer_dimensions]``) is in the asked unit; "2,605" and
"2，605" are thousands (2605), "2,6" a decimal comma, and "2.605,3" is refused as
ambiguous;
* a consequential error — right for the student's own mechanism (all their
  upstream answers, e.g. a wrong r and l), or one of its alternatives;

as far as the item's ``slips`` allow.  Per-position answers are paired with the
key's positions through the student's own crank angles, so a table in any order
scores the same; a position given twice or missing is reported.
"""
import math
import re
import unicodedata
from dataclasses import dataclass

import numpy as np

from crankbook.spec import units

PLAIN = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?\Z")
# "2,605" and "2，605" (full-width, NFKC-normalised) are thousands as Chinese (and
# English) readers read them: groups of exactly three digits, a point after them
THOUSANDS = re.compile(r"[+-]?[0-9]{1,3}(?:,[0-9]{3})+(?:\.[0-9]*)?\Z")
COMMA_DECIMAL = re.compile(r"[+-]?[0-9]+,[0-9]+\Z")      # "2,6": a decimal comma
# a point before a comma ("2.605,3"): thousands and decimals the other way round,
# or a typo — no reader can tell
AMBIGUOUS = re.compile(r"[+-]?[0-9]+(?:\.[0-9]{3})+,[0-9]+\Z|[+-]?[0-9.]*\.[0-9]*,[0-9,.]*\Z")
WITH_UNIT = re.compile(r"([+-]?(?:[0-9]{1,3}(?:,[0-9]{3})+(?:\.[0-9]*)?|[0-9]+(?:[.,][0-9]*)?|"
                       r"[.,][0-9]+)(?:[eE][+-]?[0-9]+)?)"
                       r"\s*(\S.{0,15})\Z")
CLEARLY_NOT_ZERO = 3.0            # × the absolute floor


@dataclass
class CellResult:
    label: str
    value: object
    expected: float
    fraction: float
    reason: str                   # a word of templates/words/grading.toml
    detail: dict


def _plain_number(text):
    if PLAIN.match(text):
        return float(text)
    if THOUSANDS.match(text):
        return float(text.replace(",", ""))
    if COMMA_DECIMAL.match(text):
        return float(text.replace(",", "."))
    return None


def read_answer(value):
    """(number, unit) of a typed answer: a number, or text as students type it — ASCII
    or full-width digits (Chinese input methods), a decimal comma, and a unit after
    the number ("103.4mm", "4.019 m/s"); unit None when none was typed.  (None, None)
    for anything else (words, 1_000, a unit nobody uses)."""
    if isinstance(value, bool) or value is None:
        return None, None
    if isinstance(value, (int, float)):
        return (float(value), None) if math.isfinite(value) else (None, None)
    text = unicodedata.normalize("NFKC", str(value)).strip().replace("−", "-")
    number = _plain_number(text)
    if number is not None:
        return number, None
    match = WITH_UNIT.match(text)
    if match:
        number, unit = _plain_number(match.group(1)), units.typed_unit(match.group(2))
        if number is not None and unit is not None:
            return number, unit
    return None, None


def unread_reason(value):
    """Why a typed answer that is not empty was not read as a number: the word
    ``ambiguous_number`` for "2.605,3", else ``not_a_number``."""
    text = unicodedata.normalize("NFKC", str(value)).strip().replace("−", "-")
    head = WITH_UNIT.match(text)
    if AMBIGUOUS.match(text) or (head and AMBIGUOUS.match(text.split()[0] if " " in text
                                                        else text)):
        return "ambiguous_number"
    return "not_a_number"


def answer_number(value):
    """A typed answer as a float (see :func:`read_answer`; a unit typed after it is
    ignored); None for anything that is not a number."""
    return read_answer(value)[0]


def _within(value, expected, tolerance, floor):
    return abs(value - expected) <= max(tolerance * abs(expected), floor)


def _close(value, expected, item):
    """Whether an answer (in the item's unit) is right: an angle within the item's
    ``angle_tolerance`` in degrees (modulo its ``modulo`` where the statement allows
    it), anything else within its relative tolerance or its floor."""
    if item.angle_tolerance is None:
        return _within(value, expected, item.tolerance, item.abs_floor)
    per_degree = units.si_factor("deg") / units.si_factor(item.unit)
    difference = value - expected
    if item.modulo:
        period = item.modulo * per_degree
        difference = (difference + period / 2) % period - period / 2
    return abs(difference) <= max(item.angle_tolerance * per_degree, item.abs_floor)


def unit_slips(unit):
    """(other unit, factor) pairs: the expected value in ``unit`` is factor × in other."""
    dimension = units.dimension(unit)
    if dimension in ("ratio", "count", "percent"):
        return []
    out = []
    for other in units.slip_units_of(dimension):
        factor = units.si_factor(unit) / units.si_factor(other)
        if other != unit and not math.isclose(factor, 1.0):
            out.append((other, factor))
    return out


def _right(number, targets, item):
    return any(np.isfinite(t) and _close(number, t, item)
               for t in targets)


def score_cell(label, value, expected, item, rubric, alternatives=(), consequential=()):
    """One answer cell against the key.  Slips are judged in the item's own unit: the
    answer is converted back (value / factor) and must meet the item's tolerance and
    floor; an answer that is zero (within the floor, once converted back) never earns
    slip credit — it is right only where the key itself is zero.  ``consequential``:
    the values (the student's own mechanism's, and its alternatives) that earn
    consequential credit."""
    if getattr(value, "machine_dependent", False):
        return CellResult(label, str(value), expected, 0.0, "machine_dependent", {})
    number, typed = read_answer(value)
    if number is None:
        reason = "no_answer" if value is None or value == "" else unread_reason(value)
        return CellResult(label, value, expected, 0.0, reason, {})
    if not np.isfinite(expected):
        return CellResult(label, value, expected, 0.0, "no_expected", {})
    floor = item.abs_floor
    fraction = rubric["unit_slip"]["fraction"]
    if typed is not None and units.same_unit(typed, item.unit):
        typed = None                       # N·m for a J item: the asked unit
    if typed is not None and typed != item.unit:
        if not units.answer_convertible(typed, item.unit):
            return CellResult(label, value, expected, 0.0, "wrong_unit",
                              {"unit": typed, "wanted": item.unit})
        number = number * units.si_factor(typed) / units.si_factor(item.unit)
        if "unit" in item.slips and abs(number) > floor and \
                _right(number, (expected, *alternatives), item):
            return CellResult(label, value, expected, fraction, "unit_slip", {"unit": typed})
        return CellResult(label, value, expected, 0.0, "wrong", {})
    if _close(number, expected, item):
        return CellResult(label, value, expected, 1.0, "correct", {})
    if _right(number, alternatives, item):
        return CellResult(label, value, expected, 1.0, "alternative", {})
    zero = abs(number) <= floor
    clearly = abs(expected) > CLEARLY_NOT_ZERO * floor
    if "unit" in item.slips and clearly:
        for other, factor in unit_slips(item.unit):
            # zero is judged after converting back: 0.0222 m for 22.2 mm is no zero
            converted = number / factor
            if abs(converted) > floor and _close(converted, expected, item):
                return CellResult(label, value, expected, fraction, "unit_slip", {"unit": other})
    # a sign slip at any magnitude the floor can tell from zero (−12.31 typed for a
    # 12.3 N·m torque whose floor is 5 N·m): only "right but for the sign" is asked
    if "sign" in item.slips and not zero and abs(expected) > floor and \
            _right(-number, (expected, *alternatives), item):
        return CellResult(label, value, expected, rubric["sign_slip"]["fraction"],
                          "sign_slip", {})
    if item.consequential and _right(number, consequential, item):
        return CellResult(label, value, expected, rubric["consequential"]["fraction"],
                          "consequential", {})
    return CellResult(label, value, expected, 0.0, *_thousands_or_wrong(value, expected, item))


def _thousands_or_wrong(value, expected, item):
    """(reason, detail) of a wrong answer: "wrong", or — where a comma read as
    thousands ("104,135" as 104135) would be right read as a decimal point — the word
    that tells the student so (no credit: the rule is the class's, said in advance)."""
    if isinstance(value, str):
        text = unicodedata.normalize("NFKC", value).strip().split(" ")[0]
        if text.count(",") == 1 and THOUSANDS.match(text):
            decimal = float(text.replace(",", "."))
            if _close(decimal, expected, item):
                return "thousands_read", {"number": f"{float(text.replace(',', '')):g}",
                                          "decimal": f"{decimal:g}"}
    return "wrong", {}


def answer_in(value, unit):
    """A typed answer as a number in ``unit`` (a unit typed after it converted), or None."""
    number, typed = read_answer(value)
    if number is None or typed is None or typed == unit:
        return number
    if not units.answer_convertible(typed, unit):
        return None
    return number * units.si_factor(typed) / units.si_factor(unit)


@dataclass
class Pairing:
    """Which key position each answer row holds, and what the grader had to assume."""
    rows: list                    # position index (or None) per answer row
    problems: list                # (word, fields) for the feedback
    angles: dict                  # row -> the crank angle the row means (a ′ row's φ + 360)


def pair_positions(angles, key_angles, labels, tolerance, own_angles=None, row_labels=None):
    """Each answer row's key position.

    A row whose crank angle is within ``tolerance`` of a position — of the key's
    mechanism, or of the student's own (``own_angles``: their r and l) — names it; a
    second-revolution row (labelled A0′…) whose angle is typed as 0–360° is that
    angle + 360°.  A row without a usable angle takes the position its label names
    (``row_labels``: the labels beside the student's rows, moved with any row they
    inserted), else that of its own row (the statement's order) when free.
    """
    rows = max(len(angles), len(row_labels or ()))
    chosen = [None] * rows
    taken, problems, meant = {}, [], {}
    numbers = [answer_number(a) for a in angles] + [None] * (rows - len(angles))
    targets = [np.asarray(key_angles, float)]
    if own_angles is not None:
        targets.append(np.asarray(own_angles, float))
    position_of_label = {str(label).strip(): i for i, label in enumerate(labels)}
    unplaced = []

    def nearest(angle):
        best = min(((float(np.min(np.abs(t - angle))), int(np.argmin(np.abs(t - angle))))
                    for t in targets), default=(np.inf, None))
        return best[1] if best[0] <= tolerance else None

    for i in range(rows):
        a = numbers[i]
        label = _row_label(i, row_labels, labels)
        position = None
        if a is not None and label and label.endswith("′") and a < 360:
            # a second-revolution row typed 0–360°: that row's φ + 360°
            position = nearest(a + 360.0)
            if position is not None:
                meant[i] = a + 360.0
                problems.append(("second_revolution", {"label": label, "angle": f"{a:g}"}))
        if position is None and a is not None:
            position = nearest(a)
        if position is None:
            unplaced.append(i)
            continue
        if position in taken:
            problems.append(("position_twice", {"label": labels[position],
                                                "first": taken[position] + 1,
                                                "second": i + 1}))
            continue
        chosen[i], taken[position] = position, i
    for i in unplaced:
        label = str(row_labels[i]).strip() if row_labels and i < len(row_labels) and \
            row_labels[i] is not None else None
        by_label = position_of_label.get(label) if label else None
        if row_labels is not None and by_label is None:
            continue                     # a row the student added (a note): not an answer
        position = by_label if by_label is not None else i
        if position not in taken and position < len(key_angles):
            chosen[i], taken[position] = position, i
            if numbers[i] is not None:
                problems.append(("position_by_row", {"row": i + 1, "angle": f"{numbers[i]:g}",
                                                     "label": labels[position]}))
    for position, label in enumerate(labels):
        if position not in taken:
            problems.append(("position_missing", {"label": label}))
    return Pairing(chosen, _grouped(problems), meant)


def _grouped(problems):
    """One note per kind where a student repeats a slip row after row (a column of
    zeros gives 28 "given twice" notes): the rows or labels listed in one, where the
    first of them stood."""
    runs = {}
    for number, (word, fields) in enumerate(problems):
        key = (word, fields["label"]) if word == "position_twice" else \
            word if word in ("position_missing", "second_revolution") else number
        runs.setdefault(key, []).append((word, fields))
    out = []
    for run in runs.values():
        word, fields = run[0]
        if len(run) == 1:
            out.append(run[0])
        elif word == "position_twice":
            out.append(("position_repeated", {
                "label": fields["label"], "first": fields["first"], "count": len(run) + 1,
                "rows": [f["second"] for _, f in run]}))
        else:
            plural = "positions_missing" if word == "position_missing" else "second_revolutions"
            out.append((plural, {"labels": [f["label"] for _, f in run]}))
    return out


def _row_label(row, row_labels, labels):
    """The label of an answer row: the one beside it in the student's file, else the
    statement's label of that row."""
    if row_labels is not None:
        label = row_labels[row] if row < len(row_labels) else None
    else:
        label = labels[row] if row < len(labels) else None
    return str(label).strip() if label is not None else None


def place_rows(row_labels, expected_labels):
    """Answer row of each expected row of a labelled table (cam angles, gears, …), found
    by its label where the student's rows moved (an inserted note row), else by order."""
    def key(label):
        number = answer_number(label)
        return f"{number:g}" if number is not None else str(label).strip()
    where = {}
    for row, label in enumerate(row_labels):
        if label is not None and key(label) not in where:
            where[key(label)] = row
    return [where.get(key(label), i if i < len(row_labels) else None)
            for i, label in enumerate(expected_labels)]


def score_item(item, rubric, answers, expected, labels, pairing=None, consequential=(),
               angles=None):
    """(points, [CellResult]) of one item.  ``pairing``: the key position of each answer
    row; ``consequential``: arrays of the values the student's own mechanism gives
    (with its alternatives); ``angles``: row -> the value a row means (a ′ row's angle)."""
    want = expected["value"]
    alternatives = expected["alternatives"]
    cells = []
    if pairing is None:
        given = {i: answers[i] if i < len(answers) else None for i in range(want.size)}
    else:
        given = {}
        for row, position in enumerate(pairing):
            if position is not None and row < len(answers):
                given[position] = (angles or {}).get(row, answers[row])
    for i in range(want.size):
        cells.append(score_cell(labels[i] if labels else "", given.get(i), float(want[i]), item,
                                rubric, [float(a[i]) for a in alternatives if i < a.size],
                                [float(c[i]) for c in consequential if i < np.size(c)]))
    points = item.points * float(np.mean([c.fraction for c in cells])) if cells else 0.0
    return points, cells
