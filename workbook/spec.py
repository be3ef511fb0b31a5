"""Workbook specifications: the TOML files in templates/ read into plain objects.

A specification lists parameters (inputs, named p_<key>), input tables, input
rules, derived scalars, sheets of series and cycle results (named q_<key>).
Each computed quantity pairs an Excel formula template with a calc function; see
the header of templates/engine.toml for the template syntax.
"""
import importlib
import inspect
import re
import tomllib
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

from workbook import units
from workbook.errors import UnknownPresetError

TEMPLATES = Path(__file__).resolve().parent.parent / "templates"
# Functions newer than Excel 2010 or volatile: a workbook must open in Excel 2010,
# LibreOffice and WPS and recompute the same everywhere.
FORBIDDEN = re.compile(r"\b(FILTER|SORT|SORTBY|UNIQUE|XLOOKUP|XMATCH|LET|LAMBDA|SEQUENCE|"
                       r"IFS|SWITCH|CONCAT|TEXTJOIN|MAXIFS|MINIFS|RANDARRAY|OFFSET|INDIRECT|"
                       r"NOW|TODAY|RAND|RANDBETWEEN)\s*\(")
REFERENCE = re.compile(r"\{([a-z_0-9]+)(?::(head|tail|prev|last))?\}")
ROW_INDEX = "row_index"        # {row_index}: 0-based row number within the grid


def calc_function(path):
    """The function a dotted path such as 'calc.kinematics.stroke' names."""
    module, _, name = path.rpartition(".")
    return getattr(importlib.import_module(module), name)


@dataclass(frozen=True)
class Parameter:
    key: str
    unit: str
    zh: str
    en: str
    group: str
    default: float
    kind: str = "number"          # "number" or "flag" (0 or 1)
    min: float | None = None
    max: float | None = None
    min_open: bool = False
    max_open: bool = False

    def bounds_text(self):
        """The rule in words, e.g. '> 0 and ≤ 5000 mm'."""
        if self.kind == "flag":
            return "0 or 1"
        parts = []
        if self.min is not None:
            parts.append(f"{'>' if self.min_open else '≥'} {self.min:g}")
        if self.max is not None:
            parts.append(f"{'<' if self.max_open else '≤'} {self.max:g}")
        unit = "" if self.unit == "-" else f" {self.unit}"
        return " and ".join(parts) + unit


@dataclass(frozen=True)
class InputColumn:
    key: str
    unit: str
    zh: str
    en: str


@dataclass(frozen=True)
class InputTable:
    key: str
    sheet: str
    capacity: int
    columns: tuple


@dataclass(frozen=True)
class Rule:
    key: str
    fails: str          # Excel condition, true when the inputs break the rule
    python: str         # the same condition as a Python expression
    names: tuple        # parameters the rule is about, for the error message
    zh: str
    en: str


@dataclass(frozen=True)
class Quantity:
    key: str
    kind: str           # "scalar" (derived constant), "series" or "result"
    unit: str
    zh: str
    en: str
    formula: str | None
    calc: str | None
    args: dict = field(default_factory=dict)
    sheet: str | None = None
    summary: bool = False
    format: str | None = None
    grid: str | None = None       # series: key of the grid it is tabulated on
    first: str | None = None      # series: formula of the first row (recurrences)
    start: float | None = None    # numeric grids: start, stop, step
    stop: float | None = None
    step: float | None = None
    rows: int | None = None       # formula grids: number of rows
    axis: tuple = ()              # grids: chart x-axis (min, max, major unit)

    @property
    def is_grid(self):
        return self.grid == self.key

    def calc_function(self):
        return calc_function(self.calc)

    def calc_arguments(self):
        """Mapping of the calc function's argument names to quantity keys."""
        names = inspect.signature(self.calc_function()).parameters
        return {name: self.args.get(name, name) for name in names}

    def references(self):
        text = (self.formula or "") + (self.first or "")
        return [m.group(1) for m in REFERENCE.finditer(text) if m.group(1) != ROW_INDEX]


@dataclass(frozen=True)
class Sheet:
    key: str
    zh: str
    en: str
    title_zh: str
    title_en: str
    axis_zh: str
    axis_en: str
    unit: str
    chart: tuple
    columns: tuple
    grid: str | None = None       # series sheets: their grid
    kind: str = "series"          # "series" or "scalars"


@dataclass
class WorkbookSpec:
    key: str
    zh: str
    en: str
    grid: Quantity                # the main crank-angle grid (its step is a build option)
    grids: list
    groups: dict
    parameters: list
    input_tables: list
    rules: list
    scalars: list
    sheets: list
    results: list
    summary: list = field(default_factory=list)
    highlights: tuple = ()        # results the command line reports after a build

    def __post_init__(self):
        self.parameter = {p.key: p for p in self.parameters}
        self.table_column = {c.key: c for t in self.input_tables for c in t.columns}
        self.quantity = {q.key: q for q in self.quantities()}

    @property
    def grid_start(self):
        return self.grid.start

    @property
    def grid_stop(self):
        return self.grid.stop

    @property
    def grid_step(self):
        return self.grid.step

    def series(self):
        return list(self.grids) + [c for s in self.sheets if s.kind == "series"
                                   for c in s.columns]

    def sheet_scalars(self):
        return [c for s in self.sheets if s.kind == "scalars" for c in s.columns]

    def quantities(self):
        """Every computed quantity, grids first, in the order they are laid out."""
        return self.series() + self.scalars + self.sheet_scalars() + self.results + self.summary

    def unit_of(self, key):
        for table in (self.parameter, self.table_column, self.quantity):
            if key in table:
                return table[key].unit
        raise KeyError(key)


def _quantity(entry, kind, sheet=None, grid=None):
    return Quantity(key=entry["key"], kind=kind, unit=entry["unit"], zh=entry["zh"],
                    en=entry["en"], formula=entry.get("formula"), calc=entry.get("calc"),
                    args=dict(entry.get("args", {})), sheet=sheet,
                    summary=entry.get("summary", False), format=entry.get("format"),
                    grid=grid, first=entry.get("first"))


def _grid(entry):
    """A grid: numeric (start, stop, step) or computed (rows, formula, calc)."""
    start, stop = entry.get("start"), entry.get("stop")
    axis = tuple(entry.get("axis", (start, stop, 90.0)))
    return Quantity(key=entry["key"], kind="series", unit=entry.get("unit", "deg"),
                    zh=entry["zh"], en=entry["en"], formula=entry.get("formula"),
                    calc=entry.get("calc"), args=dict(entry.get("args", {})),
                    format=entry.get("format", "0.0"), grid=entry["key"], start=start,
                    stop=stop, step=entry.get("step"), rows=entry.get("rows"), axis=axis)


def _instantiate(member, prefix, grid, members, aliases, summary):
    """A column-set member placed on a grid: keys of the set get the prefix,
    ``crank_angle`` stands for the grid and each alias for the key it names."""
    def rename(key):
        if key in aliases:
            return aliases[key]
        if key == "crank_angle":
            return grid
        return prefix + key if key in members else key

    def rewrite(template):
        if template is None:
            return None
        return REFERENCE.sub(lambda m: "{" + rename(m.group(1)) +
                             (":" + m.group(2) if m.group(2) else "") + "}", template)

    entry = dict(member, key=prefix + member["key"], formula=rewrite(member.get("formula")),
                 first=rewrite(member.get("first")),
                 summary=member.get("summary", False) and summary)
    function = calc_function(member["calc"])
    args = {name: member.get("args", {}).get(name, name)
            for name in inspect.signature(function).parameters}
    entry["args"] = {name: rename(source) for name, source in args.items()}
    return entry


def _summary_quantities(grids, series):
    """Max/min of each summary series and the grid angle where it occurs (in the unit of
    that series' own grid)."""
    out = []
    for q in series:
        for stat, word_zh, word_en in (("max", "最大值", "maximum"), ("min", "最小值", "minimum")):
            out.append(Quantity(
                key=f"{q.key}_{stat}", kind="result", unit=q.unit,
                zh=f"{q.zh} {word_zh}", en=f"{q.en} {word_en}",
                formula=f"{stat.upper()}({{{q.key}}})", calc=f"calc.cycle.{word_en}",
                args={"values": q.key}))
            out.append(Quantity(
                key=f"{q.key}_{stat}_angle", kind="result", unit=grids[q.grid].unit,
                zh=f"{q.zh} {word_zh}处曲轴转角", en=f"crank angle of {q.en} {word_en}",
                formula=f"INDEX({{{q.grid}}},MATCH({{{q.key}_{stat}}},{{{q.key}}},0))",
                calc=f"calc.cycle.angle_of_{word_en}",
                args={"crank_angle": q.grid, "values": q.key}))
    return out


@lru_cache(maxsize=None)
def load(name):
    """The workbook specification templates/<name>.toml."""
    path = TEMPLATES / f"{name}.toml"
    if not path.is_file():
        raise UnknownPresetError(f"workbook template {name!r} does not exist in {TEMPLATES}")
    with open(path, "rb") as handle:
        data = tomllib.load(handle)
    for name in data.pop("include", []):
        with open(TEMPLATES / "common" / f"{name}.toml", "rb") as handle:
            shared = tomllib.load(handle)
        for key, value in shared.items():
            if isinstance(value, list):
                data[key] = data.get(key, []) + value
            else:
                data[key] = {**data.get(key, {}), **value}
    head = data["workbook"]
    main = _grid({"key": head["grid"], "zh": "曲轴转角 α", "en": "Crank angle α",
                  "start": head["grid_start"], "stop": head["grid_stop"],
                  "step": head["grid_step"], "axis": (head["grid_start"], head["grid_stop"], 90.0),
                  **head.get("grid_labels", {})})
    grids = [main] + [_grid(g) for g in data.get("grid", [])]
    parameters = [Parameter(**p) for p in data["parameter"]]
    tables = [InputTable(key=t["key"], sheet=t["sheet"], capacity=t["capacity"],
                         columns=tuple(InputColumn(**c) for c in t["column"]))
              for t in data.get("input_table", [])]
    rules = [Rule(key=r["key"], fails=r["fails"], python=r["python"], names=tuple(r["names"]),
                  zh=r["zh"], en=r["en"]) for r in data.get("rule", [])]
    columnsets = {c["key"]: c["column"] for c in data.get("columnset", [])}
    # A member of any set, referred to from a set placed with a prefix, is the
    # same-prefixed column (pos_gas_force reads pos_cylinder_pressure).
    all_members = {m["key"] for members in columnsets.values() for m in members}
    sheets = []
    for s in data["sheet"]:
        kind = s.get("kind", "series")
        grid = s.get("grid", main.key) if kind == "series" else None
        entries = list(s.get("column", []))
        for use in s.get("use", []):
            members = columnsets[use["columnset"]]
            names = all_members
            chosen = use.get("columns") or [m["key"] for m in members]
            by_key = {m["key"]: m for m in members}
            entries += [_instantiate(by_key[k], use.get("prefix", ""), grid, names,
                                     use.get("aliases", {}), use.get("summary", False))
                        for k in chosen]
        if kind == "scalars":
            columns = tuple(_quantity(c, "scalar", sheet=s["key"]) for c in s.get("scalar", []))
        else:
            columns = tuple(_quantity(c, "series", sheet=s["key"], grid=grid) for c in entries)
        sheets.append(Sheet(key=s["key"], zh=s["zh"], en=s["en"], title_zh=s["title_zh"],
                            title_en=s["title_en"], axis_zh=s.get("axis_zh", ""),
                            axis_en=s.get("axis_en", ""), unit=s.get("unit", "-"),
                            chart=tuple(s.get("chart", [])), columns=columns, grid=grid,
                            kind=kind))
    series = [c for s in sheets if s.kind == "series" for c in s.columns if c.summary]
    spec = WorkbookSpec(
        key=head["key"], zh=head["zh"], en=head["en"], grid=main, grids=grids,
        groups=data.get("groups", {}), parameters=parameters, input_tables=tables, rules=rules,
        scalars=[_quantity(q, "scalar") for q in data.get("scalar", [])], sheets=sheets,
        results=[_quantity(q, "result") for q in data.get("result", [])],
        summary=_summary_quantities({g.key: g for g in grids}, series), highlights=tuple(head.get("highlights", ())))
    check(spec)
    return spec


def check(spec):
    """Fail loudly on a specification that references what it does not define."""
    known = set(spec.parameter) | set(spec.table_column) | set(spec.quantity)
    seen = set()
    for key in [p.key for p in spec.parameters] + list(spec.table_column) + \
            [q.key for q in spec.quantities()]:
        if key in seen:
            raise ValueError(f"{spec.key}: key {key!r} is defined twice")
        seen.add(key)
    homes = {s.grid for s in spec.sheets if s.kind == "series"}
    for g in spec.grids:
        if g.key not in homes:
            raise ValueError(f"{spec.key}: grid {g.key!r} is on no sheet")
    for q in spec.quantities():
        if q.is_grid and q.formula is None:
            continue
        bad = FORBIDDEN.search((q.formula or "") + (q.first or ""))
        if bad:
            raise ValueError(f"{spec.key}: formula of {q.key!r} uses {bad.group(1)}, which "
                             f"Excel 2010 lacks or which is volatile")
        for ref in q.references():
            if ref not in known:
                raise ValueError(f"{spec.key}: formula of {q.key!r} refers to unknown {ref!r}")
        for name, source in q.calc_arguments().items():
            if source not in known:
                raise ValueError(f"{spec.key}: calc {q.calc} argument {name!r} maps to "
                                 f"unknown {source!r}")
        if not units.known(q.unit):
            raise ValueError(f"{spec.key}: unit {q.unit!r} of {q.key!r} is not in units.toml")
    for s in spec.sheets:
        for key in s.chart:
            if key not in spec.quantity or spec.quantity[key].kind != "series" or \
                    spec.quantity[key].grid != s.grid:
                raise ValueError(f"{spec.key}: chart of sheet {s.key!r} lists {key!r}, "
                                 f"not a series on the sheet's grid")
