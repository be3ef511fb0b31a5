"""The model of a workbook specification: what templates/<name>.toml says, as objects.

docs/templates.md documents the language; crankbook.spec.loader reads the TOML
into these objects and crankbook.spec.check refuses what cannot be meant.  Inputs
are named p_<key>, every computed quantity q_<key>.
"""
import importlib
import inspect
from dataclasses import dataclass, field
from functools import cached_property, lru_cache
from types import MappingProxyType

from crankbook.spec import placeholders

# Tolerance of the "crank angle at the maximum/minimum" cells: the first grid angle
# where the series comes within this fraction of its peak |value| of its extreme.
from crankbook.calc.cycle import EXTREME_TOLERANCE  # noqa: E402,F401  (re-exported)
GUARD = "inputs_valid"            # every guarded formula is IF(q_inputs_valid=1, …, "")
# an axis's item name that repeats for the items its fixed names leave ("Throw {each}")
EACH = "{each}"


@lru_cache(maxsize=None)
def calc_function(path):
    """The function a path such as 'calc.kinematics.stroke' names (under crankbook)."""
    module, _, name = path.rpartition(".")
    return getattr(importlib.import_module("crankbook." + module), name)


@dataclass(frozen=True)
class Parameter:
    """An input cell p_<key>, or with ``axis`` a column of a per-item table."""
    key: str
    unit: str
    zh: str
    en: str
    group: str
    default: object
    kind: str = "number"          # number, integer, flag (0/1) or choice (one of ``choices``)
    min: float | None = None
    max: float | None = None
    min_open: bool = False
    max_open: bool = False
    choices: tuple = ()
    axis: str | None = None       # per-item parameter: one value per item of this axis
    fill: bool = False            # per-item: its one-value default fills every item the
                                  # axis's other columns make (typed: one per item)

    def bounds_text(self):
        """The rule in words, e.g. '> 0 and ≤ 5000 mm'."""
        if self.kind == "flag":
            return "0 or 1"
        if self.kind == "choice":
            return "one of " + ", ".join(self.choices)
        parts = ["a whole number"] if self.kind == "integer" else []
        if self.min is not None:
            parts.append(f"{'>' if self.min_open else '≥'} {self.min:g}")
        if self.max is not None:
            parts.append(f"{'<' if self.max_open else '≤'} {self.max:g}")
        unit = "" if self.unit in ("-", "count") else f" {self.unit}"
        return " and ".join(parts) + unit

    def choice_number(self, word):
        """The 1-based index of ``word`` among the choices, or None.  Letter case does
        not count, as in the sheet's MATCH and its drop-down list in every engine: a
        cell holding "sae30" is computed with SAE30 there, so it is read as SAE30."""
        folded = [c.casefold() for c in self.choices]
        if isinstance(word, str) and word.casefold() in folded:
            return folded.index(word.casefold()) + 1
        return None

    def breaks_bounds(self, value):
        """True when a number is outside this parameter's own rule."""
        if self.kind == "flag":
            return value not in (0, 1)
        if self.kind == "choice":
            return not (float(value).is_integer() and 1 <= value <= len(self.choices))
        if self.kind == "integer" and not float(value).is_integer():
            return True
        lo, hi = self.min, self.max
        return ((lo is not None and (value <= lo if self.min_open else value < lo))
                or (hi is not None and (value >= hi if self.max_open else value > hi)))


@dataclass(frozen=True)
class Axis:
    """Items a quantity can have one value per (cylinders, throws, stages, gears, …).

    ``size`` is fixed when the workbook is built: the number of values of the axis's
    per-item parameters, or a calc function of them.
    """
    key: str
    zh: str
    en: str
    label_zh: str
    label_en: str
    size_calc: str | None = None
    size_args: dict = field(default_factory=dict)
    max: int = 64
    # a product of two axes (throws × pressure cases): item m is (a, b) with
    # m = (b − 1)·size(a) + a, the first axis counting fastest
    product: tuple = ()
    # an axis of one item or as many as ``aligned`` (a pressure per operating point, or
    # one for all): a formula of item k of ``aligned`` means item k here, or item 1
    aligned: str | None = None
    # items named by a value rather than a number (an order k): the quantity that holds
    # each item's value and the row label's pattern per language ("k = {value:g}")
    value_key: str | None = None
    value_label_zh: str = ""
    value_label_en: str = ""
    # items named by words (a fixed list of checks): one name per item and language
    item_names_zh: tuple = ()
    item_names_en: tuple = ()

    @property
    def live_keys(self):
        """The results its items' names hold: "Main bearing {checked_journal}" (the
        writer makes such a name a live text formula; crankbook.writer.live_text)."""
        names = self.item_names_zh + self.item_names_en
        return tuple(dict.fromkeys(node.key for name in names
                                   for node in placeholders.parse(name.replace(EACH, ""))
                                   if isinstance(node, placeholders.Ref)))

    def names(self, lang, size):
        """The items' names as laid out for ``size`` items.  The one entry holding
        ``{each}`` stands for every item the fixed names before and after it leave,
        numbered 1, 2, … in it: ["Front", "Throw {each}", "Flywheel"] names five
        stations Front, Throw 1 … Throw 3, Flywheel.  () when the items are not named
        by words, or when ``size`` leaves no room for the fixed names."""
        names = list(self.item_names_zh if lang == "zh" else self.item_names_en)
        runs = [i for i, name in enumerate(names) if EACH in name]
        if not runs:
            return tuple(names)
        i = runs[0]
        count = size - (len(names) - 1)
        if count < 0:
            return ()
        return tuple(names[:i] + [names[i].replace(EACH, str(k)) for k in range(1, count + 1)]
                     + names[i + 1:])

    def label(self, lang, number, value=None, size=None):
        """"Cylinder 3", for an axis named by values "k = 2" / "2 阶", for an axis
        named by words its item's name (an axis with an ``{each}`` run only when its
        ``size`` is given)."""
        names = self.item_names_zh if lang == "zh" else self.item_names_en
        if any(EACH in name for name in names):
            names = self.names(lang, size) if size is not None else ()
        if names and 1 <= number <= len(names):
            return names[number - 1]
        if self.value_key and value is not None:
            pattern = self.value_label_zh if lang == "zh" else self.value_label_en
            return pattern.format(value=value)
        return f"{self.label_zh if lang == 'zh' else self.label_en} {number}"


def worded(word, item):
    """An ``item_word`` naming item ``item``: "Mode 2", or the word with ``{item}`` in it
    at each place: "Section {item} (main journal {item})" → "Section 2 (main journal 2)"."""
    return word.replace("{item}", str(item)) if "{item}" in word else f"{word} {item}"


@dataclass(frozen=True)
class Constant:
    """A number fixed by the template (e.g. the cycle, 720°), written into formulas."""
    key: str
    unit: str
    value: float
    zh: str = ""
    en: str = ""


@dataclass(frozen=True)
class InputColumn:
    key: str
    unit: str
    zh: str
    en: str
    items: str | None = None      # one column per item of this axis (a trace per speed)


@dataclass(frozen=True)
class InputTable:
    """A block of input columns of any length up to ``capacity`` (a measured trace)."""
    key: str
    sheet: str
    capacity: int
    columns: tuple


@dataclass(frozen=True)
class Quantity:
    """A computed q_<key>: an Excel formula template and the calc function of the same."""
    key: str
    kind: str                     # scalar, series, result, summary or rule
    unit: str
    zh: str
    en: str
    formula: str | None
    calc: str | None
    args: dict = field(default_factory=dict)
    part: str | None = None       # one named part of a calc result of several (x of a curve)
    sheet: str | None = None
    summary: bool = False
    format: str | None = None
    grid: str | None = None       # series: the grid it is tabulated on
    first: str | None = None      # series: formula of the first row (recurrences)
    items: str | None = None      # per-item: the axis (a block of columns for a series)
    # the word before an item's number in this quantity's headers and legend names
    # ({"zh": …, "en": …}), where its axis is shared by two meanings: a torsional
    # system's sections and modes are counted alike, a critical speed belongs to a mode
    item_word: dict = field(default_factory=dict)
    guard: bool = True            # wrapped in IF(q_inputs_valid=1, …, "")
    array: bool = False           # written as a legacy (Ctrl+Shift+Enter) array formula
    start: float | None = None    # numeric grids: start, stop, step, and a period
    stop: float | None = None
    step: float | None = None
    period: float | None = None
    step_option: str | None = None  # a build option that sets this grid's step
    rows: int | None = None       # formula grids: number of rows
    chart_range: tuple = ()       # grids: chart x-axis (min, max, major unit)
    names: tuple = ()             # rules: the parameters the rule is about
    discrete: bool = False        # an index or a grid angle: agrees exactly or not at all
    must_pass: bool = False       # a 1/0 check: 0 refuses the build with one line
    verdict: bool = False         # a 1/0 pass mark: its cell is green at 1, red at 0
    target: str | float | None = None   # a factor asked to reach a key's value or a
                                        # number: green at or above it, red below
    fold: bool = False            # items sheets: a working column, grouped and folded
                                  # (it neither shows nor prints until unfolded)
    source: str = ""              # the template file that defines it

    @property
    def is_grid(self):
        return self.grid == self.key

    @property
    def is_series(self):
        return self.kind == "series"

    @property
    def is_numeric_grid(self):
        return self.is_grid and self.formula is None and self.calc is None

    def calc_function(self):
        return calc_function(self.calc)

    def calc_arguments(self):
        """The calc function's argument names mapped to the keys that feed them
        (read from its signature once: evaluation asks for every quantity, every
        time)."""
        return self._calc_arguments

    @cached_property
    def _calc_arguments(self):
        names = inspect.signature(self.calc_function()).parameters
        # a computed grid's ``rows`` is its layout, given by the evaluator, not a key
        return MappingProxyType({name: self.args.get(name, name) for name in names
                                 if not (self.is_grid and name == "rows")})

    @cached_property
    def takes_rows(self):
        """("rows",) when this computed grid's calc function takes its laid-out rows."""
        if not self.is_grid or not self.calc:
            return ()
        return ("rows",) if "rows" in inspect.signature(self.calc_function()).parameters else ()

    @cached_property
    def nodes(self):
        return placeholders.parse(self.formula or "")

    @cached_property
    def first_nodes(self):
        return placeholders.parse(self.first) if self.first else None

    def references(self):
        return placeholders.references((self.formula or "") + " " + (self.first or ""))


@dataclass(frozen=True)
class Chart:
    """A native chart: ``y`` series against ``x`` (the sheet's grid when None)."""
    y: tuple
    x: str | None = None
    x_each: tuple = ()            # an x per y curve (x–y charts of several curves)
    title_zh: str = ""
    title_en: str = ""
    axis_zh: str = ""
    axis_en: str = ""
    unit: str = "-"
    x_axis_zh: str = ""
    x_axis_en: str = ""
    x_unit: str | None = None
    equal_axes: bool = False
    type: str = "scatter"         # scatter (lines) or column (bars over x)
    log: bool | str = False       # True: logarithmic x and y axes (a p–V diagram); "y":
                                  # the y axis alone (pressures of several stages)
    curve_zh: str = ""            # per-item curves named "<curve> n" ("Mode 1") instead of
    curve_en: str = ""            # "<quantity> — <item label> n"
    curves: int | None = None     # per-item curves: only the first n items (lowest modes)
    live_names: bool = False      # per-item curves' legend names are formulas that say
                                  # when a curve has no values (a mode above the grid)
    emphasis: str | None = None   # a per-item quantity of the first y's axis: 2 = a bold
                                  # curve in the legend, 1 = thin grey, 0 = thin grey dashed
                                  # (1 and 0 leave the legend)
    heavy: tuple = ()             # y keys whose curves are drawn thick and dashed
    rows_from: float | None = None  # draw the rows from this value of the sheet's grid on
                                    # (the orbit's second cycle, not its start transient)


@dataclass(frozen=True)
class Sheet:
    key: str
    zh: str
    en: str
    title_zh: str
    title_en: str
    kind: str                     # series, scalars or items
    columns: tuple
    charts: tuple = ()
    grid: str | None = None       # series sheets: their grid
    axis: str | None = None       # items sheets: their axis
    item_word: dict = field(default_factory=dict)  # items sheets: names the rows instead
                                                   # of the axis' label (model.worded)
    print_step: float | None = None  # print every k-th row so a report stays short
    report: tuple | None = None   # series sheets: the columns the results table prints
                                  # (None: the columns its charts plot)

    def report_columns(self):
        """The keys of this series sheet's columns on the printed results table."""
        keys = [q.key for q in self.columns]
        if self.report is not None:
            return [k for k in keys if k in self.report]
        plotted = {k for c in self.charts for k in (*c.y, c.x) if k}
        return [k for k in keys if k in plotted]


@dataclass
class WorkbookSpec:
    key: str
    file: str
    zh: str
    en: str
    grid: Quantity                # the main grid (its step is the --step build option)
    grids: list
    groups: dict
    parameters: list
    axes: list
    constants: list
    input_tables: list
    rules: list
    scalars: list
    sheets: list
    results: list
    summary: list = field(default_factory=list)
    highlights: tuple = ()
    key_data: tuple = ()          # inputs and results shown at the top of the Summary
    print_step: float | None = None   # series tables print every print_step (rows between grouped)
    notes: tuple = ()             # Summary warnings: ({"when_nonzero": key, "zh", "en"}, …)
    coarse_step: dict | None = None   # {"above": °, "compare": keys}: a coarser step warns

    def __post_init__(self):
        self.parameter = {p.key: p for p in self.parameters}
        self.axis = {a.key: a for a in self.axes}
        self.constant = {c.key: c for c in self.constants}
        self.table_column = {c.key: c for t in self.input_tables for c in t.columns}
        self.quantity = {q.key: q for q in self.quantities()}

    @property
    def cycle(self):
        return self.grid.period

    def scalar_parameters(self):
        return [p for p in self.parameters if p.axis is None]

    def item_parameters(self, axis=None):
        return [p for p in self.parameters if p.axis is not None
                and (axis is None or p.axis == axis)]

    def series(self):
        return list(self.grids) + [c for s in self.sheets if s.kind == "series"
                                   for c in s.columns]

    def sheet_scalars(self):
        return [c for s in self.sheets if s.kind in ("scalars", "items") for c in s.columns]

    def quantities(self):
        """Every computed quantity, grids first, in the order they are laid out."""
        return (self.series() + self.scalars + self.sheet_scalars() + self.results
                + self.summary + self.rules)

    def unit_of(self, key):
        for table in (self.parameter, self.table_column, self.quantity, self.constant):
            if key in table:
                return table[key].unit
        raise KeyError(key)

    def components(self, axis):
        """The axes of a product axis, or (axis,) for a plain one."""
        return self.axis[axis].product or (axis,)

    def grid_options(self):
        """Numeric grids whose step a build option sets: option name -> grid."""
        return {g.step_option: g for g in self.grids if g.step_option}
