"""A worksheet that writes formula columns as prepared XML.

xlsxwriter escapes every formula with regular expressions, rewrites "future"
functions and assembles attributes cell by cell — most of a build's time.  A
column of crankbook formulas is one template whose rows differ only in the row
number, so it is escaped once and each cell becomes a finished <c> element, the
same XML xlsxwriter writes.  crankbook's templates use no future functions
(spec_check refuses them: the workbooks must open in Excel 2010, LibreOffice and
WPS), so skipping that rewriting changes nothing.

Where a column's rows differ only in relative row references (no {row_index}
literal), its cells are one *shared formula*: the first cell of the run holds the
text and the range, the others point at it (<f t="shared" si="k"/>), as Excel
itself saves a filled-down column.  Excel, LibreOffice, Gnumeric and WPS expand it;
every cell keeps its own cached value.  It shrinks the sheet XML several-fold, and
with it the writing and the compression of every build.
"""
import numpy as np
from xlsxwriter.utility import xl_col_to_name
from xlsxwriter.worksheet import Worksheet

from crankbook.formulas import INDEX, PREV, ROW


class CellXml(str):
    """A cell's finished <c> element (its format's index fixed when written)."""
    __slots__ = ()


def _pattern(template):
    """The formula (without '='), XML-escaped, as a str.format pattern of the row
    number {0}, the row above {1} and the grid index {2}."""
    text = template[1:].replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    text = text.replace("{", "{{").replace("}", "}}")
    return text.replace(ROW, "{0}").replace(PREV, "{1}").replace(INDEX, "{2}")


class FastWorksheet(Worksheet):
    _shared_formulas = 0          # shared-formula indices handed out on this sheet
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
        style = f' s="{fmt._get_xf_index()}"' if fmt else ""
        table = self.table
        # the run of rows written as one shared formula: all rows but a distinct first
        shared_from = 0 if first is None or first == template else 1
        shareable = INDEX not in template and len(values) - shared_from >= 2
        numbers = np.asarray(values, dtype=float)
        cached = [repr(v) if ok else "" for v, ok in
                  zip(numbers.tolist(), np.isfinite(numbers).tolist())]
        dependent = None
        for i, value in enumerate(cached):
            row = first_row + i
            ref = f"{letter}{row + 1}"
            if dependent is not None:
                formula = dependent
            elif shareable and i == shared_from:
                index = self._next_shared_index()
                last = first_row + len(values)
                formula = f'<f t="shared" ref="{ref}:{letter}{last}" si="{index}">' \
                    f'{body(row + 1, row, i)}</f>'
                dependent = f'<f t="shared" si="{index}"/>'
            else:
                formula = f"<f>{(head if i == 0 else body)(row + 1, row, i)}</f>"
            table[row][col] = CellXml(f'<c r="{ref}"{style}>{formula}<v>{value}</v></c>')
        self._check_dimensions(first_row, col)
        self._check_dimensions(first_row + len(values) - 1, col)

    def _next_shared_index(self):
        self._shared_formulas += 1
        return self._shared_formulas - 1

    def _write_cell(self, row, col, cell):
        if cell.__class__ is CellXml:
            self.fh.write(cell)
            return
        super()._write_cell(row, col, cell)

    def _calculate_spans(self):
        """xlsxwriter's <row spans="…"> per block of 16 rows, from the cells each row
        holds instead of a scan over every column of every row (same result)."""
        if self.comments:
            return super()._calculate_spans()
        spans = {}
        for row_num, cells in self.table.items():
            if not cells or not self.dim_rowmin <= row_num <= self.dim_rowmax:
                continue
            block = row_num // 16
            low, high = min(cells), max(cells)
            if block in spans:
                low, high = min(low, spans[block][0]), max(high, spans[block][1])
            spans[block] = (low, high)
        self.row_spans = {block: f"{low + 1}:{high + 1}" for block, (low, high) in spans.items()}

    def _write_rows(self):
        """xlsxwriter's row loop over the rows that hold something, each row's cells in
        column order (the same XML, without a scan of every column of every row)."""
        if self.comments:
            return super()._write_rows()
        self._calculate_spans()
        filled = {row for row, cells in self.table.items() if cells}
        for row_num in sorted(filled | set(self.row_info)):
            if not self.dim_rowmin <= row_num <= self.dim_rowmax:
                continue
            span = self.row_spans.get(row_num // 16)
            info = self.row_info.get(row_num)
            if row_num in filled:
                if info is None:
                    self._write_row(row_num, span)
                else:
                    self._write_row(row_num, span, info)
                cells = self.table[row_num]
                for col_num in sorted(cells):
                    self._write_cell(row_num, col_num, cells[col_num])
                self._xml_end_tag("row")
            else:
                self._write_empty_row(row_num, span, info)

    def _get_range_data(self, row_start, col_start, row_end, col_end):
        """No cached chart data: the formula cells are finished XML xlsxwriter cannot
        read back, so a cache would hold the x values without the y values; every
        engine draws the charts from the cells (Excel recalculates on load,
        fullCalcOnLoad)."""
        return []
