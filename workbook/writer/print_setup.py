"""Page setup shared by the sheet writers: A4 landscape, one page wide, headers
repeated on every page."""
import math

from crankbook.writer.layout import FIRST_ROW

A4 = 9
NO_PRINT = (0, 16383, 0, 16383)   # a print area on an always-empty cell: the sheet is
                                  # skipped when the whole workbook prints


def wrapped_title(ws, row, text, widths, fmt):
    """A title merged across the table's columns (``widths`` in characters), wrapped,
    its row as tall as its lines: a printed page never cuts it."""
    last = len(widths) - 1
    if last < 1:
        ws.write(row, 0, text, fmt)
        return
    chars = sum(widths) * 1.1
    width = sum(1.9 if ord(ch) > 0x2E7F else 1 for ch in text)
    lines = max(1, math.ceil(width / chars))
    ws.merge_range(row, 0, row, last, text, fmt)
    ws.set_row(row, 20 * lines if fmt.bold else 14 * lines)


def landscape_report(ws, layout, sheet_spec, rows, last_col, chart_col):
    """A series table: portrait when it has a few columns (a whole coarse-step table
    on one page), landscape when wide; one page wide either way."""
    ws.set_paper(A4)
    if last_col <= 8:
        ws.set_portrait()
    else:
        ws.set_landscape()
    ws.set_margins(left=0.5, right=0.4, top=0.5, bottom=0.5)
    ws.fit_to_pages(1, 0)
    ws.repeat_rows(FIRST_ROW - 3, FIRST_ROW - 1)
    ws.repeat_columns(0, 0)


def landscape_page(ws):
    """A4 landscape, one page wide (tables of a few dozen rows)."""
    ws.set_paper(A4)
    ws.set_landscape()
    ws.fit_to_pages(1, 0)
