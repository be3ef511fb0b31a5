"""Where things go: sheet names in the chosen language, and the place of every key.

The layout is decided before anything is written, so that every formula can refer
to any key; each sheet writer then fills the places it is given.
"""
from dataclasses import dataclass, field

import numpy as np

from crankbook.spec.formulas import Locator, Place
from crankbook.spec.model import GUARD, worded

FIRST_ROW = 5            # 0-based row of the first grid point / item on series and items sheets
SCALAR_FIRST_ROW = 4     # first value row of a scalars sheet
OTHER = {"zh": "en", "en": "zh"}
FIXED_SHEETS = {"parameters": {"zh": "参数", "en": "Parameters"},
                "summary": {"zh": "汇总", "en": "Summary"},
                "charts": {"zh": "图表", "en": "Charts"},
                "report": {"zh": "计算结果表", "en": "Results table"}}
PARAMETER_TABLE_ROW = 6  # header row of the Parameters sheet's input table


def label(item, lang, attr=""):
    """The zh or en text of a spec item (``attr`` prefix such as 'title_')."""
    return getattr(item, f"{attr}{lang}")


def unit_text(unit):
    return {"deg": "°", "-": "–", "count": "–"}.get(unit, unit)


def step_text(step, unit):
    """A grid's print step as a note says it: 15°, 0.5 mm, 0.01 (a ratio)."""
    if unit == "deg":
        return f"{step:g}°"
    return f"{step:g}" if unit in ("-", "count") else f"{step:g} {unit}"


@dataclass
class Row:
    """One row of the Parameters sheet: what it shows and where."""
    kind: str            # group, parameter, heading, scalar, bound, rule, valid, note
    row: int
    item: object = None  # the spec object (group words, Parameter, Quantity)


@dataclass
class ItemsPlan:
    """An items sheet: one row per item, inputs then results then checks."""
    sheet: object
    inputs: list = field(default_factory=list)      # per-item Parameters
    columns: list = field(default_factory=list)     # per-item Quantities (results, rules)


class Layout:
    def __init__(self, spec, lang, grid_sizes, axis_sizes, table_lengths=None, results=None):
        """``grid_sizes``: grid key -> rows; ``axis_sizes``: axis key -> items;
        ``results``: the build's, for the names that hold one."""
        self.spec = spec
        self.lang = lang
        self.other = OTHER[lang]
        # results items' names hold ("Main bearing {checked_journal}"), and their values
        # once the build's results are known (crankbook.writer.live_text)
        self.live_keys = frozenset(k for a in spec.axes for k in a.live_keys)
        self.live_values = {} if results is None else \
            {key: results[key] for key in self.live_keys}
        # the values that name a value-named axis's items ("0.5 阶", not "谐次 1")
        self.item_values = {} if results is None else \
            {a.key: np.ravel(np.asarray(results[a.value_key], dtype=float))
             for a in spec.axes if a.value_key and a.value_key in results}
        self.axis_sizes = axis_sizes
        self.sheet_name = {key: names[lang] for key, names in FIXED_SHEETS.items()}
        for sheet in spec.sheets:
            self.sheet_name[sheet.key] = label(sheet, lang)
        self.master = {}
        for sheet in spec.sheets:
            if sheet.kind == "series":
                self.master.setdefault(sheet.grid, sheet.key)
        self.table_capacity = {t.key: max(t.capacity, (table_lengths or {}).get(t.key, 0))
                               for t in spec.input_tables}
        grid_rows = {g: (FIRST_ROW, FIRST_ROW + n - 1) for g, n in grid_sizes.items()}
        self.locator = Locator(spec, {}, grid_rows, self._grid_numbers(grid_sizes), axis_sizes)
        self.places = self.locator.places
        self.table_start = {}
        self.chart_column = {}             # sheet key -> the column its charts stand in
        self.column_of = {}                  # series key -> first column on its sheet
        self._place_series_sheets()
        self.items_plans = self._place_items_sheets()
        self.parameter_rows = self._place_parameters_sheet()
        self.summary_rows = self._place_summary_sheet()
        self._place_scalar_sheets()
        self.defined_names = {}             # name -> reference, filled by the writers
        # Workbooks of one layout (a class pack's keys) share their compiled formulas.
        self.signature = (spec.key, spec.file, lang, tuple(sorted(grid_sizes.items())),
                          tuple(sorted(axis_sizes.items())),
                          tuple(sorted(self.table_capacity.items())))

    def item_label(self, axis_key, lang, item, word=None):
        """'Throw 2', or for an item of a product axis 'Throw 2 · Pressure 3' (a part
        whose axis has a single item is left out); ``word`` (a quantity's
        ``item_word``) names the item instead of the axis' label: 'Mode 2'."""
        axis = self.spec.axis[axis_key]
        if word and lang in word:
            return worded(word[lang], item)
        if not axis.product:
            values = self.item_values.get(axis_key, ())
            value = float(values[item - 1]) if item <= len(values) else None
            return axis.label(lang, item, value if value is not None and np.isfinite(value)
                              else None, size=self.axis_sizes.get(axis_key))
        first, second = axis.product
        size = self.axis_sizes[first]
        words = [self.spec.axis[first].label(lang, (item - 1) % size + 1, size=size)]
        if self.axis_sizes[second] > 1:
            words.append(self.spec.axis[second].label(lang, (item - 1) // size + 1,
                                                      size=self.axis_sizes[second]))
        return " · ".join(words)

    def series_template(self, quantity, sheet_name, item=None, first=False):
        """The compiled formula of a series column (its first row's when ``first``)."""
        return _compiled(self, self.signature, quantity.key, sheet_name, item, first)

    # ------------------------------------------------------------ per sheet kind
    def _grid_numbers(self, grid_sizes):
        """grid -> (start, step, points of one period) of each periodic numeric grid: what
        a phase-shifted reference {key:at(…)} needs (the step follows from the rows)."""
        out = {}
        for grid in self.spec.grids:
            rows = grid_sizes.get(grid.key)
            if grid.is_numeric_grid and grid.period and rows and rows > 1:
                step = (grid.stop - grid.start) / (rows - 1)
                out[grid.key] = (grid.start, step, int(round(grid.period / step)))
        return out

    def _place_series_sheets(self):
        spec = self.spec
        for grid_key, home in self.master.items():
            self.places[grid_key] = Place("column", self.sheet_name[home], FIRST_ROW, 0,
                                          grid=grid_key)
        for sheet in spec.sheets:
            if sheet.kind != "series":
                continue
            col = 1
            for column in sheet.columns:
                count = self.axis_sizes[column.items] if column.items else 1
                kind = "block" if column.items else "column"
                self.places[column.key] = Place(kind, self.sheet_name[sheet.key], FIRST_ROW, col,
                                                grid=sheet.grid, count=count)
                self.column_of[column.key] = col
                col += count
            tables = [t for t in spec.input_tables if t.sheet == sheet.key]
            if tables and sheet.charts:
                # the charts stand beside the sheet's own columns, the input tables
                # (a trace of any width) after them: never pushed off to column 1,513
                self.chart_column[sheet.key] = col + 1
                col += 2
            for table in spec.input_tables:
                if table.sheet == sheet.key:
                    self.table_start[table.key] = col + 1
                    col += 1
                    for column in table.columns:
                        width = self.axis_sizes[column.items] if column.items else 1
                        self.places[column.key] = Place(
                            "range", self.sheet_name[sheet.key], FIRST_ROW, col,
                            count=self.table_capacity[table.key], width=width)
                        col += width

    def _place_items_sheets(self):
        spec, plans, homes = self.spec, [], {}
        for sheet in spec.sheets:
            if sheet.kind == "items":
                plan = ItemsPlan(sheet)
                if sheet.axis not in homes:
                    homes[sheet.axis] = plan
                    plan.inputs = spec.item_parameters(sheet.axis)
                plan.columns = list(sheet.columns)
                plans.append(plan)
        for rule in spec.rules:
            if rule.items:
                homes[rule.items].columns.append(rule)
        for axis in spec.axes:
            if axis.key not in homes and spec.item_parameters(axis.key):
                raise ValueError(f"axis {axis.key!r} has inputs but no items sheet")
        for plan in plans:
            name = self.sheet_name[plan.sheet.key]
            count = self.axis_sizes[plan.sheet.axis]
            for col, item in enumerate(plan.inputs + plan.columns, start=1):
                self.places[item.key] = Place("items", name, FIRST_ROW, col, count=count)
        return plans

    def _place_parameters_sheet(self):
        spec, name = self.spec, self.sheet_name["parameters"]
        rows, row = [], PARAMETER_TABLE_ROW + 1
        scalar_parameters = spec.scalar_parameters()
        for group, words in spec.groups.items():
            members = [p for p in scalar_parameters if p.group == group]
            if not members:
                continue
            rows.append(Row("group", row, words))
            row += 1
            for parameter in members:
                rows.append(Row("parameter", row, parameter))
                self.places[parameter.key] = Place("cell", name, row, 1)
                row += 1
        derived = [q for q in spec.scalars if not q.items]
        if derived:
            row += 1
            rows.append(Row("heading", row, "derived"))
            row += 1
            for quantity in derived:
                rows.append(Row("scalar", row, quantity))
                self.places[quantity.key] = Place("cell", name, row, 1)
                row += 1
        row += 1
        rows.append(Row("heading", row, "checks"))
        row += 1
        for parameter in spec.parameters:
            rows.append(Row("bound", row, parameter))
            row += 1
        for rule in spec.rules:
            rows.append(Row("rule", row, rule))
            if not rule.items:
                self.places[rule.key] = Place("cell", name, row, 1)
            row += 1
        rows.append(Row("valid", row, None))
        self.places[GUARD] = Place("cell", name, row, 1)
        self.places["input_status"] = Place("cell", name, 2, 1)
        # the notes' words stand in cells that the status cell and the Summary's line
        # read: written into those formulas, forty notes passed Excel's 8,192
        # characters of a formula, and one note its 255 of a text in a formula
        self.note_rows = []
        if spec.notes:
            row += 2
            rows.append(Row("heading", row, "notes"))
            row += 1
            for note in spec.notes:
                rows.append(Row("note", row, note))
                self.note_rows.append(row)
                row += 1
        return rows

    def note_words(self, index, sheet=False):
        """A formula's text of note ``index``'s words, the workbook's language first
        ("zh / en"), read from its cells on the Parameters sheet."""
        from crankbook.spec.formulas import quote_sheet
        prefix = f"{quote_sheet(self.sheet_name['parameters'])}!" if sheet else ""
        primary, other = ("D", "E") if self.lang == "zh" else ("E", "D")
        row = self.note_rows[index] + 1
        return f'{prefix}${primary}${row}&" / "&{prefix}${other}${row}'

    def _place_summary_sheet(self):
        spec, name = self.spec, self.sheet_name["summary"]
        rows, row = {}, 3
        rows["key_data"] = row
        row += len(spec_key_data(spec)) + 2 if spec_key_data(spec) else 0
        rows["extremes"] = row
        row += 1
        for quantity in summary_series(spec):
            for col, stat in enumerate(["max", "max_angle", "min", "min_angle"], start=3):
                self.places[f"{quantity.key}_{stat}"] = Place("cell", name, row, col)
            row += 1
        row += 1
        rows["results"] = row
        row += 1
        for quantity in spec.results:
            if quantity.items:
                raise ValueError(f"result {quantity.key!r}: per-item results go on items sheets")
            self.places[quantity.key] = Place("cell", name, row, 3)
            row += 1
        return rows

    def _place_scalar_sheets(self):
        for sheet in self.spec.sheets:
            if sheet.kind == "scalars":
                name = self.sheet_name[sheet.key]
                for index, quantity in enumerate(sheet.columns):
                    if quantity.items:
                        raise ValueError(f"{quantity.key!r}: per-item scalars go on items sheets")
                    self.places[quantity.key] = Place("cell", name, SCALAR_FIRST_ROW + index, 1)

    # ------------------------------------------------------------ helpers
    def last_row(self, grid):
        return self.locator.grid_rows[grid][1]

    def tables_on(self, sheet_key):
        return [t for t in self.spec.input_tables if t.sheet == sheet_key]

    def define_all(self):
        """A defined name for every placed key: p_<key> for inputs, q_<key> otherwise."""
        for key in self.places:
            self.defined_names[self.locator.name(key)] = "=" + self.locator.whole_range(key)


def spec_key_data(spec):
    return list(spec.key_data)


def summary_series(spec):
    return [q for s in spec.sheets if s.kind == "series" for q in s.columns
            if q.summary and not q.items]


_LAYOUTS = {}


def _compiled(layout, signature, key, sheet_name, item, first):
    cache = _LAYOUTS.setdefault(signature, {})
    if len(_LAYOUTS) > 16:                # a long-lived process builds many layouts
        _LAYOUTS.clear()
        cache = _LAYOUTS.setdefault(signature, {})
    slot = (key, sheet_name, item, first)
    if slot not in cache:
        quantity = layout.spec.quantity[key]
        nodes = quantity.first_nodes if first else quantity.nodes
        cache[slot] = None if nodes is None else layout.locator.series_formula(
            nodes, sheet_name, quantity.grid, item=item, axis=quantity.items,
            guard=quantity.guard)
    return cache[slot]
