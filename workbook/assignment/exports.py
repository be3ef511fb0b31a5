"""`grade --lms NAME`: the file a learning-management system imports, as it documents it.

* ``generic`` — ``lms-import.csv`` only (identifier, grade, feedback), always written.
* ``moodle`` — ``moodle-grading-worksheet.csv``: Moodle's offline grading worksheet
  (Identifier, Full name, Email address, Status, Grade, Maximum Grade, Grade can be
  changed, Last modified (submission), Last modified (grade), Feedback comments).
  Moodle matches rows by its own ``Identifier`` ("Participant 1234"), so the teacher
  gives the worksheet Moodle exported (``--lms-template``); its rows are kept and
  filled, each matched to a roster student by a key that names one student only:
  the roster's email column, the roster id as the worksheet's ID number or as its
  email's local part (``2023105010004@school.edu.cn``), else the full name when one
  roster student and one worksheet row have it.  A row that only a name two
  students share could match is refused before grading, in one line naming both —
  one student's grade and feedback never reach another.
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


def check_lms(lms, template, roster=None):
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
        rows = _moodle_rows(template)     # a bad worksheet is refused before grading
        if roster is not None:            # … and one no unique key matches
            moodle_match(rows, [(r["student_id"], r["name"], r) for r in roster], template)


def _grade_value(g, missing_as_zero):
    if g.status == "graded":
        return round(g.score, 2)
    return 0 if missing_as_zero else ""


def _column(g, names):
    return _field(g.extra, names)


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


def _field(record, names):
    for key, value in record.items():
        if str(key).strip().lower() in names:
            return str(value).strip()
    return ""


def moodle_match(rows, students, template):
    """{worksheet row number: student id}; ``students``: (id, name, roster columns).
    A row that only a shared name could match, or two rows one student, is refused
    (CrankbookError naming the students and the row)."""
    header = rows[0]
    at = {name: header.index(name) for name in header}

    def cell(row, name):
        return row[at[name]].strip() if name in at and at[name] < len(row) else ""
    by_email, by_id, by_name = {}, {}, {}
    for sid, name, columns in students:
        email = _field(columns, EMAIL_COLUMNS).lower()
        if email:
            by_email[email] = sid
        by_id[sid.casefold()] = sid
        by_name.setdefault(" ".join(name.split()), []).append(sid)
    names_in_sheet = {}
    for row in rows[1:]:
        key = " ".join(cell(row, "Full name").split())
        names_in_sheet[key] = names_in_sheet.get(key, 0) + 1
    matched, owner = {}, {}
    for number, row in enumerate(rows[1:], start=2):
        email = cell(row, "Email address").lower()
        local = email.split("@")[0] if "@" in email else ""
        id_number = cell(row, "ID number")
        name = " ".join(cell(row, "Full name").split())
        sid = by_email.get(email) if email else None
        sid = sid or (by_id.get(id_number.casefold()) if id_number else None)
        sid = sid or (by_id.get(local.casefold()) if local else None)
        if sid is None and name in by_name:
            same = by_name[name]
            if len(same) > 1 or names_in_sheet.get(name, 0) > 1:
                who = ", ".join(same)
                raise CrankbookError(
                    f"--lms-template {template}, row {number}: {name} is the name of "
                    f"{'students ' + who if len(same) > 1 else 'student ' + who + ' and of several worksheet rows'}"
                    f"; a name two people share matches nobody: add an email column to the "
                    f"roster (or ID numbers to the Moodle worksheet)")
            sid = same[0]
        if sid is None:
            continue                      # a Moodle participant not on the roster
        if sid in owner:
            raise CrankbookError(f"--lms-template {template}: rows {owner[sid]} and {number} "
                                 f"both match student {sid}")
        owner[sid], matched[number] = number, sid
    return matched


def _write_moodle(directory, template, assignment, lang, grades, mode, missing_as_zero):
    rows = _moodle_rows(template)
    header = rows[0]
    at = {name: header.index(name) for name in header}
    by_id = {g.student_id: g for g in grades}
    matched = moodle_match(rows, [(g.student_id, g.name, g.extra) for g in grades], template)
    out = [header]
    for number, row in enumerate(rows[1:], start=2):
        row = row + [""] * (len(header) - len(row))
        g = by_id.get(matched.get(number))
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
