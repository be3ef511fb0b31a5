"""Assignment templates (templates/assignments/*.toml): variant ranges, the answer
sheets, the items and the rubric."""
import tomllib
from dataclasses import dataclass, field

from crankbook.errors import UnknownPresetError
from crankbook import resources

ASSIGNMENTS = "assignments"


@dataclass
class Item:
    key: str                      # a_<key> in the student file, q_<key> in the key
    points: float
    tolerance: float
    abs_floor: float = 0.0
    consequential: bool = False
    alternatives: tuple = ()      # other q_ keys that also earn full credit


@dataclass
class AnswerSheet:
    key: str
    zh: str
    en: str
    rows: str                     # "scalar", or the grid the rows follow
    items: tuple


@dataclass
class Assignment:
    key: str
    preset: str
    zh: str
    en: str
    statement_zh: str
    statement_en: str
    given: tuple
    given_step: float | None
    grid_angles: tuple | None
    variant: dict
    constraints: dict
    rubric: dict
    sheets: list
    items: list = field(default_factory=list)

    @property
    def item(self):
        return {i.key: i for i in self.items}

    @property
    def max_score(self):
        return sum(i.points for i in self.items)


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
        with open(path, "rb") as handle:
            data = tomllib.load(handle)
    elif resources.is_safe_name(name) and resources.exists(ASSIGNMENTS, f"{name}.toml"):
        data = resources.read_toml(ASSIGNMENTS, f"{name}.toml")
    else:
        raise UnknownPresetError(f"unknown assignment {name!r}; assignments are "
                                 f"{', '.join(names())}")
    head, rubric = data["assignment"], data["rubric"]
    items = [Item(key=i["key"], points=float(i["points"]),
                  tolerance=float(i.get("tolerance", rubric["tolerance"])),
                  abs_floor=float(i.get("abs_floor", 0.0)),
                  consequential=bool(i.get("consequential", False)),
                  alternatives=tuple(i.get("alternatives", ()))) for i in data["item"]]
    sheets = [AnswerSheet(key=s["key"], zh=s["zh"], en=s["en"], rows=s["rows"],
                          items=tuple(s["items"])) for s in data["sheet"]]
    placed = [k for s in sheets for k in s.items]
    if sorted(placed) != sorted(i.key for i in items):
        raise ValueError(f"assignment {name}: items and answer sheets do not match")
    return Assignment(key=head["key"], preset=head["preset"], zh=head["zh"], en=head["en"],
                      statement_zh=head["statement_zh"], statement_en=head["statement_en"],
                      given=tuple(head.get("given", ())), given_step=head.get("given_step"),
                      grid_angles=tuple(head["grid_angles"]) if "grid_angles" in head else None,
                      variant=data["variant"], constraints=data.get("constraints", {}),
                      rubric=rubric, sheets=sheets, items=items)
