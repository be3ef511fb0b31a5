"""A quantity sheet: the grid column, formula columns (a block of columns for a
per-item series), input tables and the sheet's charts."""
import math


from crankbook.spec.formulas import ROW, quote_sheet
from crankbook.writer import live_text
from crankbook.writer.charts import add_chart, chart_column_width
from crankbook.writer.fast_sheet import FastWorksheet
from crankbook.writer.layout import FIRST_ROW, label, step_text, unit_text
from crankbook.writer.print_setup import NO_PRINT, landscape_report, line_height, text_lines

COLUMN_WIDTH = 15


def cached(value):
    """The cached result stored with a formula: a number, or '' where numpy gives NaN
    or ±inf (Excel repairs a file that caches an infinity)."""
    value = float(value)
    return value if math.isfinite(value) else ""


def headers(ws, col, words, unit, layout, styles, width=COLUMN_WIDTH, row=FIRST_ROW - 3):
    """Three header rows: the label in the sheet's language, in the other, the unit
    (``fit_header_rows`` then makes the first two as tall as their longest label)."""
    live_text.write_text(ws, row, col, words[0], styles.header, layout)
    live_text.write_text(ws, row + 1, col, words[1], styles.header_other, layout)
    ws.write(row + 2, col, f"[{unit_text(unit)}]", styles.unit)
    ws.set_column(col, col, width)
    if not hasattr(ws, "header_lines"):
        ws.header_lines = {}                # header row -> lines of its two label rows
    tallest = ws.header_lines.get(row, (3, 3))
    ws.header_lines[row] = (max(tallest[0], text_lines(live_text.cached(words[0], layout), width,
                                                       bold=True)),
                            max(tallest[1], text_lines(live_text.cached(words[1], layout), width)))


def fit_header_rows(ws, row=FIRST_ROW - 3):
    """The two label rows of the headers at ``row`` as tall as their longest label
    (three lines at least, so neighbouring tables line up); their height in points."""
    heights = [lines * line_height() + 2
               for lines in getattr(ws, "header_lines", {}).get(row, (3, 3))]
    for offset, height in enumerate(heights):
        ws.set_row(row + offset, height)
    return sum(heights)


def _words(item, layout, suffix=""):
    return (label(item, layout.lang) + suffix, label(item, layout.other) + suffix)


def write_series_sheet(book, sheet_spec, layout, results, styles):
    spec, locator = layout.spec, layout.locator
    name = layout.sheet_name[sheet_spec.key]
    ws = book.add_worksheet(name, worksheet_class=FastWorksheet)
    ws.write(0, 0, label(sheet_spec, layout.lang, "title_"), styles.title)
    ws.write(1, 0, label(sheet_spec, layout.other, "title_"), styles.subtitle)
    ws.freeze_panes(FIRST_ROW, 1)

    grid_q = spec.quantity[sheet_spec.grid]
    grid = results[grid_q.key]
    headers(ws, 0, _words(grid_q, layout), grid_q.unit, layout, styles, width=11)
    angle_format = styles.number(grid_q.unit, grid_q.format)
    if layout.master[grid_q.key] == sheet_spec.key:
        if grid_q.formula is None:
            for i, angle in enumerate(grid):
                ws.write_number(FIRST_ROW + i, 0, float(angle), angle_format)
        else:
            template = locator.series_formula(grid_q.nodes, name, grid_q.key)
            ws.write_formula_column(FIRST_ROW, 0, template, None, angle_format, grid)
    else:
        master = quote_sheet(layout.sheet_name[layout.master[grid_q.key]])
        ws.write_formula_column(FIRST_ROW, 0, f"={master}!$A{ROW}", None, angle_format, grid)

    for quantity in sheet_spec.columns:
        _write_column(ws, quantity, layout, results, styles, name, len(grid))

    last_col = max((p.col + p.count - 1 for k, p in layout.places.items()
                    if p.sheet == name), default=0)
    for table in layout.tables_on(sheet_spec.key):
        _write_input_table(ws, table, layout, results, styles)
    fit_header_rows(ws)
    chart_col = layout.chart_column.get(sheet_spec.key, last_col + 2)
    row = FIRST_ROW
    for chart_spec in sheet_spec.charts:
        chart = add_chart(book, chart_spec, sheet_spec, layout, results, ws, styles)
        # Anchored below the header rows, which repeat on every printed page, inside
        # one column wider than any chart: no engine's column widths can stretch it.
        ws.insert_chart(row, chart_col, chart, {"x_offset": 10, "y_offset": 4})
        row += math.ceil((chart.height + 20) / 20)
    if sheet_spec.charts:
        ws.set_column(chart_col, chart_col, chart_column_width(sheet_spec.charts))
    step = sheet_spec.print_step or (spec.print_step if sheet_spec.grid == spec.grid.key
                                     else None)
    if step:
        _group_between_print_steps(ws, grid, step, layout, styles, sheet_spec.grid)
    landscape_report(ws, layout, sheet_spec, len(grid), last_col, chart_col)
    # The sheet is for the screen: its columns print on the results table at the print
    # step, its charts on the Charts sheet.  A print area on an empty cell makes Excel
    # and LibreOffice skip it when the whole workbook prints (select the table and
    # print the selection to print it alone).
    ws.print_area(*NO_PRINT)
    return ws


def _group_between_print_steps(ws, grid, step, layout, styles, grid_key):
    """Rows between multiples of ``step`` are grouped and folded (click + to show
    them): the sheet opens and prints at the coarser step; charts plot every row."""
    ratio = [float(a) / step for a in grid]
    folded = [i for i, r in enumerate(ratio) if abs(r - round(r)) > 1e-9]
    if not folded:
        return
    for i in folded:
        ws.set_row(FIRST_ROW + i, None, None, {"level": 1, "hidden": True})
    ws.outline_settings(True, False, True, False)
    shown = step_text(step, layout.spec.quantity[grid_key].unit)
    note = (f"每 {shown} 一行；其间各行已折叠（点左侧 + 展开），图表画出全部各行" if layout.lang == "zh"
            else f"one row every {shown}; the rows between are folded (click + at the left to "
                 f"show them); the charts plot every row")
    ws.write(0, 8, note, styles.subtitle)


def _write_column(ws, quantity, layout, results, styles, sheet_name, rows):
    place = layout.places[quantity.key]
    fmt = styles.number(quantity.unit, quantity.format)
    values = results[quantity.key]
    items = range(1, place.count + 1) if quantity.items else [None]
    for offset, item in enumerate(items):
        col = place.col + offset
        if item is None:
            words = _words(quantity, layout)
        else:
            words = tuple(f"{label(quantity, lang)} — "
                          f"{layout.item_label(quantity.items, lang, item, quantity.item_word)}"
                          for lang in (layout.lang, layout.other))
        headers(ws, col, words, quantity.unit, layout, styles)
        template = layout.series_template(quantity, sheet_name, item)
        first = layout.series_template(quantity, sheet_name, item, first=True)
        column = values if item is None else values[:, offset]
        ws.write_formula_column(FIRST_ROW, col, template, first, fmt, column[:rows])


def _write_input_table(ws, table, layout, results, styles):
    """Editable input columns (e.g. a measured trace), named p_<key> over the capacity."""
    capacity = layout.table_capacity[table.key]
    for column in table.columns:
        place = layout.places[column.key]
        values = results.get(column.key, [])
        fmt = styles.number(column.unit, role="input")
        for offset in range(place.width):
            col = place.col + offset
            words = _words(column, layout)
            if column.items:
                words = tuple(f"{w} — {layout.item_label(column.items, lang, offset + 1)}"
                              for w, lang in zip(words, (layout.lang, layout.other)))
            headers(ws, col, words, column.unit, layout, styles)
            data = [row[offset] for row in values] if column.items else values
            for i in range(capacity):
                if i < len(data):
                    ws.write_number(FIRST_ROW + i, col, float(data[i]), fmt)
                else:
                    ws.write_blank(FIRST_ROW + i, col, None, fmt)
