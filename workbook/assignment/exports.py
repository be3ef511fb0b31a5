"""`grade --lms NAME`: the file a learning-management system imports, as it documents it.

* ``generic`` — ``lms-import.csv`` only (identifier, grade, feedback), always written.
* ``moodle`` — ``moodle-grading-worksheet.csv``: Moodle's offline grading worksheet
  (Identifier, Full name, Email address, Status, Grade, Maximum Grade, Grade can be
  changed, Last modified (submission), Last modified (grade), Feedback comments).
  Moodle matches rows by its own ``Identifier`` ("Participant 1234"), so the teacher
  gives the worksheet Moodle exported (``--lms-template``); its rows are kept and
  filled, each matched to a student by the roster's ``email`` column, else by name.
* ``canvas`` — ``canvas-gradebook.csv``: Student, ID, SIS User ID, SIS Login ID,
  Section, then the assignment's column and a "Points Possible" row (Canvas's
  gradebook import); SIS User ID is the student id.
* ``xuexitong`` — ``xuexitong-import.xlsx`` (学习通 / 雨课堂 score import): 学号 stored
  as text (leading zeros and 12-digit ids intact), 姓名, 成绩, 评语.

Feedback is the student-side text of ``lms-import.csv``: never a flag, a suspicion
or another student's id.
"""
import csv
import io
from pathlib import Path

import xlsxwriter

from crankbook.assignment.results import WORKBOOK_OPTIONS, lms_text
from crankbook.support.csv_safety import csv_text
from crankbook.errors import CrankbookError
from crankbook.writer.build import FIXED_TIME
from crankbook.support.paths import require_file

LMS = ("generic", "moodle", "canvas", "xuexitong")
MOODLE_COLUMNS = ("Identifier", "Full name", "Email address", "Status", "Grade",
                  "Maximum Grade", "Grade can be changed", "Last modified (submission)",
                  "Last modified (grade)", "Feedback comments")
CANVAS_COLUMNS = ("Student", "ID", "SIS User ID", "SIS Login ID", "Section")
SECTION_COLUMNS = ("班级", "class", "section", "班")
EMAIL_COLUMNS = ("email", "邮箱", "e-mail", "email address")


def check_lms(lms, template):
    if lms not in LMS:
        raise CrankbookError(f"--lms {lms!r}: choose {', '.join(LMS)}")
    if template is not None and lms != "moodle":
        raise CrankbookError("--lms-template is Moodle's grading worksheet: use it with "
                             "--lms moodle")
    if lms == "moodle" and template is None:
        raise CrankbookError("--lms moodle: give the grading worksheet Moodle exported "
                             "(Assignment → View all submissions → Download grading "
                             "worksheet) with --lms-template")
    if template is not None:
        _moodle_rows(template)            # a bad worksheet is refused before grading


def _grade_value(g, missing_as_zero):
    if g.status == "graded":
        return round(g.score, 2)
    return 0 if missing_as_zero else ""


def _column(g, names):
    for key, value in g.extra.items():
        if key.strip().lower() in names:
            return value
    return ""


def write_lms(directory, lms, template, assignment, lang, grades, mode, missing_as_zero):
    directory = Path(directory)
    if lms == "moodle":
        _write_moodle(directory, template, assignment, lang, grades, mode, missing_as_zero)
    elif lms == "canvas":
        _write_canvas(directory, assignment, lang, grades, mode, missing_as_zero)
    elif lms == "xuexitong":
        _write_xuexitong(directory, assignment, lang, grades, mode, missing_as_zero)


def _moodle_rows(path):
    require_file(path, CrankbookError, "--lms-template")
    try:
        text = Path(path).read_bytes()[:5_000_000].decode("utf-8-sig")
    except (OSError, UnicodeDecodeError) as error:
        raise CrankbookError(f"--lms-template {path}: cannot be read as UTF-8 CSV "
                             f"({type(error).__name__})") from None
    rows = list(csv.reader(io.StringIO(text)))
    if not rows or not {"Identifier", "Grade", "Feedback comments"} <= set(rows[0]):
        raise CrankbookError(f"--lms-template {path}: not a Moodle grading worksheet (its "
                             f"first row has no Identifier, Grade and Feedback comments)")
    return rows


def _write_moodle(directory, template, assignment, lang, grades, mode, missing_as_zero):
    rows = _moodle_rows(template)
    header = rows[0]
    at = {name: header.index(name) for name in header}
    by_email = {_column(g, EMAIL_COLUMNS).strip().lower(): g for g in grades
                if _column(g, EMAIL_COLUMNS).strip()}
    by_name = {g.name.strip(): g for g in grades}
    out = [header]
    for row in rows[1:]:
        row = row + [""] * (len(header) - len(row))
        email = row[at["Email address"]].strip().lower() if "Email address" in at else ""
        name = row[at["Full name"]].strip() if "Full name" in at else ""
        g = by_email.get(email) if email else None
        g = g or by_name.get(name)
        if g is not None:
            row[at["Grade"]] = _grade_value(g, missing_as_zero)
            row[at["Feedback comments"]] = lms_text(g, assignment, lang, mode)
            if "Maximum Grade" in at:
                row[at["Maximum Grade"]] = round(assignment.max_score, 2)
        out.append(row)
    (directory / "moodle-grading-worksheet.csv").write_text(csv_text(out), encoding="utf-8",
                                                            newline="")


def _write_canvas(directory, assignment, lang, grades, mode, missing_as_zero):
    title = assignment.name(lang)
    out = [[*CANVAS_COLUMNS, title],
           ["Points Possible", "", "", "", "", round(assignment.max_score, 2)]]
    for g in grades:
        out.append([g.name, _column(g, ("canvas_id", "canvas id")), g.student_id,
                    _column(g, ("login", "sis login id", *EMAIL_COLUMNS)),
                    _column(g, SECTION_COLUMNS), _grade_value(g, missing_as_zero)])
    (directory / "canvas-gradebook.csv").write_text(csv_text(out), encoding="utf-8",
                                                    newline="")


def _write_xuexitong(directory, assignment, lang, grades, mode, missing_as_zero):
    book = xlsxwriter.Workbook(str(directory / "xuexitong-import.xlsx"), WORKBOOK_OPTIONS)
    book.set_properties({"author": "crankbook", "created": FIXED_TIME})
    ws = book.add_worksheet("成绩导入")
    text = book.add_format({"num_format": "@"})
    for col, name in enumerate(("学号", "姓名", "成绩", "评语")):
        ws.write_string(0, col, name)
    for row, g in enumerate(grades, start=1):
        ws.write_string(row, 0, g.student_id, text)
        ws.write_string(row, 1, g.name, text)
        value = _grade_value(g, missing_as_zero)
        if value != "":
            ws.write_number(row, 2, float(value))
        ws.write_string(row, 3, lms_text(g, assignment, lang, mode, limit=2000), text)
    ws.set_column(0, 0, 16, text)
    ws.set_column(1, 1, 12)
    ws.set_column(3, 3, 80)
    book.close()
