"""The Summary sheet: extremes of each quantity with their crank angles, and the
cycle results (mean torque, indicated work and power)."""
from xlsxwriter.utility import xl_rowcol_to_cell

from workbook.formulas import quote_sheet
from workbook.writer.layout import label, unit_text
from workbook.writer.series_sheet import cached

COLUMNS = [("量", "Quantity"), ("Quantity", "量"), ("单位", "Unit"), ("最大值", "Maximum"),
           ("最大值处 α [°]", "α at maximum [°]"), ("最小值", "Minimum"),
           ("最小值处 α [°]", "α at minimum [°]")]


def write_summary_sheet(book, layout, results, styles):
    spec, lang, locator = layout.spec, layout.lang, layout.locator
    name = layout.sheet_name["summary"]
    ws = book.add_worksheet(name)
    sheet_ref = quote_sheet(name)

    def put(row, col, key):
        quantity = spec.quantity[key]
        ws.write_formula(row, col, locator.scalar_formula(quantity.formula),
                         styles.number(quantity.unit, quantity.format), cached(results[key]))
        layout.defined_names[f"q_{key}"] = \
            "=" + sheet_ref + "!" + xl_rowcol_to_cell(row, col, True, True)

    for col, width in enumerate([56, 44, 9, 14, 16, 14, 16]):
        ws.set_column(col, col, width)
    ws.write(0, 0, f"{label(spec, lang)} — {'汇总' if lang == 'zh' else 'Summary'}", styles.title)
    ws.write(1, 0, "所有数值均为公式 / every value is a formula", styles.subtitle)
    row = 3
    for col, pair in enumerate(COLUMNS):
        ws.write(row, col, pair[0] if lang == "zh" else pair[1], styles.header)
    row += 1
    series = [q for s in spec.sheets for q in s.columns if q.summary]
    for quantity in series:
        ws.write(row, 0, label(quantity, lang), styles.text)
        ws.write(row, 1, label(quantity, layout.other), styles.text)
        ws.write(row, 2, unit_text(quantity.unit))
        for col, stat in enumerate(["max", "max_angle", "min", "min_angle"], start=3):
            put(row, col, f"{quantity.key}_{stat}")
        row += 1

    row += 1
    ws.merge_range(row, 0, row, 6, "循环结果 / Cycle results" if lang == "zh"
                   else "Cycle results / 循环结果", styles.group)
    row += 1
    for quantity in spec.results:
        ws.write(row, 0, label(quantity, lang), styles.text)
        ws.write(row, 1, label(quantity, layout.other), styles.text)
        ws.write(row, 2, unit_text(quantity.unit))
        put(row, 3, quantity.key)
        row += 1
    ws.freeze_panes(4, 1)
    ws.set_paper(9)
    ws.set_landscape()
    ws.fit_to_pages(1, 0)
    return ws
