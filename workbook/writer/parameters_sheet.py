"""The Parameters sheet: named inputs with validation, the derived constants, the
input checks, and a status cell that says in words what is wrong."""
from xlsxwriter.utility import xl_col_to_name, xl_rowcol_to_cell

from crankbook.spec.formulas import number
from crankbook.writer.layout import PARAMETER_TABLE_ROW, label, unit_text
from crankbook.writer.print_setup import key_width, landscape_page, wrapped_texts
from crankbook.writer.scalar_sheet import write_formula_cell

HEADERS = {
    "inputs": [("键", "Key"), ("数值", "Value"), ("单位", "Unit"), ("说明", "Description (zh)"),
               ("Description", "Description (en)"), ("允许范围", "Allowed")],
    "derived": ("计算常数（公式）", "Derived constants (formulas)"),
    "checks": ("输入检查（1 = 不满足）", "Input checks (1 = broken)"),
    "gathered": ("不满足的检查（逐行累计）", "Broken checks (gathered row by row)"),
    "notes": ("提示文字（状态单元格与汇总页的提示行引用）",
              "Notes' words (the status cell and the Summary's line read them)"),
}
GATHERED = 6                     # column G, beside the checks: the broken ones' keys so far
STATUS_OK = ("✓ 输入有效：所有表格与图表已按这些参数计算",
             "✓ inputs valid: every table and chart follows these parameters")
BROKEN = ("不满足的规则", "every broken rule")      # more than one: each named by its key


def both(pair, lang):
    zh, en = pair
    return f"{zh} / {en}" if lang == "zh" else f"{en} / {zh}"


def _choice_list(parameter):
    return "{" + ",".join('"' + c + '"' for c in parameter.choices) + "}"


def bound_condition(parameter, ref):
    """Excel condition that is true when the single value in ``ref`` breaks its rule."""
    if parameter.kind == "flag":
        return f"AND({ref}<>0,{ref}<>1)"
    if parameter.kind == "choice":
        return f"ISNA(MATCH({ref},{_choice_list(parameter)},0))"
    parts = [f"{ref}<>INT({ref})"] if parameter.kind == "integer" else []
    if parameter.min is not None:
        parts.append(f"{ref}{'<=' if parameter.min_open else '<'}{number(parameter.min)}")
    if parameter.max is not None:
        parts.append(f"{ref}{'>=' if parameter.max_open else '>'}{number(parameter.max)}")
    return f"OR({','.join(parts)})" if parts else "FALSE"


def _items_bound_condition(parameter, ref, count):
    """True when any of the ``count`` values in ``ref`` is missing or out of bounds."""
    parts = [f"COUNT({ref})<{count}"]
    if parameter.kind == "flag":
        return f"OR(COUNT({ref})<{count},COUNTIF({ref},0)+COUNTIF({ref},1)<{count})"
    if parameter.min is not None:
        parts.append(f'COUNTIF({ref},"{"<=" if parameter.min_open else "<"}{number(parameter.min)}")>0')
    if parameter.max is not None:
        parts.append(f'COUNTIF({ref},"{">=" if parameter.max_open else ">"}{number(parameter.max)}")>0')
    return f"OR({','.join(parts)})"


def input_cell(ws, row, col, parameter, value, styles):
    """A yellow input cell: a number, or the word of a choice parameter."""
    if parameter.kind == "choice":
        ws.write_string(row, col, parameter.choices[int(value) - 1],
                        styles.number("-", "@", role="input"))
        return
    fmt = "0" if parameter.kind in ("flag", "integer") else "General"
    ws.write_number(row, col, float(value), styles.number(parameter.unit, fmt, role="input"))


def validation(ws, row, col, parameter, lang):
    """Data validation of one input cell, with its rule as the prompt."""
    cell = xl_rowcol_to_cell(row, col)
    prompt = f"{parameter.zh}\n{parameter.en}\n{parameter.bounds_text()}"[:255]
    common = {"input_title": parameter.key[:32], "input_message": prompt,
              "error_title": both(("输入无效", "Invalid input"), lang)[:32],
              "error_message": f"{parameter.key} must be {parameter.bounds_text()}"[:255]}
    if parameter.kind == "choice":
        ws.data_validation(row, col, row, col, {"validate": "list",
                                                "source": list(parameter.choices), **common})
        return
    ws.data_validation(row, col, row, col, {
        "validate": "custom",
        "value": f"=AND(ISNUMBER({cell}),NOT({bound_condition(parameter, cell)}))", **common})


WIDTHS = [28, 16, 9, 60, 70, 24]       # key, value, unit, 中文, English, range


def _describe(ws, row, zh, en, styles, allowed=None):
    """The row's two descriptions (and a parameter's allowed range), wrapped, the row
    as tall as the longest: a range wider than its column ("a whole number and ≥ 0
    and ≤ 24") would otherwise be cut at the page's edge."""
    texts = {3: (zh, WIDTHS[3]), 4: (en, WIDTHS[4])}
    if allowed is not None:
        texts[5] = (allowed, WIDTHS[5])
    wrapped_texts(ws, row, texts, styles.text)


def write_parameters_sheet(book, layout, values, results, preset, styles):
    spec, lang = layout.spec, layout.lang
    name = layout.sheet_name["parameters"]
    ws = book.add_worksheet(name)
    keys = ["inputs_valid"] + [e.item.key for e in layout.parameter_rows
                               if e.kind in ("parameter", "scalar", "bound", "rule")]
    widths = [key_width(keys, WIDTHS[0]), *WIDTHS[1:]]
    for col, width in enumerate(widths):
        ws.set_column(col, col, width)
    ws.write(0, 0, f"{label(spec, lang)} — {both(('参数', 'Parameters'), lang)}", styles.title)
    ws.write(1, 0, f"{both(('预设', 'Preset'), lang)}: {preset['name']} — {preset[lang]}",
             styles.subtitle)
    ws.write(2, 0, both(("状态", "Status"), lang), styles.group)
    status_row = layout.places["input_status"].row
    ws.set_row(status_row, 36)
    ws.write(4, 0, both(("黄色单元格可修改；所有结果随之重算。", "Yellow cells are inputs: "
                         "edit them and every result recomputes."), lang), styles.subtitle)
    for col, pair in enumerate(HEADERS["inputs"]):
        ws.write(PARAMETER_TABLE_ROW, col, pair[0] if lang == "zh" else pair[1], styles.header)

    checks = []                     # (row, zh message, en message)
    for entry in layout.parameter_rows:
        row, item = entry.row, entry.item
        if entry.kind == "group":
            ws.merge_range(row, 0, row, 5, both((item["zh"], item["en"]), lang), styles.group)
        elif entry.kind == "heading":
            ws.merge_range(row, 0, row, 5, both(HEADERS[item], lang), styles.group)
        elif entry.kind == "parameter":
            ws.write(row, 0, item.key, styles.key)
            input_cell(ws, row, 1, item, values[item.key], styles)
            validation(ws, row, 1, item, lang)
            ws.write(row, 2, unit_text(item.unit), styles.top)
            _describe(ws, row, item.zh, item.en, styles, allowed=item.bounds_text())
        elif entry.kind == "scalar":
            ws.write(row, 0, item.key, styles.key)
            write_formula_cell(ws, row, 1, item, layout, results, styles, name)
            ws.write(row, 2, unit_text(item.unit), styles.top)
            _describe(ws, row, item.zh, item.en, styles)
        elif entry.kind == "bound":
            ref = f"p_{item.key}"
            if item.axis:
                count = layout.axis_sizes[item.axis]
                condition = _items_bound_condition(item, ref, count)
                value = int(any(item.breaks_bounds(float(v)) for v in values[item.key]))
                where = f"（每个{spec.axis[item.axis].label_zh}）", f" (each {spec.axis[item.axis].label_en.lower()})"
            else:
                condition = f"IF(ISNUMBER({ref}),{bound_condition(item, ref)},TRUE)" \
                    if item.kind != "choice" else bound_condition(item, ref)
                value = int(item.breaks_bounds(float(values[item.key])))
                where = "", ""
            ws.write(row, 0, item.key, styles.key)
            ws.write_formula(row, 1, f"=IF({condition},1,0)", styles.number("-", "0"), value)
            zh = f"{item.zh}{where[0]}：须为 {item.bounds_text()}"
            en = f"{item.key}{where[1]} must be {item.bounds_text()}"
            _describe(ws, row, zh, en, styles)
            checks.append(row)
        elif entry.kind == "rule":
            ws.write(row, 0, item.key, styles.key)
            if item.items:
                flags = f"q_{item.key}"
                ws.write_formula(row, 1, f"=IF(MAX({flags})>0,1,0)", styles.number("-", "0"),
                                 int(max(results[item.key]) > 0))
                axis = spec.axis[item.items]
                ws.write_formula(row, 3, f'="{item.zh}（{axis.label_zh} "&IFERROR(MATCH(1,{flags},0),"")&"）"',
                                 styles.text, item.zh)
                ws.write_formula(row, 4, f'="{item.en} ({axis.label_en.lower()} "&IFERROR(MATCH(1,{flags},0),"")&")"',
                                 styles.text, item.en)
            else:
                write_formula_cell(ws, row, 1, item, layout, results, styles, name)
                _describe(ws, row, item.zh, item.en, styles)
            checks.append(row)
        elif entry.kind == "note":
            ws.write(row, 0, item["when_nonzero"], styles.key)
            _describe(ws, row, item["zh"], item["en"], styles)
        elif entry.kind == "valid":
            first, last = checks[0], checks[-1]
            flags = f"$B${first + 1}:$B${last + 1}"
            primary, other = ("D", "E") if lang == "zh" else ("E", "D")
            ws.write(row, 0, "inputs_valid", styles.key)
            # Only valid inputs are ever written (the command line refuses the rest).
            ws.write_formula(row, 1, f"=IF(SUM({flags})=0,1,0)", styles.number("-", "0"), 1)
            _describe(ws, row, "1 = 全部输入有效（所有公式以此为前提）",
                      "1 = all inputs valid (every formula is guarded by this cell)", styles)
            ok_text = STATUS_OK[0] + " / " + STATUS_OK[1][2:] if lang == "zh" else \
                STATUS_OK[1] + " / " + STATUS_OK[0][2:]
            msg = f"${primary}${first + 1}:${primary}${last + 1}"
            msg_other = f"${other}${first + 1}:${other}${last + 1}"
            # notes marked ``status`` (a Holzer grid that misses modes) follow the ✓:
            # the inputs are valid, but some cells are blank, and the status says why
            ok_formula, ok_value = f'"{ok_text}"', ok_text
            for index, note in enumerate(spec.notes):
                if not note.get("status"):
                    continue
                key, text = note["when_nonzero"], f"{note[lang]} / {note[layout.other]}"
                ok_formula += (f'&IF({layout.locator.name(key)}<>0,'
                               f'" — "&{layout.note_words(index)},"")')
                ok_value += f" — {text}" if float({**values, **results}[key]) != 0 else ""
            # more than one broken: every one by its key (no TEXTJOIN before Excel 2019),
            # gathered down column G, one check a row: one IF per check in this formula
            # passed Excel's 8,192 characters of a formula as the parameters grew
            column = "$" + xl_col_to_name(GATHERED)
            for before, r in zip([None, *checks], checks):
                gathered = f'IF($B${r + 1}=1,", "&$A${r + 1},"")'
                if before is not None:
                    gathered = f"{column}${before + 1}&{gathered}"
                ws.write_formula(r, GATHERED, f"={gathered}", styles.text, "")
            ws.write(checks[0] - 1, GATHERED, both(HEADERS["gathered"], lang), styles.group)
            names = f"{column}${checks[-1] + 1}"
            status = (f'=IF(SUM({flags})=0,{ok_formula},"✗ "&INDEX({msg},MATCH(1,{flags},0))'
                      f'&" / "&INDEX({msg_other},MATCH(1,{flags},0))'
                      f'&IF(SUM({flags})>1," ({both(BROKEN, lang)}: "&MID({names},3,2000)&")",""))')
            ws.merge_range(status_row, 1, status_row, 5, "", styles.status)
            ws.write_formula(status_row, 1, status, styles.status, ok_value)
            ws.conditional_format(status_row, 1, status_row, 5, {
                "type": "formula", "criteria": "=q_inputs_valid=1", "format": styles.status_ok})
            ws.conditional_format(status_row, 1, status_row, 5, {
                "type": "formula", "criteria": "=q_inputs_valid<>1", "format": styles.status_bad})
            ws.conditional_format(first, 1, last, 1, {
                "type": "cell", "criteria": "==", "value": 1, "format": styles.status_bad})
    ws.freeze_panes(3, 0)
    # the inputs and derived values print; the checks below them stay on the screen —
    # one 0 per rule is not worth a page, and the status cell at the top says in words
    # which rule the inputs break
    printed = next(e.row for e in layout.parameter_rows
                   if e.kind == "heading" and e.item == "checks") - 2
    ws.print_area(0, 0, printed, len(widths) - 1)
    landscape_page(ws, widths, printed)
    ws.activate()
    return ws
