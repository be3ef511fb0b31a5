"""`grade --return DIR`: each student's workbook back, graded where they typed.

The returned workbook is *written*, not passed on: it is the workbook the student
was assigned (the class folder keeps it) with the student's answer values — as
the bounded reader read them from the hand-in — typed into its answer cells.
Nothing else of the hand-in travels: no links, hyperlinks, hidden sheets,
comments, headers, validation prompts, names or properties of the submitted file,
and never a classmate's score box (a copy of a classmate's return brings only its
answer values).  No submission is ever loaded whole: openpyxl opens only
crankbook's own assigned file.

Every answer cell is coloured (right, partial, wrong, unreadable, empty) and
carries a comment in the class's language — the reason and the cell's points,
the expected value only with ``--feedback full`` — and the first sheet gets a
score box.  Beside it, ``<id>.html``: the feedback as a page any phone opens.
A student whose workbook cannot go back is told why, on that page and in the
gradebook's notes.
"""
import html
import io
import math
import zipfile
from pathlib import Path

import openpyxl
from openpyxl.writer.excel import ExcelWriter
from openpyxl.comments import Comment
from openpyxl.styles import Alignment, Border, Font, PatternFill, Side

from crankbook.assignment.results import (_item_summary, _points, reason_text, say, shown,
                                          student_notes, words)
from crankbook.writer.build import FIXED_TIME
from crankbook.writer.layout import unit_text
from crankbook.reading.workbook_reader import parse_reference

FILLS = {"right": "C6EFCE", "partial": "FFEB9C", "wrong": "FFC7CE", "unreadable": "D9D2E9",
         "empty": "EDEDED"}
UNREADABLE = ("not_a_number", "wrong_unit", "machine_dependent")
MAX_TEXT = 200                  # characters of a typed answer written back


def kind_of(cell):
    """right / partial / wrong / unreadable / empty for one CellResult."""
    if cell.reason == "no_answer":
        return "empty"
    if cell.reason in UNREADABLE:
        return "unreadable"
    if cell.fraction >= 1.0:
        return "right"
    return "partial" if cell.fraction > 0 else "wrong"


def write_returns(directory, assignment, lang, grades, chosen, mode, assigned):
    """``directory``/<id>.xlsx (graded students) and <id>.html (every student).
    ``chosen``: student id -> the submission graded this round; ``assigned``: the
    class folder's ``students`` folder.  A graded student whose workbook cannot go
    back gets a note saying why (the gradebook and every feedback show it), before
    the page is written."""
    directory = Path(directory)
    for g in grades:
        if g.status == "graded":
            reason = _return_workbook(g, chosen.get(g.student_id), assignment, lang, mode,
                                      Path(assigned) / f"{g.student_id}.xlsx",
                                      directory / f"{g.student_id}.xlsx")
            if reason:
                word, fields = reason
                g.note("no-return", "return_missing", reason=say(words(lang), word, **fields))
        (directory / f"{g.student_id}.html").write_text(
            feedback_html(g, assignment, lang, mode), encoding="utf-8")


def _return_workbook(g, sub, assignment, lang, mode, assigned, target):
    """Write one returned workbook; (word, fields) saying why when there is none."""
    if sub is None:
        return "return_kept", {}
    if not assigned.is_file():
        return "return_no_assigned", {}
    try:
        annotate(sub, g, assignment, lang, mode, assigned, target)
    except MemoryError:
        reason = "return_failed", {"cause": "MemoryError"}
    except OSError as error:            # a full disk, a folder gone: this file, not the class
        reason = "return_failed", {"cause": error.strerror or type(error).__name__}
    except Exception as error:          # one odd file costs its own return, not the class's
        reason = "return_failed", {"cause": type(error).__name__}
    else:
        return None
    target.unlink(missing_ok=True)
    return reason


def annotate(sub, g, assignment, lang, mode, assigned, target):
    """The assigned workbook ``assigned`` with the student's answers (``sub.answers``,
    placed in the task's rows by ``sub.placement``), coloured and commented."""
    w = words(lang)
    book = openpyxl.load_workbook(assigned)
    sheets = set(book.sheetnames)
    for item in assignment.items:
        if item.key not in g.items or f"a_{item.key}" not in book.defined_names:
            continue
        points, results = g.items[item.key]
        each = item.points / len(results) if results else 0.0
        found = parse_reference(f"a_{item.key}", book.defined_names[f"a_{item.key}"].attr_text,
                                sheets)
        cells = [book[found.sheet].cell(row, col)
                 for row in range(found.min_row, found.max_row + 1)
                 for col in range(found.min_col, found.max_col + 1)]
        typed = sub.answers.get(item.key, [])
        placement = sub.placement.get(item.key, list(range(len(typed))))
        first_of = {}                    # key row -> the hand-in's row graded for it
        for index, key_row in enumerate(placement):
            if key_row is not None and index < len(typed):
                first_of.setdefault(key_row, index)
        for key_row, cell in enumerate(cells):
            if key_row >= len(results):
                continue
            if key_row in first_of:
                _type_answer(cell, typed[first_of[key_row]])
            result = results[key_row]
            kind = kind_of(result)
            cell.fill = PatternFill("solid", fgColor=FILLS[kind])
            text = say(w, "return_cell", reason=say(w, result.reason, **result.detail),
                       points=_points(result.fraction * each), max_points=_points(each))
            if mode == "full" and kind != "right":
                text += w["separator"] + say(w, "return_expected",
                                             expected=shown(result.expected, item),
                                             unit=unit_text(item.unit))
            if mode != "score-only" or kind in ("unreadable", "empty"):
                comment = Comment(text, "crankbook")
                comment.width, comment.height = 260, 90
                cell.comment = comment
    book.properties.title = assignment.name(lang)
    _score_box(book, g, assignment, lang, w)
    _save_reproducibly(book, target)


def _type_answer(cell, value):
    """The student's value as a value — a number, a bool, or text kept as text (an
    answer typed as "=…" is never turned into a formula here)."""
    if value is None or value == "":
        return
    if isinstance(value, bool) or (isinstance(value, float) and math.isfinite(value)):
        cell.value = value
        return
    cell.value = str(value)[:MAX_TEXT]
    cell.data_type = "s"


def _save_reproducibly(book, target):
    """Same submission, same bytes: openpyxl's ``save`` stamps the clock into the core
    properties and into every zip entry, so the file is written here with the
    workbooks' fixed time in both."""
    book.properties.modified = FIXED_TIME
    buffer = io.BytesIO()
    ExcelWriter(book, zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED)).save()
    with zipfile.ZipFile(buffer) as source, \
            zipfile.ZipFile(target, "w", zipfile.ZIP_DEFLATED) as archive:
        for entry in source.infolist():
            fixed = zipfile.ZipInfo(entry.filename, date_time=FIXED_TIME.timetuple()[:6])
            fixed.compress_type = zipfile.ZIP_DEFLATED
            archive.writestr(fixed, source.read(entry))


def _score_box(book, g, assignment, lang, w):
    """A first sheet of its own: the total, each item's points, the notes, the colours."""
    ws = book.create_sheet(w["return_box_title"][:31], 0)
    book.active = 0
    for sheet in book.worksheets[1:]:
        sheet.sheet_view.tabSelected = False
    thin = Side(style="thin", color="808080")
    box = Border(left=thin, right=thin, top=thin, bottom=thin)
    ws.cell(1, 1, say(w, "title_feedback", assignment=assignment.name(lang),
                      student_id=g.student_id, name=g.name)).font = Font(bold=True, size=13)
    total = ws.cell(2, 1, say(w, "score", score=_points(g.score),
                              max_score=_points(assignment.max_score)).replace("**", ""))
    total.font = Font(bold=True, size=12)
    total.fill = PatternFill("solid", fgColor="DDEBF7")
    row = 3
    for word, fields in student_notes(g):
        ws.cell(row, 1, say(w, word, **fields)).alignment = Alignment(wrap_text=True)
        row += 1
    row += 1
    for item in assignment.items:
        if item.key not in g.items:
            continue
        points = g.items[item.key][0]
        ws.cell(row, 1, item.label(lang)).border = box
        cell = ws.cell(row, 2, f"{_points(points)} / {_points(item.points)}")
        cell.border = box
        cell.alignment = Alignment(horizontal="right")
        row += 1
    row += 1
    for kind, word in (("right", "return_right"), ("partial", "return_partial"),
                       ("wrong", "return_wrong"), ("unreadable", "return_unreadable"),
                       ("empty", "return_empty")):
        ws.cell(row, 1, w[word]).fill = PatternFill("solid", fgColor=FILLS[kind])
        row += 1
    ws.column_dimensions["A"].width = 60
    ws.column_dimensions["B"].width = 14
    ws.page_setup.fitToWidth = 1
    ws.page_setup.fitToHeight = 0
    ws.sheet_properties.pageSetUpPr.fitToPage = True


def feedback_html(g, assignment, lang, mode):
    """The feedback as one self-contained HTML page (no scripts, no links)."""
    w = words(lang)
    e = html.escape
    title = say(w, "title_feedback", assignment=assignment.name(lang), student_id=g.student_id,
                name=g.name)
    parts = [f'<!DOCTYPE html><html lang="{lang}"><head><meta charset="utf-8">'
             f'<meta name="viewport" content="width=device-width, initial-scale=1">'
             f"<title>{e(title)}</title><style>body{{font-family:sans-serif;max-width:48em;"
             f"margin:1em auto;padding:0 1em}}td,th{{border:1px solid #999;padding:2px 6px}}"
             f"table{{border-collapse:collapse}}.wrong{{background:#FFC7CE}}</style></head><body>",
             f"<h1>{e(title)}</h1>"]
    if g.status != "graded":
        status = say(w, "status_missing") if g.status == "missing" else \
            say(w, "status_unreadable", reason=reason_text(g.problem, lang))
        parts.append(f"<p><strong>{e(status)}</strong></p>")
    else:
        score = say(w, "score", score=_points(g.score), max_score=_points(assignment.max_score))
        parts.append(f"<p><strong>{e(score.replace('**', ''))}</strong></p>")
        notes = student_notes(g)
        if notes:
            parts.append("<ul>" + "".join(f"<li>{e(say(w, word, **fields))}</li>"
                                          for word, fields in notes) + "</ul>")
        for head, details in _item_summary(g, assignment, lang, mode):
            parts.append(f"<h2>{e(head)}</h2>")
            if details:
                parts.append("<ul>" + "".join(f'<li class="wrong">{e(d)}</li>' for d in details)
                             + "</ul>")
    parts.append("</body></html>\n")
    return "\n".join(parts)
