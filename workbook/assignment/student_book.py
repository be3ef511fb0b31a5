"""The student's workbook: the task, their parameters (p_), the given data, and
empty answer blocks (a_) laid out like the guide's tables.  No formulas, no
results: nothing the key computes is anywhere in the file."""
import xlsxwriter
from xlsxwriter.utility import xl_rowcol_to_cell

from crankbook.atomic import atomic_path
from crankbook.formulas import quote_sheet
from crankbook.writer.build import FIXED_TIME
from crankbook.writer.layout import unit_text
from crankbook.writer.styles import Styles

TASK = {"zh": "任务", "en": "Task"}
GIVEN = {"zh": "已知数据", "en": "Given data"}


def _both(zh, en, lang):
    return f"{zh} / {en}" if lang == "zh" else f"{en} / {zh}"


def write_student_workbook(path, assignment, spec, student, values, given, lang, row_counts):
    """Write atomically.  ``given``: key -> list of numbers; ``row_counts``: grid -> rows."""
    with atomic_path(path) as temporary:
        _write(temporary, assignment, spec, student, values, given, lang, row_counts)


def _write(filename, assignment, spec, student, values, given, lang, row_counts):
    book = xlsxwriter.Workbook(filename, {"in_memory": True, "strings_to_numbers": False,
                                          "strings_to_formulas": False})
    book.set_properties({"title": getattr(assignment, lang), "author": "crankbook",
                         "created": FIXED_TIME})
    styles = Styles(book)
    names = {}

    def define(name, sheet, first_row, col, last_row=None):
        first = xl_rowcol_to_cell(first_row, col, True, True)
        ref = first if last_row is None else \
            f"{first}:{xl_rowcol_to_cell(last_row, col, True, True)}"
        names[name] = f"={quote_sheet(sheet)}!{ref}"

    # ---- task: statement, identity, parameters
    task = book.add_worksheet(TASK[lang])
    task.set_column(0, 0, 30)
    task.set_column(1, 1, 16)
    task.set_column(2, 2, 8)
    task.set_column(3, 4, 50)
    task.write(0, 0, _both(assignment.zh, assignment.en, lang), styles.title)
    task.write(2, 0, _both("学号", "Student id", lang), styles.group)
    task.write_string(2, 1, student["student_id"], styles.key)
    define("s_student_id", TASK[lang], 2, 1)
    task.write(3, 0, _both("姓名", "Name", lang), styles.group)
    task.write_string(3, 1, student["name"])
    define("s_student_name", TASK[lang], 3, 1)
    statement = assignment.statement_zh if lang == "zh" else assignment.statement_en
    task.merge_range(5, 0, 5, 4, statement, styles.text)
    task.set_row(5, 230)
    row = 7
    for col, text in enumerate([_both("键", "Key", lang), _both("数值", "Value", lang),
                                _both("单位", "Unit", lang), "说明", "Description"]):
        task.write(row, col, text, styles.header)
    row += 1
    for parameter in spec.parameters:
        if parameter.group == "pressure":
            continue                      # the pressure is given as a table instead
        task.write(row, 0, parameter.key, styles.key)
        task.write_number(row, 1, values[parameter.key])
        task.write(row, 2, unit_text(parameter.unit))
        task.write(row, 3, parameter.zh, styles.text)
        task.write(row, 4, parameter.en, styles.text)
        define(f"p_{parameter.key}", TASK[lang], row, 1)
        row += 1
    task.activate()

    # ---- given data (e.g. the cylinder pressure every degree)
    if given:
        sheet = book.add_worksheet(GIVEN[lang])
        sheet.write(0, 0, _both("已知数据（数值）", "Given data (numbers)", lang), styles.title)
        for col, key in enumerate(given):
            quantity = spec.quantity[key]
            sheet.set_column(col, col, 18)
            sheet.write(2, col, quantity.zh if lang == "zh" else quantity.en, styles.header)
            sheet.write(3, col, f"[{unit_text(quantity.unit)}]", styles.unit)
            for i, value in enumerate(given[key]):
                sheet.write_number(4 + i, col, float(value))
            define(f"p_given_{key}", GIVEN[lang], 4, col, 4 + len(given[key]) - 1)
        sheet.freeze_panes(4, 0)

    # ---- answer sheets
    answer = styles.number("-", "General", role="input")
    for answer_sheet in assignment.sheets:
        name = answer_sheet.zh if lang == "zh" else answer_sheet.en
        ws = book.add_worksheet(name)
        ws.write(0, 0, name, styles.title)
        ws.write(1, 0, _both("在黄色单元格中填写答案（数值或公式）",
                             "Type your answers into the yellow cells (numbers or formulas)",
                             lang), styles.subtitle)
        if answer_sheet.rows == "scalar":
            ws.set_column(0, 0, 24)
            ws.set_column(1, 1, 50)
            ws.set_column(2, 3, 14)
            for col, text in enumerate([_both("键", "Key", lang), _both("量", "Quantity", lang),
                                        _both("答案", "Answer", lang), _both("单位", "Unit", lang)]):
                ws.write(3, col, text, styles.header)
            for i, key in enumerate(answer_sheet.items):
                quantity = spec.quantity[key]
                ws.write(4 + i, 0, f"a_{key}", styles.key)
                ws.write(4 + i, 1, _both(quantity.zh, quantity.en, lang), styles.text)
                ws.write_blank(4 + i, 2, None, answer)
                ws.write(4 + i, 3, unit_text(quantity.unit))
                define(f"a_{key}", name, 4 + i, 2)
        else:
            rows = row_counts[answer_sheet.rows]
            ws.set_column(0, 0, 10)
            ws.write(3, 0, _both("位置", "Position", lang), styles.header)
            ws.write(4, 0, "", styles.unit)
            for i in range(rows):
                ws.write_number(5 + i, 0, i + 1)
            for col, key in enumerate(answer_sheet.items, start=1):
                quantity = spec.quantity[key]
                ws.set_column(col, col, 18)
                ws.write(3, col, f"a_{key}\n{quantity.zh if lang == 'zh' else quantity.en}",
                         styles.header)
                ws.write(4, col, f"[{unit_text(quantity.unit)}]", styles.unit)
                for i in range(rows):
                    ws.write_blank(5 + i, col, None, answer)
                define(f"a_{key}", name, 5, col, 5 + rows - 1)
            ws.set_row(3, 64)
            ws.freeze_panes(5, 1)
    for ws in book.worksheets():
        ws.set_paper(9)
        ws.set_landscape()
        ws.fit_to_pages(1, 0)
    for name in sorted(names):
        book.define_name(name, names[name])
    book.close()
