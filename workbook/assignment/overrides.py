"""`grade --overrides FILE`: a teacher's decisions, kept in a file and applied on every run.

One row per decision, columns ``student,item,action,points,reason,who``:

* ``accept`` — full points for the item (``a_flywheel_inertia``), or for one cell of
  it (``a_pos_slider_velocity!A3``: the row's label, or its 1-based number);
* ``points`` — the item's points set to ``points``;
* ``waive-flag`` — ``item`` empty: every flag of the student; else the flag's name
  (``parameters-changed``).

Every applied row is listed in the gradebook's ``overrides`` column and the class
report, with who decided and why; a row that names no roster student, no item, no
cell or no flag is refused with its row number (exit 2), so a typo never passes
silently.  Applying the same file twice gives the same gradebook.
"""
import csv
import io
from dataclasses import dataclass, replace

from crankbook.assignment.roster import excel_text
from crankbook.errors import CrankbookError
from crankbook.spec.params import NUMBER
from crankbook.support.paths import require_file

ACTIONS = ("accept", "points", "waive-flag")
COLUMNS = ("student", "item", "action", "points", "reason", "who")


class OverridesError(CrankbookError):
    """A row of the overrides file that cannot be applied."""


@dataclass(frozen=True)
class Override:
    row: int
    student: str
    item: str                    # answer key without a_, or a flag, or ""
    cell: str                    # a row label or number, or ""
    action: str
    points: float | None
    reason: str
    who: str

    def text(self):
        target = f"a_{self.item}" if self.action != "waive-flag" and self.item else self.item
        target += f"!{self.cell}" if self.cell else ""
        amount = f" = {self.points:g}" if self.points is not None else ""
        return f"{self.action} {target or '*'}{amount} ({self.who}: {self.reason})"


def read_overrides(path, roster_ids, item_points):
    """The Overrides of ``path``, every row checked against the roster and the items
    (``item_points``: item key -> its points; a row's points lie in [0, those])."""
    item_keys = set(item_points)
    require_file(path, OverridesError, "overrides")
    try:
        raw = open(path, "rb").read(2_000_000)
    except OSError as error:
        raise OverridesError(f"overrides {path}: cannot be read ({error.strerror})") from None
    text = excel_text(raw, f"overrides {path}", OverridesError)
    rows = list(csv.reader(io.StringIO(text)))
    if not rows or [c.strip().lower() for c in rows[0]][:len(COLUMNS)] != list(COLUMNS):
        raise OverridesError(f"overrides {path}: the first row must be "
                             f"{','.join(COLUMNS)}")
    out = []
    for number, row in enumerate(rows[1:], start=2):
        if not any(cell.strip() for cell in row):
            continue
        cells = dict(zip(COLUMNS, [c.strip() for c in row] + [""] * len(COLUMNS)))
        where = f"overrides {path}, row {number}"
        if cells["student"] not in roster_ids:
            raise OverridesError(f"{where}: student {cells['student']!r} is not on the roster")
        if cells["action"] not in ACTIONS:
            raise OverridesError(f"{where}: action {cells['action']!r}: choose "
                                 f"{', '.join(ACTIONS)}")
        if not cells["reason"] or not cells["who"]:
            raise OverridesError(f"{where}: give a reason and who decided")
        item, _, cell = cells["item"].partition("!")
        points = None
        if cells["action"] != "waive-flag":
            if not item.startswith("a_") or item[2:] not in item_keys:
                raise OverridesError(f"{where}: item {cells['item']!r} is not an answer of "
                                     f"this assignment (a_<key>, optionally !row)")
            item = item[2:]
        if cells["action"] == "points":
            text = cells["points"]
            if not NUMBER.match(text):            # not 1_000, １２, nan or inf
                raise OverridesError(f"{where}: points {text[:30]!r} is not a plain "
                                     f"decimal number")
            points = float(text)
            if not 0 <= points <= item_points[item]:
                raise OverridesError(f"{where}: points {text} must lie in [0, "
                                     f"{item_points[item]:g}], the item's points")
            if cell:
                raise OverridesError(f"{where}: points are set for a whole item, not a cell")
        out.append(Override(number, cells["student"], item, cell, cells["action"], points,
                            cells["reason"], cells["who"]))
    return out


def apply(grades, overrides, assignment):
    """Apply ``overrides`` to ``grades`` (student id -> Grade) in file order; each
    applied row goes to ``grade.overrides``."""
    for o in overrides:
        g = grades[o.student]
        if o.action == "waive-flag":
            if o.item and o.item not in g.flags:
                raise OverridesError(f"overrides row {o.row}: {o.student} has no flag "
                                     f"{o.item!r} (flags: {', '.join(g.flags) or 'none'})")
            waived = [o.item] if o.item else list(g.flags)
            g.flags = [f for f in g.flags if f not in waived]
        elif g.status != "graded" or o.item not in g.items:
            raise OverridesError(f"overrides row {o.row}: {o.student} has no graded "
                                 f"answer a_{o.item} to override")
        elif o.action == "points":
            _, cells = g.items[o.item]
            g.items[o.item] = (o.points, cells)
        else:
            item = assignment.item[o.item]
            _, cells = g.items[o.item]
            chosen = range(len(cells)) if not o.cell else [_cell_index(o, cells)]
            cells = [replace(c, fraction=1.0, reason="accepted") if i in chosen else c
                     for i, c in enumerate(cells)]
            points = item.points * sum(c.fraction for c in cells) / len(cells) if cells else 0.0
            g.items[o.item] = (points, cells)
        g.overrides.append(o.text())


def _cell_index(o, cells):
    labels = [str(c.label).strip() for c in cells]
    if o.cell in labels:
        return labels.index(o.cell)
    if o.cell.isdigit() and 1 <= int(o.cell) <= len(cells):
        return int(o.cell) - 1
    raise OverridesError(f"overrides row {o.row}: a_{o.item} has no row {o.cell!r} "
                         f"(rows: {', '.join(labels[:6])}…)")
