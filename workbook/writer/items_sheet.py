"""An items sheet: one row per item (cylinder, throw, stage, gear, …), the per-item
inputs (yellow, validated) and the per-item results and checks."""
import math

from crankbook.writer import live_text
from crankbook.writer.charts import add_chart
from crankbook.writer.layout import FIRST_ROW, label
from crankbook.writer.parameters_sheet import input_cell, validation
from crankbook.writer.print_setup import (format_words_width, key_width, landscape_page,
                                         wrapped_title)
from crankbook.writer.scalar_sheet import write_formula_cell
from crankbook.writer.series_sheet import fit_header_rows, headers
from crankbook.writer.styles import in_language


def write_items_sheet(book, plan, layout, values, results, styles):
    spec = layout.spec
    sheet = plan.sheet
    name = layout.sheet_name[sheet.key]
    axis = spec.axis[sheet.axis]
    count = layout.axis_sizes[sheet.axis]
    ws = book.add_worksheet(name)
    last_col = max([layout.places[p.key].col for p in plan.inputs] +
                   [layout.places[q.key].col for q in plan.columns] + [0])
    labels = [layout.item_label(sheet.axis, layout.lang, i + 1, sheet.item_word)
              for i in range(count)]
    widths = [key_width([live_text.cached(text, layout) for text in labels], 12)] + \
        [COLUMN_WIDTH] * last_col
    folded = {layout.places[q.key].col for q in plan.columns if q.fold}
    pages_wide = math.ceil(sum(w * 7 + 5 for c, w in enumerate(widths) if c not in folded)
                           / PAGE_PIXELS)
    # a table printed several pages wide: the titles wrap within its first page's share
    # of the printed columns (a merged cell cut by a page break loses its text; a folded
    # column inside the merge takes no width on paper)
    share, shown, first_page = max(2, (len(widths) - len(folded)) // pages_wide), 0, []
    for col, width in enumerate(widths):
        if shown >= share:
            break
        first_page.append(0 if col in folded else width)
        shown += col not in folded
    wrapped_title(ws, 0, label(sheet, layout.lang, "title_"), first_page, styles.title_wrap)
    wrapped_title(ws, 1, label(sheet, layout.other, "title_"), first_page, styles.subtitle_wrap)
    headers(ws, 0, (label(axis, layout.lang), label(axis, layout.other)), "-", layout, styles,
            width=widths[0])
    for i, text in enumerate(labels):
        live_text.write_text(ws, FIRST_ROW + i, 0, text, styles.key, layout)
    for parameter in plan.inputs:
        col = layout.places[parameter.key].col
        headers(ws, col, (label(parameter, layout.lang), label(parameter, layout.other)),
                parameter.unit, layout, styles, width=COLUMN_WIDTH)
        for i, value in enumerate(values[parameter.key]):
            input_cell(ws, FIRST_ROW + i, col, parameter, value, styles)
            validation(ws, FIRST_ROW + i, col, parameter, layout.lang)
    for quantity in plan.columns:
        col = layout.places[quantity.key].col
        headers(ws, col, (label(quantity, layout.lang), label(quantity, layout.other)),
                quantity.unit, layout, styles, width=max(
                    COLUMN_WIDTH, math.ceil(format_words_width(in_language(
                        quantity.format or "", layout.lang)))))
        if quantity.fold:
            # a working column (a chart's helper, an interpolation index): grouped and
            # folded, the outline's [+] opens it; it does not print
            ws.set_column(col, col, COLUMN_WIDTH, None, {"level": 1, "hidden": True})
        for i in range(count):
            write_formula_cell(ws, FIRST_ROW + i, col, quantity, layout, results, styles, name,
                               item=i + 1, value=results[quantity.key][i])
    fit_header_rows(ws)
    row = FIRST_ROW + count + 2
    for chart_spec in sheet.charts:
        chart = add_chart(book, chart_spec, sheet, layout, {**values, **results}, ws, styles)
        ws.insert_chart(row, 1, chart)
        row += math.ceil((chart.height + 20) / 20)
    ws.freeze_panes(FIRST_ROW, 1)
    landscape_page(ws)
    ws.repeat_rows(FIRST_ROW - 3, FIRST_ROW - 1)
    ws.repeat_columns(0, 0)
    # the table prints (its charts print on the Charts sheet), as many pages wide as
    # keep it at about two thirds of its size or more
    ws.fit_to_pages(pages_wide, 1)
    ws.print_area(0, 0, FIRST_ROW + count - 1, last_col)
    return ws


COLUMN_WIDTH = 13          # characters; the headers wrap
PAGE_PIXELS = 1560         # a landscape page's width at about 67 %
