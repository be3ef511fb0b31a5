"""A worksheet that writes formula columns as prepared XML.

xlsxwriter escapes every formula with regular expressions, rewrites "future"
functions and assembles attributes cell by cell — most of a build's time.  A
column of crankbook formulas is one template whose rows differ only in the row
number, so it is escaped once and each cell becomes a finished <c> element, the
same XML xlsxwriter writes.  crankbook's templates use no future functions
(spec_check refuses them: the workbooks must open in Excel 2010, LibreOffice and
WPS), so skipping that rewriting changes nothing.
"""
import math
from collections import namedtuple

from xlsxwriter.worksheet import Worksheet

from crankbook.formulas import INDEX, PREV, ROW
from xlsxwriter.utility import xl_col_to_name

PreparedFormula = namedtuple("PreparedFormula", "ref formula format value")


def _pattern(template):
    """The formula (without '='), XML-escaped, as a str.format pattern of the row
    number {0}, the row above {1} and the grid index {2}."""
    text = template[1:].replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    text = text.replace("{", "{{").replace("}", "}}")
    return text.replace(ROW, "{0}").replace(PREV, "{1}").replace(INDEX, "{2}")


class FastWorksheet(Worksheet):
    def _prepare_formula(self, formula, expand_future_functions=False):
        if formula.startswith("{"):
            formula = formula[1:]
        if formula.startswith("="):
            formula = formula[1:]
        if formula.endswith("}"):
            formula = formula[:-1]
        return formula

    def write_formula_column(self, first_row, col, template, first, fmt, values):
        """One formula per row from ``first_row``: ``template`` (compiled, with row
        markers, starting with '=') in every row but the first, which gets ``first``;
        ``values`` are the cached results (NaN and ±inf are cached as blanks)."""
        body = _pattern(template).format
        head = _pattern(first).format if first is not None else body
        letter = xl_col_to_name(col)
        table = self.table
        for i, value in enumerate(values):
            row = first_row + i
            value = float(value)
            table[row][col] = PreparedFormula(f"{letter}{row + 1}",
                                              (head if i == 0 else body)(row + 1, row, i), fmt,
                                              value if math.isfinite(value) else "")
        self._check_dimensions(first_row, col)
        self._check_dimensions(first_row + len(values) - 1, col)

    def _write_cell(self, row, col, cell):
        if cell.__class__ is PreparedFormula:
            style = f' s="{cell.format._get_xf_index()}"' if cell.format else ""
            self.fh.write(f'<c r="{cell.ref}"{style}><f>{cell.formula}</f>'
                          f'<v>{cell.value}</v></c>')
            return
        super()._write_cell(row, col, cell)
