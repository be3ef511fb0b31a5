"""Turn formula templates into Excel formulas for a given layout.

A template names quantities as {key}; :class:`Locator` knows where each one lives.
Series formulas are compiled once per column into text with markers for the row,
so each cell costs a few string replaces.
"""
from xlsxwriter.utility import xl_col_to_name

from workbook.spec import REFERENCE, ROW_INDEX

ROW = "\x00"            # the 1-based row number of the cell
PREV = "\x01"           # the 1-based row number of the row above
INDEX = "\x02"          # the 0-based index of the row within its grid
GUARD = "q_inputs_valid"


def quote_sheet(name):
    return "'" + name.replace("'", "''") + "'"


def fill(template, row, index):
    """A compiled series formula for 0-based sheet ``row``, grid index ``index``."""
    text = template.replace(ROW, str(row + 1))
    if PREV in text:
        text = text.replace(PREV, str(row))
    if INDEX in text:
        text = text.replace(INDEX, str(index))
    return text


class Locator:
    """Where every key of a specification is in the workbook.

    Parameters and input tables are names p_<key>, scalars and results names
    q_<key>; a series is a column (sheet, column index, grid) whose grid gives its
    rows (first, last), 0-based.
    """

    def __init__(self, spec, series_columns, grid_rows):
        self.spec = spec
        self.series_columns = series_columns
        self.grid_rows = grid_rows

    def is_series(self, key):
        return key in self.series_columns

    def rows(self, key):
        return self.grid_rows[self.series_columns[key][2]]

    def name(self, key):
        if key in self.spec.parameter or key in self.spec.table_column:
            return f"p_{key}"
        return f"q_{key}"

    def cell(self, key, row_text, same_sheet=None, absolute_row=False):
        sheet, col, _ = self.series_columns[key]
        prefix = "" if sheet == same_sheet else quote_sheet(sheet) + "!"
        return f"{prefix}${xl_col_to_name(col)}{'$' if absolute_row else ''}{row_text}"

    def column_range(self, key, first=None, last=None):
        sheet, col, _ = self.series_columns[key]
        top, bottom = self.rows(key)
        letter = xl_col_to_name(col)
        first = top if first is None else first
        last = bottom if last is None else last
        return f"{quote_sheet(sheet)}!${letter}${first + 1}:${letter}${last + 1}"

    def _part(self, key, part, sheet):
        top, bottom = self.rows(key)
        if part == "head":
            return self.column_range(key, last=bottom - 1)
        if part == "tail":
            return self.column_range(key, first=top + 1)
        if part == "last":
            return self.cell(key, bottom + 1, same_sheet=sheet, absolute_row=True)
        return None

    # ------------------------------------------------------------ compilers
    def series_formula(self, template, sheet, grid, guard=True):
        """Formula text of a series cell on ``grid`` with markers for its row."""
        def replace(match):
            key, part = match.group(1), match.group(2)
            if key == ROW_INDEX:
                return INDEX
            if self.is_series(key):
                if part == "prev":
                    return self.cell(key, PREV, same_sheet=sheet)
                if part:
                    return self._part(key, part, sheet)
                if self.series_columns[key][2] == grid:
                    return self.cell(key, ROW, same_sheet=sheet)
            return self.name(key)
        body = REFERENCE.sub(replace, template)
        return "=" + (f'IF({GUARD}=1,{body},"")' if guard else body)

    def scalar_formula(self, template, guard=True):
        """Formula text of a single cell; a series stands for its whole column."""
        def replace(match):
            key, part = match.group(1), match.group(2)
            if self.is_series(key) and part:
                return self._part(key, part, None)
            return self.name(key)
        body = REFERENCE.sub(replace, template)
        return "=" + (f'IF({GUARD}=1,{body},"")' if guard else body)
