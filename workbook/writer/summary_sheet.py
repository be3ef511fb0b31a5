"""The Summary sheet: the key data, the extremes of each quantity with the crank
angle where they first occur, and the cycle results — all formulas."""
from crankbook.writer.layout import label, spec_key_data, summary_series, unit_text
from crankbook.writer.print_setup import landscape_page, wrapped_texts
from crankbook.writer.scalar_sheet import write_formula_cell
from crankbook.writer.series_sheet import cached

COLUMNS = [("量", "Quantity"), ("Quantity", "量"), ("单位", "Unit"), ("最大值", "Maximum"),
           ("最大值处", "at the maximum"), ("最小值", "Minimum"), ("最小值处", "at the minimum")]


WIDTHS = [56, 44, 9, 16, 16, 14, 16]


def _labels(ws, row, item, layout, styles):
    """The quantity's name in both languages, the row as tall as the longer."""
    wrapped_texts(ws, row, {0: (label(item, layout.lang), WIDTHS[0]),
                            1: (label(item, layout.other), WIDTHS[1])}, styles.text)


def _joined(layout, item, values):
    """A per-item result in the key data as one text, its items joined by "-" (the
    firing order 1-5-3-6-2-4): the live formula and its value."""
    name = layout.locator.name(item.key)
    most = layout.spec.axis[item.items].max
    parts = [f"INDEX({name},1)"] + [f'IF(COUNT({name})>={n},"-"&INDEX({name},{n}),"")'
                                     for n in range(2, most + 1)]
    text = "-".join(f"{float(v):g}" for v in values)
    return "=" + "&".join(parts), text


def _write_status_line(ws, layout, values, results, styles):
    """One live line under the title: with inputs that break a rule, the Parameters
    status itself (the broken rule in words, then every further one by name) — not a
    consequence such as an empty Holzer grid; with valid inputs, every note whose
    parameter or result is not 0 (an offset build's series columns, a slip such as
    grams typed for kg)."""
    from crankbook.spec.formulas import quote_sheet
    spec = layout.spec
    place = layout.places["input_status"]
    status = f"{quote_sheet(place.sheet)}!$B${place.row + 1}"
    known = {**values, **results}
    parts, shown = [], []
    for index, note in enumerate(spec.notes):
        text = f"{note[layout.lang]} / {note[layout.other]}"
        parts.append(f'IF({layout.locator.name(note["when_nonzero"])}<>0,'
                     f'{layout.note_words(index, sheet=True)}&"  ","")')
        if float(known[note["when_nonzero"]]) != 0:
            shown.append(f"{text}  ")
    notes = "&".join(parts) if parts else '""'
    formula = f"=IF(q_inputs_valid<>1,{status},{notes})"
    ws.merge_range(2, 0, 2, len(WIDTHS) - 1, "", styles.warning)
    ws.write_formula(2, 0, formula, styles.warning, "".join(shown))


def write_summary_sheet(book, layout, values, results, styles):
    spec, lang = layout.spec, layout.lang
    name = layout.sheet_name["summary"]
    ws = book.add_worksheet(name)
    rows = layout.summary_rows
    for col, width in enumerate(WIDTHS):
        ws.set_column(col, col, width)
    ws.write(0, 0, f"{label(spec, lang)} — {'汇总' if lang == 'zh' else 'Summary'}", styles.title)
    ws.write(1, 0, "所有数值均为公式 / every value is a formula", styles.subtitle)
    _write_status_line(ws, layout, values, results, styles)

    key_data = spec_key_data(spec)
    if key_data:
        row = rows["key_data"]
        ws.merge_range(row, 0, row, 6, "主要数据 / Key data" if lang == "zh"
                       else "Key data / 主要数据", styles.group)
        for offset, key in enumerate(key_data, start=1):
            item = spec.parameter.get(key) or spec.quantity.get(key)
            _labels(ws, row + offset, item, layout, styles)
            ws.write(row + offset, 2, unit_text(item.unit), styles.top)
            value = values[key] if key in spec.parameter else results[key]
            if getattr(item, "items", None):        # one value per item: "1-5-3-6-2-4"
                formula, text = _joined(layout, item, value)
                ws.write_formula(row + offset, 3, formula, styles.text, text)
                continue
            ws.write_formula(row + offset, 3, f"={layout.locator.name(key)}",
                             styles.number(item.unit, getattr(item, "format", None)),
                             cached(value))

    row = rows["extremes"]
    grid_unit = unit_text(spec.grid.unit)
    for col, pair in enumerate(COLUMNS):
        text = pair[0] if lang == "zh" else pair[1]
        if col in (4, 6):
            text += f" [{grid_unit}]"
        ws.write(row, col, text, styles.header)
    for quantity in summary_series(spec):
        row += 1
        _labels(ws, row, quantity, layout, styles)
        ws.write(row, 2, unit_text(quantity.unit), styles.top)
        for col, stat in enumerate(["max", "max_angle", "min", "min_angle"], start=3):
            key = f"{quantity.key}_{stat}"
            write_formula_cell(ws, row, col, spec.quantity[key], layout, results, styles, name)

    row = rows["results"]
    if spec.results:
        ws.merge_range(row, 0, row, 6, "循环结果 / Cycle results" if lang == "zh"
                       else "Cycle results / 循环结果", styles.group)
    for quantity in spec.results:
        row += 1
        _labels(ws, row, quantity, layout, styles)
        ws.write(row, 2, unit_text(quantity.unit), styles.top)
        write_formula_cell(ws, row, 3, quantity, layout, results, styles, name)
    ws.freeze_panes(rows["extremes"] + 1, 1)
    landscape_page(ws, WIDTHS, row)
    return ws
