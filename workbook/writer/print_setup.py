"""Page setup shared by the sheet writers: A4 landscape, one page wide, headers
repeated on every page."""
from crankbook.writer.layout import FIRST_ROW

A4 = 9


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
