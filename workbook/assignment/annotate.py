"""`grade --return DIR`: each student's own workbook back, graded where they typed.

Every answer cell the grader read is coloured (right, partial, wrong, unreadable,
empty) and carries a comment in the class's language — the reason and the cell's
points, the expected value only with ``--feedback full`` — and the first sheet gets
a score box.  Beside it, ``<id>.html``: the feedback as a page any phone opens.
Only the student's own file, own values and own notes go in: never a flag, a
suspicion or another student's id (the private notes stay in the teacher's files).
"""
import html
import io
import zipfile
from pathlib import Path

import openpyxl
from openpyxl.writer.excel import ExcelWriter
from openpyxl.comments import Comment
from openpyxl.packaging.core import DocumentProperties
from openpyxl.packaging.custom import CustomPropertyList
from openpyxl.styles import Alignment, Border, Font, PatternFill, Side

from crankbook.assignment.results import (_item_summary, _points, reason_text, say, shown,
                                          student_notes, words)
from crankbook.writer.build import FIXED_TIME
from crankbook.writer.layout import unit_text
from crankbook.reading.workbook_reader import parse_reference

FILLS = {"right": "C6EFCE", "partial": "FFEB9C", "wrong": "FFC7CE", "unreadable": "D9D2E9",
         "empty": "EDEDED"}
UNREADABLE = ("not_a_number", "wrong_unit")
# openpyxl holds a whole workbook in memory: a file far larger than any task's is
# graded (the bounded reader) but only its HTML page goes back
MAX_ANNOTATED = 8 * 2**20


def kind_of(cell):
    """right / partial / wrong / unreadable / empty for one CellResult."""
    if cell.reason == "no_answer":
        return "empty"
    if cell.reason in UNREADABLE:
        return "unreadable"
    if cell.fraction >= 1.0:
        return "right"
    return "partial" if cell.fraction > 0 else "wrong"


def write_returns(directory, assignment, lang, grades, chosen, mode):
    """``directory``/<id>.xlsx (graded students) and <id>.html (every student)."""
    directory = Path(directory)
    for g in grades:
        sub = chosen.get(g.student_id)
        (directory / f"{g.student_id}.html").write_text(
            feedback_html(g, assignment, lang, mode), encoding="utf-8")
        if g.status == "graded" and sub is not None and sub.size <= MAX_ANNOTATED:
            try:
                annotate(sub, g, assignment, lang, mode, directory / f"{g.student_id}.xlsx")
            except Exception:        # one odd file costs its own return, not the class's
                (directory / f"{g.student_id}.xlsx").unlink(missing_ok=True)


def annotate(sub, g, assignment, lang, mode, target):
    w = words(lang)
    book = openpyxl.load_workbook(sub.path)
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
        placement = sub.placement.get(item.key, list(range(len(cells))))
        for index, cell in enumerate(cells):
            key_row = placement[index] if index < len(placement) else None
            if key_row is None or key_row >= len(results):
                continue
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
    _own_identity(book, g, sheets, assignment.name(lang))
    _score_box(book, g, assignment, lang, w)
    _save_reproducibly(book, target)


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


def _own_identity(book, g, sheets, title):
    """The returned file names its owner only: a file handed in with another student's
    id, name, author or document properties (a copy: title, subject, keywords, a
    custom "owner") goes back with the owner's own, and with crankbook's properties
    alone (``check`` and ``audit`` still know the file by them)."""
    for name, value in (("s_student_id", g.student_id), ("s_student_name", g.name)):
        if name in book.defined_names:
            found = parse_reference(name, book.defined_names[name].attr_text, sheets)
            book[found.sheet].cell(found.min_row, found.min_col).value = value
    book.properties = DocumentProperties(title=title, creator="crankbook",
                                         lastModifiedBy="crankbook", created=FIXED_TIME)
    ours = [p for p in book.custom_doc_props.props if p.name.startswith("crankbook_")]
    book.custom_doc_props = CustomPropertyList()
    for prop in ours:
        book.custom_doc_props.append(prop)


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
