"""A quantity sheet: crank-angle column, formula columns, input tables and a chart."""
import math

from xlsxwriter.utility import xl_rowcol_to_cell

from workbook.formulas import fill, quote_sheet
from workbook.writer.charts import add_quantity_chart
from workbook.writer.fast_sheet import FastWorksheet
from workbook.writer.layout import FIRST_ROW, label, unit_text

COLUMN_WIDTH = 15


def cached(value):
    """The cached result xlsxwriter stores: a number, or '' where numpy gives NaN."""
    value = float(value)
    return "" if math.isnan(value) else value


def _headers(ws, col, item, unit, layout, styles, width=COLUMN_WIDTH):
    ws.write(FIRST_ROW - 3, col, label(item, layout.lang), styles.header)
    ws.write(FIRST_ROW - 2, col, label(item, layout.other), styles.header_other)
    ws.write(FIRST_ROW - 1, col, f"[{unit_text(unit)}]", styles.unit)
    ws.set_column(col, col, width)


def write_series_sheet(book, sheet_spec, layout, results, styles):
    spec, locator = layout.spec, layout.locator
    name = layout.sheet_name[sheet_spec.key]
    ws = book.add_worksheet(name, worksheet_class=FastWorksheet)
    ws.write(0, 0, label(sheet_spec, layout.lang, "title_"), styles.title)
    ws.write(1, 0, label(sheet_spec, layout.other, "title_"), styles.subtitle)
    ws.set_row(FIRST_ROW - 3, 42)
    ws.set_row(FIRST_ROW - 2, 42)
    ws.freeze_panes(FIRST_ROW, 1)
    ws.set_paper(9)                       # A4, landscape, table and chart one page wide
    ws.set_landscape()
    ws.fit_to_pages(1, 0)
    ws.repeat_rows(FIRST_ROW - 3, FIRST_ROW - 1)

    # The grid column: values (or its formulas) on the grid's first sheet,
    # references to them elsewhere.
    grid_q = spec.quantity[sheet_spec.grid]
    grid = results[grid_q.key]
    _headers(ws, 0, grid_q, grid_q.unit, layout, styles, width=11)
    angle_format = styles.number(grid_q.unit, grid_q.format)
    if layout.master[grid_q.key] == sheet_spec.key:
        if grid_q.formula is None:
            for i, angle in enumerate(grid):
                ws.write_number(FIRST_ROW + i, 0, float(angle), angle_format)
        else:
            template = locator.series_formula(grid_q.formula, name, grid_q.key)
            for i, angle in enumerate(grid):
                ws.write_formula(FIRST_ROW + i, 0, fill(template, FIRST_ROW + i, i),
                                 angle_format, cached(angle))
    else:
        master = quote_sheet(layout.sheet_name[layout.master[grid_q.key]])
        for i, angle in enumerate(grid):
            row = FIRST_ROW + i + 1
            ws.write_formula(FIRST_ROW + i, 0, f"={master}!$A{row}", angle_format, cached(angle))

    for col, quantity in enumerate(sheet_spec.columns, start=1):
        _headers(ws, col, quantity, quantity.unit, layout, styles)
        template = locator.series_formula(quantity.formula, name, sheet_spec.grid)
        first = locator.series_formula(quantity.first, name, sheet_spec.grid) \
            if quantity.first else template
        fmt = styles.number(quantity.unit, quantity.format)
        values = results[quantity.key]
        for i in range(len(grid)):
            row = FIRST_ROW + i
            ws.write_formula(row, col, fill(first if i == 0 else template, row, i), fmt,
                             cached(values[i]))

    for table in layout.tables_on(sheet_spec.key):
        _write_input_table(ws, table, layout, results, styles)

    if not sheet_spec.chart:
        return ws
    x_range = f"{quote_sheet(name)}!$A${FIRST_ROW + 1}:$A${layout.last_row(sheet_spec.grid) + 1}"
    chart = add_quantity_chart(book, sheet_spec, layout, x_range)
    chart_col = len(sheet_spec.columns) + 2
    for table in layout.tables_on(sheet_spec.key):
        chart_col = max(chart_col, layout.table_start[table.key] + len(table.columns) + 1)
    # Anchored below the header rows, which repeat on every printed page.
    ws.insert_chart(FIRST_ROW, chart_col, chart, {"x_offset": 10})
    return ws


def _write_input_table(ws, table, layout, results, styles):
    """Editable input columns (e.g. a measured trace), named p_<key> over the capacity."""
    name = layout.sheet_name[table.sheet]
    start = layout.table_start[table.key]
    for offset, column in enumerate(table.columns):
        col = start + offset
        _headers(ws, col, column, column.unit, layout, styles)
        values = results.get(column.key, [])
        fmt = styles.number(column.unit, role="input")
        for i in range(layout.table_capacity[table.key]):
            if i < len(values):
                ws.write_number(FIRST_ROW + i, col, float(values[i]), fmt)
            else:
                ws.write_blank(FIRST_ROW + i, col, None, fmt)
        first = xl_rowcol_to_cell(FIRST_ROW, col, row_abs=True, col_abs=True)
        last = xl_rowcol_to_cell(FIRST_ROW + layout.table_capacity[table.key] - 1, col,
                                 row_abs=True, col_abs=True)
        layout.defined_names[f"p_{column.key}"] = f"={quote_sheet(name)}!{first}:{last}"
