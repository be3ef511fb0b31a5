"""Assignment templates (templates/assignments/*.toml): variant ranges, the answer
sheets and their rows, the items in words, the rubric."""
import tomllib
from dataclasses import dataclass, field

import numpy as np

from crankbook.support import resources

from crankbook.spec import units
from crankbook.errors import SpecError, UnknownPresetError
from crankbook.support.paths import require_file

ASSIGNMENTS = "assignments"
SLIPS = ("unit", "sign")


@dataclass
class Item:
    key: str                      # a_<key> in the student file, q_<key> in the key
    points: float
    tolerance: float
    zh: str                       # the quantity in words, without the method
    en: str
    unit: str
    abs_floor: float = 0.0
    consequential: bool = False
    alternatives: tuple = ()      # other q_ keys that also earn full credit
    slips: tuple = SLIPS          # which partial credits apply
    angle_tolerance: float | None = None   # deg, absolute: an angle item's tolerance
    modulo: float | None = None   # deg: answers equal modulo this (a mounting angle)

    def label(self, lang):
        return self.zh if lang == "zh" else self.en


@dataclass
class AnswerSheet:
    key: str
    zh: str
    en: str
    rows: str                     # "scalar", "positions", "crank_angle" (grid_angles), a grid
                                  # of row_angles, or an axis (one row per gear, mesh, …)
    items: tuple


@dataclass
class Positions:
    """Rows that are mechanism positions, listed in the guide's order: each revolution's
    positions (``order``, a series of one revolution), revolution after revolution."""
    grid: str                     # the key's grid of all positions (sorted by angle)
    order: str                    # one revolution's positions in the guide's order
    angle_item: str               # the answer item holding the student's crank angles
    revolutions: int
    period: float
    match_tolerance: float        # deg: a student's angle within this names a position
    labels_zh: tuple
    labels_en: tuple

    def labels(self, lang):
        base = self.labels_zh if lang == "zh" else self.labels_en
        return [label + "′" * revolution for revolution in range(self.revolutions)
                for label in base]

    def guide_angles(self, results):
        """The positions' crank angles in the guide's order (all revolutions)."""
        one = np.asarray(results[self.order], dtype=float)
        return np.concatenate([one + self.period * r for r in range(self.revolutions)])

    def guide_rows(self, results):
        """Index into the key's (sorted) position grid of each guide-order position."""
        grid = np.asarray(results[self.grid], dtype=float)
        wanted = self.guide_angles(results)
        return np.array([int(np.argmin(np.abs(grid - angle))) for angle in wanted])


@dataclass
class Assignment:
    key: str
    preset: str
    zh: str
    en: str
    statement_zh: str
    statement_en: str
    given_trace: bool
    given_step: float | None
    given_pressure: str | None
    grid_angles: tuple | None
    variant: dict
    constraints: dict
    rubric: dict
    sheets: list
    positions: Positions | None = None
    items: list = field(default_factory=list)
    task_groups: tuple | None = None   # parameter groups the Task sheet shows (None: all)
    row_angles: dict = field(default_factory=dict)   # grid key -> the angles asked for
    row_labels: dict = field(default_factory=dict)   # axis -> {zh, en, roles_…, caption_…}

    @property
    def item(self):
        return {i.key: i for i in self.items}

    @property
    def max_score(self):
        # items scaled to a course weight (--out-of 20) sum to 19.999999999999986
        return round(sum(i.points for i in self.items), 9)

    def statement(self, lang):
        return self.statement_zh if lang == "zh" else self.statement_en

    def row_label(self, axis, lang, number, count):
        """The words of row ``number`` of an axis's table ("啮合 1（齿轮 1–2）"), from
        the assignment's [row_labels]; None where it gives none."""
        pattern = self.row_labels.get(axis, {}).get(lang)
        if pattern is None:
            return None
        roles = self.row_labels.get(axis, {}).get(f"roles_{lang}", {})
        role = roles.get("first") if number == 1 else roles.get("last") if number == count \
            else roles.get("middle", "")
        return pattern.format(n=number, next=number + 1, role=role or "")

    def axis_caption(self, axis, lang, values):
        """A caption above an axis's table of inputs (the gear train and its ratio)."""
        pattern = self.row_labels.get(axis, {}).get(f"caption_{lang}")
        if pattern is None:
            return None
        fields = {key: (list(v) if isinstance(v, (list, tuple)) else v)
                  for key, v in values.items()}
        teeth = fields.get("gear_teeth") or [1.0]
        return pattern.format(first=f"{teeth[0]:g}", last=f"{teeth[-1]:g}",
                              ratio=f"{teeth[-1] / teeth[0]:g}")

    def name(self, lang):
        return self.zh if lang == "zh" else self.en


def names():
    return resources.names(ASSIGNMENTS)


def for_preset(preset):
    """The assignment template of a preset."""
    for name in names():
        if load(name).preset == preset:
            return load(name)
    raise UnknownPresetError(f"no assignment template for preset {preset!r}; assignments exist "
                             f"for: " + ", ".join(load(n).preset for n in names()))


def load(name, path=None):
    """An assignment template by name, or from ``path`` (the copy in a class directory)."""
    if path is not None:
        require_file(path, UnknownPresetError, "assignment")
        try:
            with open(path, "rb") as handle:
                data = tomllib.load(handle)
        except OSError as error:
            raise UnknownPresetError(f"assignment {path}: cannot be read "
                                     f"({error.strerror})") from None
        except tomllib.TOMLDecodeError as error:
            raise SpecError(str(path), "toml", str(error)) from None
        file = str(path)
    elif resources.is_safe_name(name) and resources.exists(ASSIGNMENTS, f"{name}.toml"):
        data = resources.read_toml(ASSIGNMENTS, f"{name}.toml")
        file = f"{ASSIGNMENTS}/{name}.toml"
    else:
        raise UnknownPresetError(f"unknown assignment {name!r}; assignments are "
                                 f"{', '.join(names())}")
    missing = [t for t in ("assignment", "rubric", "item", "sheet", "variant") if t not in data]
    if missing:
        raise SpecError(file, missing[0], "missing: an assignment file needs [assignment], "
                                          "[variant], [rubric], [[sheet]] and [[item]]")
    head, rubric = data["assignment"], data["rubric"]
    default_slips = tuple(rubric.get("slips", SLIPS))
    items = []
    for entry in data["item"]:
        slips = tuple(entry.get("slips", default_slips))
        if set(slips) - set(SLIPS):
            raise SpecError(file, entry["key"], f"slips are {', '.join(SLIPS)}")
        if not units.known(entry["unit"]):
            raise SpecError(file, entry["key"], f"unit {entry['unit']!r} is not in units.toml")
        angle = units.dimension(entry["unit"]) == "angle"
        for name in ("angle_tolerance", "modulo"):
            if name in entry and not angle:
                raise SpecError(file, entry["key"], f"{name} is for angle items only")
        items.append(Item(key=entry["key"], points=float(entry["points"]),
                          tolerance=float(entry.get("tolerance", rubric["tolerance"])),
                          zh=entry["zh"], en=entry["en"], unit=entry["unit"],
                          abs_floor=float(entry.get("abs_floor", 0.0)),
                          consequential=bool(entry.get("consequential", False)),
                          alternatives=tuple(entry.get("alternatives", ())), slips=slips,
                          angle_tolerance=float(entry.get("angle_tolerance",
                                                          rubric.get("angle_tolerance", 0.5)))
                          if angle else None,
                          modulo=float(entry["modulo"]) if "modulo" in entry else None))
    sheets = [AnswerSheet(key=s["key"], zh=s["zh"], en=s["en"], rows=s["rows"],
                          items=tuple(s["items"])) for s in data["sheet"]]
    placed = [k for s in sheets for k in s.items]
    if sorted(placed) != sorted(i.key for i in items):
        raise SpecError(file, "sheet", "items and answer sheets do not match")
    positions = None
    if "positions" in data:
        p = data["positions"]
        positions = Positions(grid=p["grid"], order=p["order"], angle_item=p["angle_item"],
                              revolutions=int(p["revolutions"]), period=float(p["period"]),
                              match_tolerance=float(p["match_tolerance"]),
                              labels_zh=tuple(p["labels_zh"]), labels_en=tuple(p["labels_en"]))
    return Assignment(key=head["key"], preset=head["preset"], zh=head["zh"], en=head["en"],
                      statement_zh=head["statement_zh"], statement_en=head["statement_en"],
                      given_trace=bool(head.get("given_trace", False)),
                      given_step=head.get("given_step"),
                      given_pressure=head.get("given_pressure"),
                      grid_angles=tuple(head["grid_angles"]) if "grid_angles" in head else None,
                      variant=data["variant"], constraints=data.get("constraints", {}),
                      rubric=rubric, sheets=sheets, positions=positions, items=items,
                      task_groups=tuple(head["task_groups"]) if "task_groups" in head else None,
                      row_angles={k: tuple(float(a) for a in v)
                                  for k, v in head.get("row_angles", {}).items()},
                      row_labels=dict(data.get("row_labels", {})))
