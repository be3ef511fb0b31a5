"""Rows of named scalar results (key, value, unit, labels), and sheets made of them."""
from xlsxwriter.utility import xl_rowcol_to_cell

from workbook.formulas import quote_sheet
from workbook.writer.layout import label, unit_text
from workbook.writer.series_sheet import cached


def write_scalar_rows(ws, row, quantities, layout, results, styles, sheet_name):
    """Write one row per quantity from ``row``; return the next free row.

    A quantity without a formula is a decision cell (e.g. for Excel's Solver): its
    numpy value is written as an editable input.
    """
    for quantity in quantities:
        ws.write(row, 0, quantity.key, styles.key)
        if quantity.formula is None:
            ws.write_number(row, 1, float(results[quantity.key]),
                            styles.number(quantity.unit, quantity.format, role="input"))
        else:
            ws.write_formula(row, 1, layout.locator.scalar_formula(quantity.formula),
                             styles.number(quantity.unit, quantity.format),
                             cached(results[quantity.key]))
        ws.write(row, 2, unit_text(quantity.unit))
        ws.write(row, 3, quantity.zh, styles.text)
        ws.write(row, 4, quantity.en, styles.text)
        layout.defined_names[f"q_{quantity.key}"] = \
            "=" + quote_sheet(sheet_name) + "!" + xl_rowcol_to_cell(row, 1, True, True)
        row += 1
    return row


def write_scalar_sheet(book, sheet_spec, layout, results, styles):
    name = layout.sheet_name[sheet_spec.key]
    ws = book.add_worksheet(name)
    for col, width in enumerate([30, 16, 9, 60, 70]):
        ws.set_column(col, col, width)
    ws.write(0, 0, label(sheet_spec, layout.lang, "title_"), styles.title)
    ws.write(1, 0, label(sheet_spec, layout.other, "title_"), styles.subtitle)
    headers = [("键", "Key"), ("数值", "Value"), ("单位", "Unit"), ("说明", "Description (zh)"),
               ("Description", "Description (en)")]
    for col, pair in enumerate(headers):
        ws.write(3, col, pair[0] if layout.lang == "zh" else pair[1], styles.header)
    write_scalar_rows(ws, 4, sheet_spec.columns, layout, results, styles, name)
    ws.freeze_panes(4, 0)
    ws.set_paper(9)
    ws.set_landscape()
    ws.fit_to_pages(1, 0)
    return ws
