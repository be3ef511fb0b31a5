"""Turn formula templates into Excel formulas for a given layout.

A template names quantities as {key}; :class:`Locator` knows where each one lives.
Series formulas are compiled once per column into text with a row marker, so each
cell costs one string replace.
"""
from xlsxwriter.utility import xl_col_to_name

from workbook.spec import REFERENCE

ROW = "\x00"            # stands for the 1-based row number in a compiled series formula
GUARD = "q_inputs_valid"


def quote_sheet(name):
    return "'" + name.replace("'", "''") + "'"


class Locator:
    """Where every key of a specification is in the workbook.

    Parameters and input tables are names p_<key>, scalars and results names
    q_<key>, series columns (sheet, column index) with rows first..last (0-based).
    """

    def __init__(self, spec, series_columns, first_row, last_row):
        self.spec = spec
        self.series_columns = series_columns
        self.first_row = first_row
        self.last_row = last_row

    def is_series(self, key):
        return key in self.series_columns

    def name(self, key):
        if key in self.spec.parameter or key in self.spec.table_column:
            return f"p_{key}"
        return f"q_{key}"

    def cell(self, key, row_text, same_sheet=None):
        sheet, col = self.series_columns[key]
        prefix = "" if sheet == same_sheet else quote_sheet(sheet) + "!"
        return f"{prefix}${xl_col_to_name(col)}{row_text}"

    def column_range(self, key, first=None, last=None):
        sheet, col = self.series_columns[key]
        letter = xl_col_to_name(col)
        first = self.first_row if first is None else first
        last = self.last_row if last is None else last
        return f"{quote_sheet(sheet)}!${letter}${first + 1}:${letter}${last + 1}"

    # ------------------------------------------------------------ compilers
    def series_formula(self, template, sheet, guard=True):
        """Formula text of a series cell with ROW where the row number goes."""
        def replace(match):
            key, part = match.group(1), match.group(2)
            if self.is_series(key):
                if part:
                    raise ValueError(f"{{{key}:{part}}} is only for scalar formulas")
                return self.cell(key, ROW, same_sheet=sheet)
            return self.name(key)
        body = REFERENCE.sub(replace, template)
        return "=" + (f'IF({GUARD}=1,{body},"")' if guard else body)

    def scalar_formula(self, template, guard=True):
        """Formula text of a single cell; a series stands for its whole column."""
        def replace(match):
            key, part = match.group(1), match.group(2)
            if self.is_series(key):
                if part == "head":
                    return self.column_range(key, last=self.last_row - 1)
                if part == "tail":
                    return self.column_range(key, first=self.first_row + 1)
                return self.name(key)
            return self.name(key)
        body = REFERENCE.sub(replace, template)
        return "=" + (f'IF({GUARD}=1,{body},"")' if guard else body)
