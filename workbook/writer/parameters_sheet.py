"""The Parameters sheet: named inputs with validation, input checks with a status
cell that says in words what is wrong, and the derived constants."""
from xlsxwriter.utility import xl_rowcol_to_cell

from workbook.formulas import quote_sheet
from workbook.writer.layout import label, unit_text
from workbook.writer.scalar_sheet import write_scalar_rows

HEADERS = {
    "inputs": [("键", "Key"), ("数值", "Value"), ("单位", "Unit"), ("说明", "Description (zh)"),
               ("Description", "Description (en)"), ("允许范围", "Allowed")],
    "derived": ("计算常数（公式）", "Derived constants (formulas)"),
    "checks": ("输入检查（1 = 不满足）", "Input checks (1 = broken)"),
}
STATUS_OK = ("✓ 输入有效：所有表格与图表已按这些参数计算",
             "inputs valid: every table and chart follows these parameters")
BOUND_WORDS = {"zh": "须为", "en": "must be"}


def _both(pair, lang):
    zh, en = pair
    return f"{zh} / {en}" if lang == "zh" else f"{en} / {zh}"


def _bound_condition(parameter, ref):
    """Excel condition that is true when the value in ``ref`` breaks its bounds."""
    if parameter.kind == "flag":
        return f"AND({ref}<>0,{ref}<>1)"
    parts = []
    if parameter.min is not None:
        parts.append(f"{ref}{'<=' if parameter.min_open else '<'}{parameter.min!r}")
    if parameter.max is not None:
        parts.append(f"{ref}{'>=' if parameter.max_open else '>'}{parameter.max!r}")
    return f"OR({','.join(parts)})"


def write_parameters_sheet(book, layout, values, results, preset, styles):
    spec, lang, locator = layout.spec, layout.lang, layout.locator
    name = layout.sheet_name["parameters"]
    ws = book.add_worksheet(name)
    sheet_ref = quote_sheet(name)
    names = layout.defined_names

    def define(key_name, row, col):
        names[key_name] = "=" + sheet_ref + "!" + xl_rowcol_to_cell(row, col, True, True)

    for col, width in enumerate([28, 14, 9, 60, 70, 24]):
        ws.set_column(col, col, width)
    ws.write(0, 0, f"{label(spec, lang)} — {_both(('参数', 'Parameters'), lang)}", styles.title)
    ws.write(1, 0, f"{_both(('预设', 'Preset'), lang)}: {preset['name']} — {preset[lang]}",
             styles.subtitle)
    ws.write(2, 0, _both(("状态", "Status"), lang), styles.group)
    status_row = 2
    ws.set_row(status_row, 36)
    ws.write(4, 0, _both(("黄色单元格可修改；所有结果随之重算。", "Yellow cells are inputs: "
                          "edit them and every result recomputes."), lang), styles.subtitle)

    row = 6
    for col, pair in enumerate(HEADERS["inputs"]):
        ws.write(row, col, pair[0] if lang == "zh" else pair[1], styles.header)
    row += 1
    input_cells = {}
    for group, words in spec.groups.items():
        ws.merge_range(row, 0, row, 5, _both((words["zh"], words["en"]), lang), styles.group)
        row += 1
        for parameter in (p for p in spec.parameters if p.group == group):
            ws.write(row, 0, parameter.key, styles.key)
            fmt = styles.number(parameter.unit, "0" if parameter.kind == "flag" else "General",
                                role="input")
            ws.write_number(row, 1, values[parameter.key], fmt)
            ws.write(row, 2, unit_text(parameter.unit))
            ws.write(row, 3, parameter.zh, styles.text)
            ws.write(row, 4, parameter.en, styles.text)
            ws.write(row, 5, parameter.bounds_text())
            cell = xl_rowcol_to_cell(row, 1)
            ws.data_validation(row, 1, row, 1, {
                "validate": "custom",
                "value": f"=AND(ISNUMBER({cell}),NOT({_bound_condition(parameter, cell)}))",
                "input_title": parameter.key[:32],
                "input_message": f"{parameter.zh}\n{parameter.en}\n{parameter.bounds_text()}"[:255],
                "error_title": _both(("输入无效", "Invalid input"), lang)[:32],
                "error_message": f"{parameter.key} {BOUND_WORDS['en']} "
                                 f"{parameter.bounds_text()}"[:255],
            })
            define(f"p_{parameter.key}", row, 1)
            input_cells[parameter.key] = row
            row += 1

    row += 1
    ws.merge_range(row, 0, row, 5, _both(HEADERS["derived"], lang), styles.group)
    row += 1
    row = write_scalar_rows(ws, row, spec.scalars, layout, results, styles, name)

    row += 1
    ws.merge_range(row, 0, row, 5, _both(HEADERS["checks"], lang), styles.group)
    row += 1
    first_check = row
    for parameter in spec.parameters:
        ref = f"p_{parameter.key}"
        ws.write(row, 0, f"{parameter.key}", styles.key)
        ws.write_formula(row, 1, f"=IF(ISNUMBER({ref}),IF({_bound_condition(parameter, ref)},1,0),1)",
                         styles.number("-", "0"), 0)
        ws.write(row, 3, f"{parameter.zh}：{BOUND_WORDS['zh']}数值 {parameter.bounds_text()}",
                 styles.text)
        ws.write(row, 4, f"{parameter.key} {BOUND_WORDS['en']} a number {parameter.bounds_text()}",
                 styles.text)
        row += 1
    for rule in spec.rules:
        ws.write(row, 0, rule.key, styles.key)
        condition = locator.scalar_formula(rule.fails, guard=False)[1:]
        ws.write_formula(row, 1, f"=IFERROR(IF({condition},1,0),1)", styles.number("-", "0"), 0)
        ws.write(row, 3, rule.zh, styles.text)
        ws.write(row, 4, rule.en, styles.text)
        row += 1
    last_check = row - 1
    flags = f"$B${first_check + 1}:$B${last_check + 1}"
    msg_primary = f"${'D' if lang == 'zh' else 'E'}${first_check + 1}:${'D' if lang == 'zh' else 'E'}${last_check + 1}"
    msg_other = f"${'E' if lang == 'zh' else 'D'}${first_check + 1}:${'E' if lang == 'zh' else 'D'}${last_check + 1}"
    ws.write(row, 0, "inputs_valid", styles.key)
    ws.write_formula(row, 1, f"=IF(SUM({flags})=0,1,0)", styles.number("-", "0"), 1)
    ws.write(row, 3, "1 = 全部输入有效（所有公式以此为前提）", styles.text)
    ws.write(row, 4, "1 = all inputs valid (every formula is guarded by this cell)", styles.text)
    define("q_inputs_valid", row, 1)

    ok_text = _both(STATUS_OK, lang)
    status = (f'=IF(SUM({flags})=0,"{ok_text}","✗ "&INDEX({msg_primary},MATCH(1,{flags},0))'
              f'&" / "&INDEX({msg_other},MATCH(1,{flags},0))'
              f'&IF(SUM({flags})>1," (+"&(SUM({flags})-1)&")",""))')
    ws.merge_range(status_row, 1, status_row, 5, "", styles.status)
    ws.write_formula(status_row, 1, status, styles.status, ok_text)
    define("q_input_status", status_row, 1)
    ws.conditional_format(status_row, 1, status_row, 5, {
        "type": "formula", "criteria": "=q_inputs_valid=1", "format": styles.status_ok})
    ws.conditional_format(status_row, 1, status_row, 5, {
        "type": "formula", "criteria": "=q_inputs_valid<>1", "format": styles.status_bad})
    ws.conditional_format(first_check, 1, last_check, 1, {
        "type": "cell", "criteria": "==", "value": 1, "format": styles.status_bad})
    ws.freeze_panes(3, 0)
    ws.set_paper(9)
    ws.set_landscape()
    ws.fit_to_pages(1, 0)
    ws.activate()
    return ws
