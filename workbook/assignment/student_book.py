"""The student's workbook: the task, their parameters (p_), the given data, and
empty answer blocks (a_) laid out like the guide's tables.  No formulas, no
results: nothing the key computes is anywhere in the file."""
import unicodedata

from crankbook.writer.fast_sheet import FastWorkbook
from xlsxwriter.utility import xl_col_to_name, xl_rowcol_to_cell

from crankbook.support.atomic import atomic_path
from crankbook.spec.formulas import quote_sheet
from crankbook.writer.build import FIXED_TIME, PROPERTY_ASSIGNMENT, PROPERTY_ROLE, PROPERTY_TEMPLATE
from crankbook.writer.layout import unit_text
from crankbook.writer.print_setup import key_width, landscape_page, line_height, row_points
from crankbook.writer.styles import Styles

TASK = {"zh": "任务", "en": "Task"}


class _ChoiceWords(dict):
    def __missing__(self, lang):
        from crankbook.assignment.results import words
        self[lang] = {k: v for k, v in words(lang).items() if k.startswith("choice_")}
        return self[lang]


CHOICE_WORDS = _ChoiceWords()
GIVEN = {"zh": "已知数据", "en": "Given data"}
TASK_WIDTHS = [30, 16, 9, 48, 48]
GIVEN_WIDTH = 24
PRINT_BLOCKS, PRINT_WIDTH = 6, 9         # the given pressure prints in six column pairs
GIVEN_KEYS = ("crank_angle", "pressure")  # named p_given_<key> on the given-data sheet
LABEL_WIDTH, ANSWER_WIDTH = 26, 20       # an answer sheet's row labels and answer columns


def both(zh, en, lang):
    return f"{zh} / {en}" if lang == "zh" else f"{en} / {zh}"


def display_width(text):
    """Columns a text takes: CJK and full-width characters count two."""
    return sum(2 if unicodedata.east_asian_width(c) in "WF" else 1 for c in text)


def write_student_workbook(path, assignment, spec, student, values, given, lang, rows):
    """Write atomically.  ``given``: {"crank_angle": [...], "pressure": [...]} or {} ;
    ``rows``: answer-sheet row kind -> list of row labels."""
    with atomic_path(path) as temporary:
        _write(temporary, assignment, spec, student, values, given, lang, rows)


def _write(filename, assignment, spec, student, values, given, lang, rows):
    book = FastWorkbook(filename, {"in_memory": True, "strings_to_numbers": False,
                                          "strings_to_formulas": False,
                                          "strings_to_urls": False})
    book.set_properties({"title": assignment.name(lang), "author": "crankbook",
                         "created": FIXED_TIME})
    # what the file is, never whose it is (the student's own sheet names them)
    book.set_custom_property(PROPERTY_ROLE, "student")
    book.set_custom_property(PROPERTY_ASSIGNMENT, assignment.key)
    book.set_custom_property(PROPERTY_TEMPLATE, spec.key)
    book.set_custom_property("crankbook_language", lang)     # crankbook check speaks it
    styles = Styles(book)
    names = {}

    def define(name, sheet, first_row, col, last_row=None):
        first = xl_rowcol_to_cell(first_row, col, True, True)
        ref = first if last_row is None else \
            f"{first}:{xl_rowcol_to_cell(last_row, col, True, True)}"
        names[name] = f"={quote_sheet(sheet)}!{ref}"

    task = _task_sheet(book, assignment, spec, student, values, lang, styles, define)
    given_print = _given_sheet(book, given, lang, styles, define) if given else None
    answer = styles.number("-", "General", role="input")
    tables = [task] + [_answer_sheet(book, sheet, assignment, spec, lang, styles, define,
                                     answer, rows) for sheet in assignment.sheets]
    for ws in book.worksheets():
        landscape_page(ws)
    if given_print:
        sheet, last = given_print
        tables.append((sheet, [PRINT_WIDTH] * 2 * PRINT_BLOCKS, last))
    for sheet, widths, last in tables:       # no last page holding a few rows
        landscape_page(sheet, widths, last)
    for name in sorted(names):
        book.define_name(name, names[name])
    book.close()


def _task_sheet(book, assignment, spec, student, values, lang, styles, define):
    name = TASK[lang]
    task = book.add_worksheet(name)
    shown = [p for p in spec.scalar_parameters() if p.group != "pressure" and
             (assignment.task_groups is None or p.group in assignment.task_groups)]
    widths = [key_width((p.key for p in shown), TASK_WIDTHS[0]), *TASK_WIDTHS[1:]]
    for col, width in enumerate(widths):
        task.set_column(col, col, width)
    task.write(0, 0, assignment.name(lang), styles.title)
    other = assignment.en if lang == "zh" else assignment.zh
    task.write(1, 0, other, styles.subtitle)
    task.write(3, 0, both("学号", "Student id", lang), styles.group)
    task.write_string(3, 1, student["student_id"], styles.key)
    define("s_student_id", name, 3, 1)
    task.write(4, 0, both("姓名", "Name", lang), styles.group)
    task.write_string(4, 1, student["name"])
    define("s_student_name", name, 4, 1)
    statement = assignment.statement(lang)
    task.merge_range(6, 0, 6, len(widths) - 1, statement, styles.text)
    task.set_row(6, row_points([(statement, sum(widths))]))
    # the short per-item tables (the timing gears) before the long parameter list:
    # after it they fell on a page of their own under its repeated header
    row = _item_tables(task, name, assignment, spec, values, lang, styles, define, 8, widths)
    for col, text in enumerate([both("键", "Key", lang), both("数值", "Value", lang),
                                both("单位", "Unit", lang), "说明", "Description"]):
        task.write(row, col, text, styles.header)
    task.repeat_rows(row)
    # the pressure is given as a table instead; inputs the task does not use are left out
    for parameter in shown:
        row += 1
        task.write(row, 0, parameter.key, styles.key_top)
        zh, en = parameter.zh, parameter.en
        if parameter.kind == "choice":            # the word, as the full workbook shows it
            choice = parameter.choices[int(values[parameter.key]) - 1]
            task.write_string(row, 1, choice, styles.top)
            # … and what it is, in both languages (a law's name, not its key)
            zh += "：" + CHOICE_WORDS["zh"].get(f"choice_{choice}", choice)
            en += ": " + CHOICE_WORDS["en"].get(f"choice_{choice}", choice)
        else:
            task.write_number(row, 1, float(values[parameter.key]), styles.top)
        task.write(row, 2, unit_text(parameter.unit), styles.top)
        task.write(row, 3, zh, styles.text)
        task.write(row, 4, en, styles.text)
        task.set_row(row, row_points([(zh, widths[3]), (en, widths[4])]))
        define(f"p_{parameter.key}", name, row, 1)
    task.activate()
    return task, widths, row


def _item_tables(task, name, assignment, spec, values, lang, styles, define, row, widths):
    """The per-item inputs the task uses (the gears' teeth and shifts, …): one table per
    axis, one row per item, each column named p_<key> as in the full workbook."""
    for axis in spec.axes:
        inputs = [p for p in spec.item_parameters(axis.key)
                  if assignment.task_groups is None or p.group in assignment.task_groups]
        if not inputs:
            continue
        caption = assignment.axis_caption(axis.key, lang, values)
        task.write(row, 0, caption or both(axis.zh, axis.en, lang), styles.group)
        row += 1
        # the quantity without its parenthesis ("齿数 z", not "…（曲轴齿轮在前…）"): the
        # row labels say which gear is which, and a narrow column stays one line or two
        headers = [both(axis.label_zh, axis.label_en, lang)] + [
            both(p.zh.split("（")[0], p.en.split(" (")[0], lang) for p in inputs]
        for col, text in enumerate(headers):
            task.write(row, col, text, styles.header)
        task.set_row(row, row_points(zip(headers, widths), bold=True))
        first = row + 1
        count = len(values[inputs[0].key])
        for i in range(count):
            task.write(first + i, 0, assignment.row_label(axis.key, lang, i + 1, count)
                       or axis.label(lang, i + 1, size=count), styles.key)
            for col, parameter in enumerate(inputs, start=1):
                task.write_number(first + i, col, float(values[parameter.key][i]))
        for col, parameter in enumerate(inputs, start=1):
            define(f"p_{parameter.key}", name, first, col, first + count - 1)
        row = first + count + 1
    return row


def _given_sheet(book, given, lang, styles, define):
    """The measured pressure: laid out for print in PRINT_BLOCKS pairs of columns side
    by side (721 rows in two columns printed 24 pages), and beside that in one column
    each, named p_given_crank_angle and p_given_pressure, for formulas."""
    name = GIVEN[lang]
    sheet = book.add_worksheet(name)
    sheet.write(0, 0, both("已知数据：气缸压力（绝对）", "Given data: cylinder pressure (absolute)",
                           lang), styles.title)
    named_at = 2 * PRINT_BLOCKS + 1
    first, second = xl_col_to_name(named_at), xl_col_to_name(named_at + 1)
    note = both(f"两个整数度之间按线性插值取值；同一数据在 {first}、{second} 两列中各为一列",
                f"between two whole degrees, interpolate linearly; the same data in one "
                f"column each in {first} and {second}", lang)
    sheet.merge_range(1, 0, 1, 2 * PRINT_BLOCKS - 1, note, styles.subtitle_wrap)
    sheet.set_row(1, row_points([(note, 2 * PRINT_BLOCKS * PRINT_WIDTH)]))
    angles, pressures = given["crank_angle"], given["pressure"]
    per_block = -(-len(angles) // PRINT_BLOCKS)
    for block in range(PRINT_BLOCKS):
        col = 2 * block
        sheet.set_column(col, col + 1, PRINT_WIDTH)
        sheet.write(3, col, "φ", styles.header)
        sheet.write(3, col + 1, "p", styles.header)
        sheet.write(4, col, "[°]", styles.unit)
        sheet.write(4, col + 1, "[MPa]", styles.unit)
        for i in range(block * per_block, min(len(angles), (block + 1) * per_block)):
            sheet.write_number(5 + i - block * per_block, col, float(angles[i]))
            sheet.write_number(5 + i - block * per_block, col + 1, float(pressures[i]))
    for row in range(5, 5 + per_block):      # a row's height known: pages fill (landscape_page)
        sheet.set_row(row, line_height() + 1.5)
    last = 4 + per_block
    sheet.print_area(0, 0, last, 2 * PRINT_BLOCKS - 1)
    headers = [(both("曲柄转角 φ", "Crank angle φ", lang), "°", GIVEN_KEYS[0]),
               (both("气缸压力 p", "Cylinder pressure p", lang), "MPa", GIVEN_KEYS[1])]
    for col, (title, unit, key) in enumerate(headers, start=named_at):
        sheet.set_column(col, col, GIVEN_WIDTH)
        sheet.write(3, col, title, styles.header)
        sheet.write(4, col, f"[{unit}]", styles.unit)
        for i, value in enumerate(given[key]):
            sheet.write_number(5 + i, col, float(value))
        define(f"p_given_{key}", name, 5, col, 5 + len(given[key]) - 1)
    sheet.set_row(3, row_points([(title, GIVEN_WIDTH) for title, _, _ in headers], bold=True))
    sheet.freeze_panes(5, 0)
    sheet.repeat_rows(3, 4)
    return sheet, last


def _answer_sheet(book, answer_sheet, assignment, spec, lang, styles, define, answer, rows):
    name = answer_sheet.zh if lang == "zh" else answer_sheet.en
    ws = book.add_worksheet(name)
    ws.write(0, 0, name, styles.title)
    ws.write(1, 0, both("在黄色单元格中填写答案（数值或公式）",
                        "Type your answers into the yellow cells (numbers or formulas)", lang),
             styles.subtitle)
    items = [assignment.item[key] for key in answer_sheet.items]
    if answer_sheet.rows == "scalar":
        widths = [40, 18, 10, key_width((f"a_{item.key}" for item in items), 26)]
        for col, width in enumerate(widths):
            ws.set_column(col, col, width)
        headers = [both("量", "Quantity", lang), both("答案", "Answer", lang),
                   both("单位", "Unit", lang), both("名称", "Name", lang)]
        for col, text in enumerate(headers):
            ws.write(3, col, text, styles.header)
        ws.set_row(3, row_points(zip(headers, widths), bold=True))
        for i, item in enumerate(items):
            ws.write(4 + i, 0, item.label(lang), styles.text)
            ws.write_blank(4 + i, 1, None, answer)
            ws.write(4 + i, 2, unit_text(item.unit), styles.top)
            ws.write(4 + i, 3, f"a_{item.key}", styles.key)
            ws.set_row(4 + i, row_points([(item.label(lang), widths[0])]))
            define(f"a_{item.key}", name, 4 + i, 1)
        return ws, widths, 3 + len(items)
    labels = rows[answer_sheet.rows]
    ws.set_column(0, 0, LABEL_WIDTH)
    titles = {"positions": both("位置", "Position", lang),
              "crank_angle": both("曲轴转角 α [°]", "Crank angle α [°]", lang),
              "cam_angle": both("凸轮转角 δ [°]", "Cam angle δ [°]", lang)}
    axis = spec.axis.get(answer_sheet.rows)
    title = titles.get(answer_sheet.rows) or (both(axis.label_zh, axis.label_en, lang)
                                              if axis is not None else answer_sheet.rows)
    ws.write(3, 0, title, styles.header)
    ws.write(4, 0, "", styles.unit)
    for i, text in enumerate(labels):
        if isinstance(text, str):
            ws.write_string(5 + i, 0, text, styles.key)
        else:
            ws.write_number(5 + i, 0, float(text), styles.key)
    for col, item in enumerate(items, start=1):
        ws.set_column(col, col, ANSWER_WIDTH)
        ws.write(3, col, item.label(lang), styles.header)
        ws.write(4, col, f"[{unit_text(item.unit)}]", styles.unit)
        for i in range(len(labels)):
            ws.write_blank(5 + i, col, None, answer)
        define(f"a_{item.key}", name, 5, col, 5 + len(labels) - 1)
    ws.set_row(3, row_points([(title, LABEL_WIDTH)] + [(item.label(lang), ANSWER_WIDTH)
                                                       for item in items], bold=True))
    ws.freeze_panes(5, 1)
    ws.repeat_rows(3, 4)
    return ws, [LABEL_WIDTH] + [ANSWER_WIDTH] * len(items), 4 + len(labels)
