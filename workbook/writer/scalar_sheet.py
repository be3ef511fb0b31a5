"""Rows of named scalar results (key, value, unit, labels), and sheets made of them."""
from crankbook.writer.layout import SCALAR_FIRST_ROW, label, unit_text
from crankbook.writer.print_setup import key_width, landscape_page, wrapped_texts
from crankbook.writer.series_sheet import cached


WIDTHS = [30, 16, 9, 60, 70]        # key, value, unit, 中文, English


def write_formula_cell(ws, row, col, quantity, layout, results, styles, sheet_name,
                       item=None, value=None):
    """The formula cell of a quantity (an array formula where the spec says so), with
    its numpy value cached; a quantity without a formula is an editable decision cell."""
    fmt = styles.number(quantity.unit, quantity.format,
                        role="input" if quantity.formula is None else "output")
    value = results[quantity.key] if value is None else value
    if quantity.formula is None:
        ws.write_number(row, col, float(value), fmt)
        return
    guard = quantity.guard if quantity.kind != "rule" else None
    formula = layout.locator.scalar_formula(quantity.nodes, sheet_name, item=item,
                                            axis=quantity.items, guard=guard)
    if quantity.kind == "rule":
        formula = "=" + rule_wrapper(layout, quantity, formula[1:])
    if quantity.array:
        ws.write_array_formula(row, col, row, col, "{" + formula + "}", fmt, cached(value))
    else:
        ws.write_formula(row, col, formula, fmt, cached(value))
    if quantity.verdict:
        # a pass mark reads at a glance, on screen and on a colour print
        for mark, colour in ((1, styles.status_ok), (0, styles.status_bad)):
            ws.conditional_format(row, col, row, col, {"type": "cell", "criteria": "==",
                                                       "value": mark, "format": colour})
    if quantity.target is not None:
        # a factor against what it is asked to reach, live: the target may be an input
        target = quantity.target if not isinstance(quantity.target, str) \
            else f"={layout.locator.name(quantity.target)}"
        for criteria, colour in ((">=", styles.status_ok), ("<", styles.status_bad)):
            ws.conditional_format(row, col, row, col, {"type": "cell", "criteria": criteria,
                                                       "value": target, "format": colour})


def rule_wrapper(layout, rule, condition):
    """1 when the inputs break the rule, also when the condition cannot be evaluated
    (an unguarded quantity it reads is blank or an error)."""
    spec = layout.spec
    blanks = sorted({ref for ref in rule.references()
                     if ref in spec.quantity and not spec.quantity[ref].is_series
                     and not spec.quantity[ref].items and spec.quantity[ref].kind != "rule"})
    body = f"IFERROR(IF({condition},1,0),1)"
    if blanks:
        tests = ",".join(f"ISNUMBER(q_{key})" for key in blanks)
        body = f"IF(AND({tests}),{body},1)"
    return body


def write_scalar_rows(ws, row, quantities, layout, results, styles, sheet_name):
    """Write one row per quantity from ``row``; return the next free row."""
    for quantity in quantities:
        ws.write(row, 0, quantity.key, styles.key)
        write_formula_cell(ws, row, 1, quantity, layout, results, styles, sheet_name)
        ws.write(row, 2, unit_text(quantity.unit), styles.top)
        wrapped_texts(ws, row, {3: (quantity.zh, WIDTHS[3]), 4: (quantity.en, WIDTHS[4])},
                      styles.text)
        row += 1
    return row


def write_scalar_sheet(book, sheet_spec, layout, results, styles):
    name = layout.sheet_name[sheet_spec.key]
    ws = book.add_worksheet(name)
    widths = [key_width((q.key for q in sheet_spec.columns), WIDTHS[0]), *WIDTHS[1:]]
    for col, width in enumerate(widths):
        ws.set_column(col, col, width)
    ws.write(0, 0, label(sheet_spec, layout.lang, "title_"), styles.title)
    ws.write(1, 0, label(sheet_spec, layout.other, "title_"), styles.subtitle)
    headers = [("键", "Key"), ("数值", "Value"), ("单位", "Unit"), ("说明", "Description (zh)"),
               ("Description", "Description (en)")]
    for col, pair in enumerate(headers):
        ws.write(SCALAR_FIRST_ROW - 1, col, pair[0] if layout.lang == "zh" else pair[1],
                 styles.header)
    write_scalar_rows(ws, SCALAR_FIRST_ROW, sheet_spec.columns, layout, results, styles, name)
    ws.freeze_panes(SCALAR_FIRST_ROW, 0)
    landscape_page(ws)
    ws.repeat_rows(SCALAR_FIRST_ROW - 1)
    return ws
