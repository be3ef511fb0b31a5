"""The printed results table: every series column of the workbook at its print step,
side by side, as formulas on the quantity sheets.

A quantity sheet holds its whole table (every grid row) and its charts for the
screen; printing twenty one-column tables of a few dozen rows would take twenty
pages, so the quantity sheets print nothing and this sheet prints their columns
together, a page of columns at a time (the crank angle repeated at the left of
every page), the way a thesis prints its table of results.
"""
import math

from xlsxwriter.utility import xl_rowcol_to_cell

from crankbook.spec.formulas import quote_sheet
from crankbook.writer.layout import FIRST_ROW, FIXED_SHEETS, label, step_text
from crankbook.writer.print_setup import A4, wrapped_title
from crankbook.writer.series_sheet import fit_header_rows, headers

MAX_ROWS = 49              # printed rows of one block: one page tall
COLUMN_WIDTH = 12          # characters
PAGE_WIDTH_PX = 1040       # A4 landscape less the margins, at 96 dpi
PAGE_HEIGHT_PT = 595 - 72  # A4 landscape less the margins
PORTRAIT_WIDTH_PX = 716    # A4 portrait less the margins, at 96 dpi
PORTRAIT_HEIGHT_PT = 842 - 72
ROW_POINTS = 15            # a row of numbers
CONTINUED = {"zh": "（续 / continued）", "en": "(continued / 续)"}
NOTE = {"zh": "各计算表的列（公式引用各表），每 {step} 一行；各表的完整数据与图表见各表，图表另见“图表”表。",
        "en": "The columns of the quantity sheets (formulas on them), one row every {step}; "
              "each sheet holds its full table and charts, and the Charts sheet the charts."}


def printed_rows(grid_values, step):
    """Indices of the grid rows printed: multiples of ``step`` (at most MAX_ROWS rows;
    a coarser multiple of the grid's own step when no step is given)."""
    if step is None:
        step = grid_values[1] - grid_values[0] if len(grid_values) > 1 else 1.0
    if not (math.isfinite(step) and step > 0):
        step = 1.0
    while True:
        rows = [i for i, value in enumerate(grid_values)
                if math.isfinite(value) and abs(value / step - round(value / step)) < 1e-9]
        if len(rows) <= MAX_ROWS:
            return rows, step
        step *= 2


def _columns(layout, grid):
    """(header words (lang, other), unit, sheet name, column, values) of every series
    column on ``grid``'s sheets, in sheet order."""
    spec, out = layout.spec, []
    for sheet in spec.sheets:
        if sheet.kind != "series" or sheet.grid != grid:
            continue
        chosen = sheet.report_columns()
        for quantity in sheet.columns:
            if quantity.key not in chosen:
                continue
            place = layout.places[quantity.key]
            for offset in range(place.count):
                words = []
                for lang in (layout.lang, layout.other):
                    text = label(quantity, lang)
                    if quantity.items:
                        text += " — " + layout.item_label(quantity.items, lang, offset + 1,
                                                          quantity.item_word)
                    words.append(text)
                out.append((words, quantity.unit, place.sheet, place.col + offset,
                            quantity.key, offset if quantity.items else None))
    return out


def write_report_sheet(book, layout, results, styles):
    """The results table (see the module docstring); nothing when no sheet is a series."""
    spec, lang = layout.spec, layout.lang
    grids = []
    for sheet in spec.sheets:
        if sheet.kind == "series" and sheet.grid not in grids:
            grids.append(sheet.grid)
    if not grids:
        return None
    ws = book.add_worksheet(layout.sheet_name["report"])
    # the title starts in column B: column A repeats on every page, and its cell would
    # print the title cut at A's edge on a page to the right (each such page starts
    # with the title of its own, below)
    title = f"{FIXED_SHEETS['report'][lang]} / {FIXED_SHEETS['report'][layout.other]}"
    ws.write(0, 1, title, styles.title)
    row, widest, tallest, notes, blocks = 1, 0, 0, [], []
    for grid in grids:
        columns = _columns(layout, grid)
        if not columns:
            continue
        grid_q = spec.quantity[grid]
        master = quote_sheet(layout.sheet_name[layout.master[grid]])
        step = next((s.print_step for s in spec.sheets
                     if s.kind == "series" and s.grid == grid and s.print_step), None)
        if step is None and grid == spec.grid.key:
            step = spec.print_step
        values = results[grid]
        rows, step = printed_rows(list(map(float, values)), step)
        notes.append((row, NOTE[lang].format(step=step_text(step, grid_q.unit))))
        header = row + 1
        headers(ws, 0, (label(grid_q, lang), label(grid_q, layout.other)), grid_q.unit,
                layout, styles, width=10, row=header)
        angle_format = styles.number(grid_q.unit, grid_q.format)
        for k, i in enumerate(rows):
            ws.write_formula(header + 3 + k, 0, f"={master}!{xl_rowcol_to_cell(FIRST_ROW + i, 0)}",
                             angle_format, float(values[i]))
        for c, (words, unit, sheet, source_col, key, item) in enumerate(columns, start=1):
            quantity = spec.quantity[key]
            fmt = styles.number(unit, quantity.format)
            headers(ws, c, words, unit, layout, styles, width=COLUMN_WIDTH, row=header)
            data = results[key] if item is None else results[key][:, item]
            for k, i in enumerate(rows):
                value = float(data[i])
                ws.write_formula(header + 3 + k, c,
                                 f"={quote_sheet(sheet)}!{xl_rowcol_to_cell(FIRST_ROW + i, source_col)}",
                                 fmt, value if math.isfinite(value) else "")
        header_points = fit_header_rows(ws, header)
        widest = max(widest, len(columns))
        blocks.append((row, (len(rows) + 5) * ROW_POINTS + header_points))
        tallest = max(tallest, blocks[-1][1])
        row = header + 3 + len(rows) + 1
    ws.set_column(0, 0, 10)
    ws.set_column(1, widest, COLUMN_WIDTH)
    # a narrow table: a portrait page holds its columns larger
    portrait = widest <= _capacity(PORTRAIT_WIDTH_PX, _scale(tallest, PORTRAIT_HEIGHT_PT))
    width, height = (PORTRAIT_WIDTH_PX, PORTRAIT_HEIGHT_PT) if portrait else \
        (PAGE_WIDTH_PX, PAGE_HEIGHT_PT)
    scale = _scale(tallest, height)
    capacity = _capacity(width, scale)
    per_page = math.ceil(widest / math.ceil(widest / capacity))    # pages alike
    breaks = list(range(1 + per_page, widest + 1, per_page))
    ws.set_v_pagebreaks(breaks)
    for column in breaks:                 # each page to the right: the whole title again
        ws.write(0, column, f"{title} {CONTINUED[lang]}", styles.title)
    ws.set_h_pagebreaks(_blocks_kept_whole(blocks, scale, height))
    # the notes wrap across the first page's columns (a page wide even when the table
    # is narrower), so neither they nor the title are cut at the print area's edge
    span = per_page if widest > capacity else capacity
    for note_row, text in notes:
        wrapped_title(ws, note_row, text, [10] + [COLUMN_WIDTH] * span, styles.subtitle_wrap)
    ws.repeat_columns(0, 0)
    ws.freeze_panes(0, 1)
    ws.set_paper(A4)
    if portrait:
        ws.set_portrait()
    else:
        ws.set_landscape()
    ws.set_margins(left=0.4, right=0.4, top=0.5, bottom=0.5)
    ws.set_print_scale(scale)
    ws.print_area(0, 0, row, max(widest, span))
    return ws


def _blocks_kept_whole(blocks, scale, height=PAGE_HEIGHT_PT):
    """Rows where a page must begin so that no block of ``blocks`` (first row, height
    in points) is split, every block fitting on a page ``height`` points tall at
    ``scale`` (%): a table's last rows no longer print alone on a page of their own."""
    room, used, breaks = height * 100 / scale, ROW_POINTS, []     # the title
    for first, height in blocks:
        if used + height > room and used > ROW_POINTS:
            breaks.append(first)
            used = 0
        used += height
    return breaks


def _scale(points, height=PAGE_HEIGHT_PT):
    """A print scale that fits a block ``points`` tall on one page ``height`` tall."""
    return max(40, min(100, int(100 * height / points)))


def _capacity(width, scale):
    """Columns of the table (after the angle) a page ``width`` pixels wide holds at
    ``scale`` (%)."""
    return max(1, int((width * 100 / scale - 75) / (COLUMN_WIDTH * 7 + 5)))
