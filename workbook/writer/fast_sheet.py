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
import zipfile

import numpy as np
import xlsxwriter.workbook
from xlsxwriter.utility import xl_col_to_name
from xlsxwriter import Workbook
from xlsxwriter.chart import Chart
from xlsxwriter.worksheet import Worksheet

from crankbook.spec.formulas import INDEX, PREV, ROW


_COLUMN_XML = {}          # (template, place, style, …) -> the column's cell XML around values
MAX_CACHED_COLUMNS = 4000


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
        style = f' s="{fmt._get_xf_index()}"' if fmt else ""
        numbers = np.asarray(values, dtype=float)
        cached = [repr(v) if ok else "" for v, ok in
                  zip(numbers.tolist(), np.isfinite(numbers).tolist())]
        # everything but the values is the same for every workbook of one layout (the
        # keys of a class): the cells' XML around their values is made once
        key = (template, first, first_row, col, len(cached), style, self._shared_formulas)
        parts = _COLUMN_XML.get(key)
        if parts is None:
            parts, shared = self._column_xml(first_row, col, template, first, style,
                                             len(cached))
            if len(_COLUMN_XML) > MAX_CACHED_COLUMNS:
                _COLUMN_XML.clear()
            _COLUMN_XML[key] = parts = (parts, shared)
        parts, shared = parts
        self._shared_formulas += shared
        table = self.table
        for i, (head, tail) in enumerate(parts):
            table[first_row + i][col] = CellXml(head + cached[i] + tail)
        self._check_dimensions(first_row, col)
        self._check_dimensions(first_row + len(cached) - 1, col)

    def _column_xml(self, first_row, col, template, first, style, count):
        """([(XML before the value, XML after it)] per row, shared formulas used)."""
        body = _pattern(template).format
        head = _pattern(first).format if first is not None else body
        letter = xl_col_to_name(col)
        # the run of rows written as one shared formula: all rows but a distinct first
        shared_from = 0 if first is None or first == template else 1
        shareable = INDEX not in template and count - shared_from >= 2
        parts, dependent, shared = [], None, 0
        for i in range(count):
            row = first_row + i
            ref = f"{letter}{row + 1}"
            if dependent is not None:
                formula = dependent
            elif shareable and i == shared_from:
                index = self._shared_formulas + shared
                shared += 1
                last = first_row + count
                formula = f'<f t="shared" ref="{ref}:{letter}{last}" si="{index}">' \
                    f'{body(row + 1, row, i)}</f>'
                dependent = f'<f t="shared" si="{index}"/>'
            else:
                formula = f"<f>{(head if i == 0 else body)(row + 1, row, i)}</f>"
            parts.append((f'<c r="{ref}"{style}>{formula}<v>', "</v></c>"))
        return parts, shared

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
                order = sorted(cells)
                if all(cells[c].__class__ is CellXml for c in order):
                    self.fh.write("".join([cells[c] for c in order]))   # one write a row
                else:
                    for col_num in order:
                        self._write_cell(row_num, col_num, cells[col_num])
                self._xml_end_tag("row")
            else:
                self._write_empty_row(row_num, span, info)

    def _get_range_data(self, row_start, col_start, row_end, col_end):
        """No cached chart data read back from the cells: the formula cells are
        finished XML xlsxwriter cannot read; the chart writer hands every series its
        cache from the numpy values instead (crankbook.writer.charts)."""
        return []


def _write_num_cache(self, data):
    """xlsxwriter's <c:numCache> as one string: the same XML, without an element call
    per point (a workbook's charts cache some hundred thousand points); made once for
    points that keep it (crankbook.writer.charts.Points)."""
    made = getattr(data, "xml", None)
    if made is not None:
        self.fh.write(made)
        return
    count = len(data) if data else 0
    parts = [f'<c:numCache><c:formatCode>General</c:formatCode><c:ptCount val="{count}"/>']
    for index, token in enumerate(data or ()):
        if token is None:
            continue
        try:
            float(token)
        except (TypeError, ValueError):
            token = 0
        parts.append(f'<c:pt idx="{index}"><c:v>{token}</c:v></c:pt>')
    parts.append("</c:numCache>")
    text = "".join(parts)
    if hasattr(data, "xml"):
        data.xml = text
    self.fh.write(text)


Chart._write_num_cache = _write_num_cache


def _write_plot_vis_only(self):
    """<c:plotVisOnly> always written: xlsxwriter leaves it out for a chart that plots
    hidden rows, and openpyxl (the first thing a Python user saves a workbook with)
    reads a missing element as 1 — after its save the charts would skip the rows
    folded for printing and draw every curve at the print step."""
    self._xml_empty_tag("c:plotVisOnly", [("val", 0 if self.show_hidden else 1)])


Chart._write_plot_vis_only = _write_plot_vis_only


class FastWorkbook(Workbook):
    """A workbook whose every sheet is a FastWorksheet (crankbook's formulas need none
    of xlsxwriter's per-cell formula rewriting), in Arial 10 throughout: the Normal
    style's font sets the width of a column's character, and Calibri — xlsxwriter's
    default — is missing on most Linux machines, where LibreOffice then measures
    columns in a wider substitute (DejaVu Sans) and prints every sheet at two thirds of
    its size.  Arial's metric twin, Liberation Sans, comes with LibreOffice; Arial 10
    and Calibri 11 both make a 7-pixel character, so Excel's layout does not change."""

    def __init__(self, filename=None, options=None):
        super().__init__(filename, options)
        self.formats[0].set_font_name("Arial")
        self.formats[0].set_font_size(10)

    def add_worksheet(self, name=None, worksheet_class=None):
        return super().add_worksheet(name, worksheet_class=worksheet_class or FastWorksheet)

    def _store_workbook(self):
        # xlsxwriter zips each part at zlib's default level 6, a fifth of a class key's
        # writing time; level 1 takes half as long for a file some 14 % larger.  The
        # level rides on the ZipInfo xlsxwriter makes per part (in-memory mode), so
        # its class is swapped for this workbook's packing only.
        xlsxwriter.workbook.ZipInfo = _QuickZipInfo
        try:
            super()._store_workbook()
        finally:
            xlsxwriter.workbook.ZipInfo = zipfile.ZipInfo


class _QuickZipInfo(zipfile.ZipInfo):
    """A zip member deflated at level 1 (fast; the same bytes on every run)."""
    __slots__ = ()

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._compresslevel = 1
