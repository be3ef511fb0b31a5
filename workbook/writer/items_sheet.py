"""An items sheet: one row per item (cylinder, throw, stage, gear, …), the per-item
inputs (yellow, validated) and the per-item results and checks."""
from crankbook.writer.charts import add_chart
from crankbook.writer.layout import FIRST_ROW, label
from crankbook.writer.parameters_sheet import input_cell, validation
from crankbook.writer.print_setup import landscape_page
from crankbook.writer.scalar_sheet import write_formula_cell
from crankbook.writer.series_sheet import headers


def write_items_sheet(book, plan, layout, values, results, styles):
    spec = layout.spec
    sheet = plan.sheet
    name = layout.sheet_name[sheet.key]
    axis = spec.axis[sheet.axis]
    count = layout.axis_sizes[sheet.axis]
    ws = book.add_worksheet(name)
    ws.write(0, 0, label(sheet, layout.lang, "title_"), styles.title)
    ws.write(1, 0, label(sheet, layout.other, "title_"), styles.subtitle)
    ws.set_row(FIRST_ROW - 3, 42)
    ws.set_row(FIRST_ROW - 2, 42)
    headers(ws, 0, (label(axis, layout.lang), label(axis, layout.other)), "-", layout, styles,
            width=12)
    for i in range(count):
        ws.write(FIRST_ROW + i, 0, axis.label(layout.lang, i + 1), styles.key)
    for parameter in plan.inputs:
        col = layout.places[parameter.key].col
        headers(ws, col, (label(parameter, layout.lang), label(parameter, layout.other)),
                parameter.unit, layout, styles, width=18)
        for i, value in enumerate(values[parameter.key]):
            input_cell(ws, FIRST_ROW + i, col, parameter, value, styles)
            validation(ws, FIRST_ROW + i, col, parameter, layout.lang)
    for quantity in plan.columns:
        col = layout.places[quantity.key].col
        headers(ws, col, (label(quantity, layout.lang), label(quantity, layout.other)),
                quantity.unit, layout, styles, width=18)
        for i in range(count):
            write_formula_cell(ws, FIRST_ROW + i, col, quantity, layout, results, styles, name,
                               item=i + 1, value=results[quantity.key][i])
    for index, chart_spec in enumerate(sheet.charts):
        chart = add_chart(book, chart_spec, sheet, layout, results)
        ws.insert_chart(FIRST_ROW + count + 2 + index * 24, 1, chart)
    ws.freeze_panes(FIRST_ROW, 1)
    landscape_page(ws)
    ws.repeat_rows(FIRST_ROW - 3, FIRST_ROW - 1)
    return ws
