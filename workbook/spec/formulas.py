"""Compile formula templates into Excel formulas for a given layout.

:class:`Locator` knows where every key lives in the workbook and turns a parsed
template (crankbook.spec.placeholders) into Excel text for one context: a sheet, a grid
row (series formulas carry markers for the row, filled per cell by :func:`fill`),
an item (per-item quantities) and the indices of enclosing {sum:…} placeholders.
What each placeholder becomes is documented in docs/templates.md.
"""
import re
from dataclasses import dataclass, field, replace

from xlsxwriter.utility import xl_col_to_name, xl_rowcol_to_cell

from crankbook.spec import units
from crankbook.support.arithmetic import integer
from crankbook.spec.placeholders import Special, Sum
from crankbook.spec.model import GUARD

ROW = "\x00"            # the 1-based row number of the cell
PREV = "\x01"           # the 1-based row number of the row above
INDEX = "\x02"          # the 0-based index of the row within its grid
INTEGER_EXPRESSION = re.compile(r"[0-9+\-*() ]{1,40}\Z")


def quote_sheet(name):
    return "'" + name.replace("'", "''") + "'"


def number(value):
    """A number as formula text: 720, 0.5, 1E-09."""
    value = float(value)
    if value.is_integer() and abs(value) < 1e15:
        return str(int(value))
    return repr(value).upper().replace("E-0", "E-").replace("E+0", "E+")


def fill(template, row, index):
    """A compiled series formula for 0-based sheet ``row``, grid index ``index``."""
    text = template.replace(ROW, str(row + 1))
    if PREV in text:
        text = text.replace(PREV, str(row))
    if INDEX in text:
        text = text.replace(INDEX, str(index))
    return text


@dataclass(frozen=True)
class Place:
    """Where a key lives.  ``kind``: cell, column (a series on ``grid``), block (a
    per-item series: ``count`` columns from ``col``), items (``count`` cells down from
    ``row``: per-item inputs and results) or range (an input table column, ``count``
    rows; ``width`` columns for one column per item)."""
    kind: str
    sheet: str
    row: int
    col: int
    grid: str | None = None
    count: int = 1
    width: int = 1                # range: columns (a per-item input column, one per item)


@dataclass(frozen=True)
class Context:
    sheet: str
    grid: str | None = None       # set for series formulas
    item: int | None = None       # the formula's own item (1-based)
    axis: str | None = None
    sums: tuple = ()              # ((axis, index), …) of enclosing {sum:…}


class CompileError(ValueError):
    """A reference that the layout cannot express (a spec mistake the checker let by)."""


@dataclass
class Locator:
    spec: object
    places: dict = field(default_factory=dict)        # key -> Place
    grid_rows: dict = field(default_factory=dict)     # grid -> (first row, last row)
    grid_numbers: dict = field(default_factory=dict)  # grid -> (start, step, period points)
    axis_sizes: dict = field(default_factory=dict)

    # ------------------------------------------------------------ addresses
    def name(self, key):
        spec = self.spec
        return f"p_{key}" if key in spec.parameter or key in spec.table_column else f"q_{key}"

    def _cell(self, sheet, row, col, context, row_text=None, absolute_row=True):
        prefix = "" if sheet == context.sheet else quote_sheet(sheet) + "!"
        if row_text is not None:
            return f"{prefix}${xl_col_to_name(col)}{row_text}"
        return prefix + xl_rowcol_to_cell(row, col, row_abs=absolute_row, col_abs=True)

    def column_range(self, key, first=None, last=None, col=None):
        place = self.places[key]
        top, bottom = self.grid_rows[place.grid]
        col = place.col if col is None else col
        letter = xl_col_to_name(col)
        first = top if first is None else first
        last = bottom if last is None else last
        return f"{quote_sheet(place.sheet)}!${letter}${first + 1}:${letter}${last + 1}"

    def whole_range(self, key):
        """Absolute reference of everything a key names (its defined name's target)."""
        place = self.places[key]
        if place.kind == "cell":
            return f"{quote_sheet(place.sheet)}!{xl_rowcol_to_cell(place.row, place.col, True, True)}"
        if place.kind in ("items", "range"):
            first = xl_rowcol_to_cell(place.row, place.col, True, True)
            last = xl_rowcol_to_cell(place.row + place.count - 1, place.col + place.width - 1,
                                     True, True)
            return f"{quote_sheet(place.sheet)}!{first}:{last}"
        top, bottom = self.grid_rows[place.grid]
        first = xl_rowcol_to_cell(top, place.col, True, True)
        last = xl_rowcol_to_cell(bottom, place.col + place.count - 1, True, True)
        return f"{quote_sheet(place.sheet)}!{first}:{last}"

    # ------------------------------------------------------------ compilers
    def series_formula(self, template_nodes, sheet, grid, item=None, axis=None, guard=True):
        """Formula text of a series cell on ``grid`` with markers for its row."""
        context = Context(sheet=sheet, grid=grid, item=item, axis=axis)
        return "=" + self.guarded(self.compile(template_nodes, context), guard)

    def scalar_formula(self, template_nodes, sheet, item=None, axis=None, guard=True):
        """Formula text of a single cell; a series stands for its whole column."""
        context = Context(sheet=sheet, item=item, axis=axis)
        return "=" + self.guarded(self.compile(template_nodes, context), guard)

    @staticmethod
    def guarded(body, guard):
        """True: blank unless the inputs are valid; False: blank where the formula fails
        (quantities the input rules read); None: the bare formula (the rules)."""
        if guard is True:
            return f'IF(q_{GUARD}=1,{body},"")'
        if guard is False:
            return f'IFERROR({body},"")'
        return body

    def compile(self, nodes, context):
        out = []
        for node in nodes:
            if isinstance(node, str):
                out.append(node)
            elif isinstance(node, Special):
                out.append(self._special(node, context))
            elif isinstance(node, Sum):
                terms = [self.compile(node.body, replace(context, sums=context.sums + (
                    (node.axis, k),))) for k in range(1, self.axis_sizes[node.axis] + 1)]
                out.append("(" + "+".join(f"({t})" for t in terms) + ")")
            else:
                text = self._reference(node, context)
                if node.unit:
                    text = units.excel_conversion(text, self.spec.unit_of(node.key), node.unit)
                out.append(text)
        return "".join(out)

    def _special(self, node, context):
        if node.name == "row_index":
            return INDEX
        if node.name == "item":
            return str(self._component(node.axis, context) if node.axis else context.item)
        return str(context.sums[-1][1])

    def _component(self, axis, context):
        """The item of ``axis`` that the context fixes (1-based), or None: an enclosing
        {sum:axis(…)}, the formula's own item, its part of a product item, or the item
        of an aligned axis (item k of the axis it is aligned to, or 1 if it has one)."""
        for sum_axis, index in reversed(context.sums):
            if sum_axis == axis:
                return index
        if context.axis is None or context.item is None:
            return None
        if context.axis == axis:
            return context.item
        product = self.spec.axis[context.axis].product
        if axis in product:
            first, second = product
            size = self.axis_sizes[first]
            return (context.item - 1) % size + 1 if axis == first \
                else (context.item - 1) // size + 1
        aligned = self.spec.axis[axis].aligned
        if aligned is not None:
            item = self._component(aligned, context)
            if item is not None:
                return item if self.axis_sizes[axis] > 1 else 1
        # the other way: case k of an aligned axis reads item k of the axis it is
        # aligned to (a pressure per operating point reads its point's heat)
        for own in (context.axis, *product):
            if self.spec.axis[own].aligned == axis:
                return self._component(own, context)
        return None

    def _reference(self, node, context):
        spec, key = self.spec, node.key
        if key in spec.constant:
            return number(spec.constant[key].value)
        parameter = spec.parameter.get(key)
        if parameter is not None and parameter.axis is None:
            if parameter.kind == "choice":
                words = ",".join('"' + c + '"' for c in parameter.choices)
                return f"MATCH(p_{key},{{{words}}},0)"
            return f"p_{key}"
        if key in spec.table_column:
            return self._table_column(node, spec.table_column[key], context)
        if node.part == "rows":
            # a grid's rows as laid out when the workbook was built: a number, so a rule
            # can tell a count typed afterwards from the layout without reading the
            # grid's (guarded) cells
            top, bottom = self.grid_rows[spec.quantity[key].grid]
            return str(bottom - top + 1)
        place = self.places[key]
        axis = parameter.axis if parameter is not None else spec.quantity[key].items
        if place.kind == "items":
            return self._item_cells(node, place, axis, context)
        if place.kind == "cell":
            return self.name(key)
        if place.kind == "block":
            return self._block(node, place, axis, context)
        return self._column(node, place, context, col=place.col)

    def _table_column(self, node, column, context):
        """An input-table column: its name, or with one column per item, the column of
        the item the context fixes."""
        item = self._component(column.items, context) \
            if column.items and node.part not in ("all", "items") else None
        if item is None:
            return f"p_{column.key}"
        place = self.places[column.key]
        letter = xl_col_to_name(place.col + item - 1)
        return (f"{quote_sheet(place.sheet)}!${letter}${place.row + 1}:"
                f"${letter}${place.row + place.count}")

    def _item_argument(self, node, context):
        text = self.compile(node.argument, context).strip()
        folded = integer(text) if INTEGER_EXPRESSION.match(text) else None
        return folded if folded is not None else text

    def _chosen_item(self, node, axis, context):
        """The item a reference means: item(EXPR) literal, an enclosing sum, or the
        formula's own item (or its part, or an aligned item); None when it means all
        items."""
        if node.part == "item":
            return self._item_argument(node, context)
        if node.part in ("all", "items"):
            for sum_axis, index in reversed(context.sums):
                if sum_axis == axis:
                    return index
            return None
        return self._component(axis, context)

    def _item_cells(self, node, place, axis, context):
        item = self._chosen_item(node, axis, context)
        if item is None:
            return self.name(node.key)
        if isinstance(item, str):
            return f"INDEX({self.name(node.key)},{item})"
        if not 1 <= item <= place.count:
            return "0"                    # item(EXPR) folded to no item: see README
        return self._cell(place.sheet, place.row + item - 1, place.col, context)

    def _product_block(self, node, place, axis, context):
        """A per-item series of a product axis (a × b): one column when the context (and
        item(EXPR), for the part it leaves open) fixes both parts, else the columns of
        one item of b (b counts slowest, so they are adjacent)."""
        first, second = self.spec.axis[axis].product
        size = self.axis_sizes[first]
        fixed = {c: None if node.part == "all" else self._component(c, context)
                 for c in (first, second)}
        if node.part == "item":
            free = [c for c in (first, second) if fixed[c] is None]
            if len(free) != 1:
                raise CompileError(f"{{{node.key}:item(…)}}: the context must fix all but "
                                   f"one of {first}, {second}")
            fixed[free[0]] = self._item_argument(node, context)
        a, b = fixed[first], fixed[second]
        if b is None or isinstance(b, str):
            if a is None and b is None and (node.part == "all" or context.grid is None):
                return self.name(node.key)
            raise CompileError(f"{{{node.key}}}: which {second}?")
        left = place.col + (b - 1) * size
        if isinstance(a, int):
            if not 1 <= a <= size:
                return "0"               # item(EXPR) folded to no item, as for any axis
            return self._column(node, place, context, col=left + a - 1)
        top, bottom = self.grid_rows[place.grid]
        if context.grid == place.grid:
            first_cell = self._cell(place.sheet, 0, left, context, row_text=ROW)
            row_range = f"{first_cell}:${xl_col_to_name(left + size - 1)}{ROW}"
            if a is None:
                return row_range
            return f"INDEX({row_range},1,{a})" if size > 1 else first_cell
        if a is not None:
            raise CompileError(f"{{{node.key}:item({a})}} outside its grid")
        first_row = top + 1 if node.part == "tail" else top
        last_row = bottom - 1 if node.part == "head" else bottom
        return (f"{quote_sheet(place.sheet)}!${xl_col_to_name(left)}${first_row + 1}:"
                f"${xl_col_to_name(left + size - 1)}${last_row + 1}")

    def _block(self, node, place, axis, context):
        if self.spec.axis[axis].product and node.part != "items":
            return self._product_block(node, place, axis, context)
        if node.part == "items":
            if context.grid == place.grid:
                first = self._cell(place.sheet, 0, place.col, context, row_text=ROW)
                last = xl_col_to_name(place.col + place.count - 1)
                return f"{first}:${last}{ROW}"
            return self.name(node.key)
        item = self._chosen_item(node, axis, context)
        if item is None:
            if node.part == "all" or context.grid is None:
                return self.name(node.key)
            raise CompileError(f"{{{node.key}}}: which {axis}? use :items or :item(…)")
        if isinstance(item, int) and not 1 <= item <= place.count:
            return "0"                    # item(EXPR) folded to no item: see README
        if isinstance(item, str):
            if context.grid != place.grid:
                raise CompileError(f"{{{node.key}:item({item})}} outside its grid")
            first = self._cell(place.sheet, 0, place.col, context, row_text=ROW)
            if place.count == 1:          # Gnumeric's INDEX of one cell is #REF!
                return first
            last = xl_col_to_name(place.col + place.count - 1)
            return f"INDEX({first}:${last}{ROW},1,{item})"     # row, column: Gnumeric too
        return self._column(node, place, context, col=place.col + item - 1)

    def _column(self, node, place, context, col):
        part, key = node.part, node.key
        top, bottom = self.grid_rows[place.grid]
        if part == "prev":
            return self._cell(place.sheet, 0, col, context, row_text=PREV)
        if part == "head":
            return self.column_range(key, last=bottom - 1, col=col)
        if part == "tail":
            return self.column_range(key, first=top + 1, col=col)
        if part == "last":
            return self._cell(place.sheet, bottom, col, context)
        if part == "at":
            start, step, points = self.grid_numbers[place.grid]
            angle = self.compile(node.argument, context)
            offset = f"({angle})" if not start else f"({angle}-{number(start)})"
            head = self.column_range(key, last=top + points - 1, col=col)
            return f"INDEX({head},MOD(INT({offset}/{number(step)}+0.5),{points})+1)"
        if part in (None, "item") and context.grid == place.grid:
            return self._cell(place.sheet, 0, col, context, row_text=ROW)
        if col == place.col and place.count == 1:
            return self.name(key)
        return self.column_range(key, col=col)
