"""Grading results in the class's language: gradebook, LMS import, per-student
feedback and the class report.

* ``gradebook.csv`` (UTF-8 with BOM, so Excel shows Chinese): student_id, name,
  status, score, max_score, flags, one column of points per item (headed by the
  item's name in words), notes.
* ``lms-import.csv``: identifier, grade, feedback; a missing student's grade is
  blank (an LMS records no submission, not a zero) unless ``missing_as_zero``.
* ``feedback/<id>.md``: ``full`` (every value with the expected one), ``hints``
  (which items and cells are wrong and why, no expected values — for a
  resubmission round) or ``score-only``.
* ``class-report.xlsx``: per item, the distribution of totals, the students.

Every CSV field is made safe for spreadsheets (crankbook.csv_safety).
"""
import math
from pathlib import Path

import xlsxwriter

from crankbook import resources
from crankbook.csv_safety import csv_text
from crankbook.writer.build import FIXED_TIME
from crankbook.writer.layout import unit_text
from crankbook.writer.print_setup import landscape_page
from crankbook.writer.styles import Styles

FEEDBACK_MODES = ("full", "hints", "score-only")


def words(lang):
    return resources.read_toml("words", "grading.toml")[lang]


def say(w, word, **fields):
    text = w.get(word, word)
    if "rule" in fields:
        fields = dict(fields, rule=w.get(fields["rule"], fields["rule"]))
    if "what" in fields:
        fields = dict(fields, what=w.get(fields["what"], fields["what"]))
    return text.format(**fields)


def _fmt(x):
    if x is None or x == "":
        return "—"
    if isinstance(x, float):
        return "—" if math.isnan(x) else f"{x:.6g}"
    return str(x).replace("|", "\\|").replace("\n", " ")[:40]


def _points(x):
    return f"{x:.2f}".rstrip("0").rstrip(".")


def write_results(output, assignment, spec, lang, grades, unmatched, feedback="full",
                  missing_as_zero=False):
    output = Path(output)
    w = words(lang)
    items = assignment.items
    # fixed column names (a second round and an LMS read them); the items by name in
    # the class's language, the notes in it too
    header = ["student_id", "name", "status", "score", "max_score", "flags",
              *[f"{i.label(lang)} (a_{i.key})" for i in items], "notes"]
    rows = [header]
    for g in grades:
        notes = [say(w, word, **fields) for word, fields in g.notes]
        if g.problem:
            notes.append(say(w, "status_unreadable", reason=g.problem))
        graded = g.status == "graded"
        rows.append([g.student_id, g.name, g.status,
                     round(g.score, 2) if graded or missing_as_zero else "",
                     assignment.max_score, ";".join(g.flags),
                     *[round(g.items[i.key][0], 2) if i.key in g.items else "" for i in items],
                     "; ".join(notes)])
    for sub in unmatched:
        note = say(w, "unmatched", file=sub.relative)
        if sub.inside_id:
            note += say(w, "unmatched_inside", inside=sub.inside_id)
        if sub.problem:
            note += "; " + say(w, "status_unreadable", reason=sub.problem)
        rows.append(["", "", "unmatched", "", assignment.max_score, "", *["" for _ in items], note])
    (output / "gradebook.csv").write_text(csv_text(rows), encoding="utf-8-sig", newline="")

    lms = [["identifier", "grade", "feedback"]]
    for g in grades:
        if g.status == "graded":
            text = say(w, "lms_graded", score=_points(g.score),
                       max_score=_points(assignment.max_score))
            grade = round(g.score, 2)
        elif g.status == "missing":
            text, grade = say(w, "lms_missing"), 0 if missing_as_zero else ""
        else:
            text, grade = say(w, "lms_unreadable", reason=g.problem), 0 if missing_as_zero else ""
        if g.flags:
            text += " " + w["separator"].join(say(w, word, **fields)
                                              for word, fields in g.notes) + w["stop"]
        lms.append([g.student_id, grade, text + " " + say(w, "lms_see", student_id=g.student_id)])
    (output / "lms-import.csv").write_text(csv_text(lms), encoding="utf-8", newline="")

    (output / "feedback").mkdir()
    for g in grades:
        (output / "feedback" / f"{g.student_id}.md").write_text(
            feedback_text(g, assignment, lang, feedback), encoding="utf-8")
    write_class_report(output / "class-report.xlsx", assignment, lang, grades)


def feedback_text(g, assignment, lang, mode):
    w = words(lang)
    lines = [f"# {say(w, 'title_feedback', assignment=assignment.name(lang), student_id=g.student_id, name=g.name)}",
             ""]
    if g.status != "graded":
        status = say(w, "status_missing") if g.status == "missing" else \
            say(w, "status_unreadable", reason=g.problem)
        return "\n".join(lines + [f"**{status}**", ""]) + "\n"
    lines += [say(w, "score", score=_points(g.score), max_score=_points(assignment.max_score)), ""]
    if g.notes:
        lines += [w["flags"], ""] + [f"- {say(w, word, **fields)}" for word, fields in g.notes]
        lines.append("")
    for item in assignment.items:
        if item.key not in g.items:
            continue
        points, cells = g.items[item.key]
        lines += [f"## {say(w, 'item_heading', label=item.label(lang), unit=unit_text(item.unit), points=_points(points), max_points=_points(item.points))}",
                  ""]
        if mode == "score-only":
            continue
        shown = cells if mode == "full" else [c for c in cells if c.fraction < 1]
        if not shown:
            lines += [w["all_right"], ""]
            continue
        if mode == "full":
            lines += [w["table_full"], "|---|---|---|---|---|"]
        else:
            lines += [w["table_hints"], "|---|---|---|---|"]
        for cell in shown:
            label = cell.label or w["scalar_row"]
            reason = say(w, cell.reason, **cell.detail)
            if mode == "full":
                lines.append(f"| {label} | {_fmt(cell.value)} | {_fmt(float(cell.expected))} | "
                             f"{cell.fraction:.0%} | {reason} |")
            else:
                lines.append(f"| {label} | {_fmt(cell.value)} | {cell.fraction:.0%} | {reason} |")
        lines.append("")
    return "\n".join(lines) + "\n"


def _width(texts, least=10, most=60):
    from crankbook.assignment.student_book import display_width
    return max(least, min(most, max((display_width(str(t)) for t in texts), default=0) + 2))


def write_class_report(path, assignment, lang, grades):
    w = words(lang)
    graded = [g for g in grades if g.status == "graded" and g.kept is None]
    book = xlsxwriter.Workbook(str(path), {"strings_to_formulas": False,
                                           "strings_to_numbers": False, "strings_to_urls": False})
    book.set_properties({"title": w["report_title"].format(assignment=assignment.name(lang),
                                                           graded=len(graded), total=len(grades)),
                         "author": "crankbook", "created": FIXED_TIME})
    styles = Styles(book)
    ws = book.add_worksheet(w["report_items"])
    ws.write(0, 0, w["report_title"].format(assignment=assignment.name(lang), graded=len(graded),
                                            total=len(grades)), styles.title)
    for col, word in enumerate(["col_item", "col_points", "col_mean", "col_mean_pct",
                                "col_success"]):
        ws.write(2, col, w[word], styles.header)
    labels = [i.label(lang) for i in assignment.items]
    ws.set_column(0, 0, _width(labels, 20))
    ws.set_column(1, 4, 14)
    for row, item in enumerate(assignment.items, start=3):
        scores = [g.items[item.key][0] for g in graded if item.key in g.items]
        cells = [c for g in graded if item.key in g.items for c in g.items[item.key][1]]
        mean = sum(scores) / len(scores) if scores else 0.0
        success = sum(c.fraction == 1.0 for c in cells) / len(cells) if cells else 0.0
        ws.write(row, 0, item.label(lang))
        ws.write_number(row, 1, item.points)
        ws.write_number(row, 2, mean, styles.number("-", "0.00"))
        ws.write_formula(row, 3, f"=IF(B{row + 1}=0,0,C{row + 1}/B{row + 1})",
                         styles.number("-", "0.0%"), mean / item.points if item.points else 0)
        ws.write_number(row, 4, success, styles.number("-", "0.0%"))
    last = 3 + len(assignment.items) - 1
    chart = book.add_chart({"type": "bar"})
    chart.add_series({"name": w["chart_mean"], "categories": [w["report_items"], 3, 0, last, 0],
                      "values": [w["report_items"], 3, 3, last, 3], "fill": {"color": "#4F81BD"}})
    chart.add_series({"name": w["chart_success"],
                      "categories": [w["report_items"], 3, 0, last, 0],
                      "values": [w["report_items"], 3, 4, last, 4], "fill": {"color": "#9BBB59"}})
    chart.set_title({"name": w["chart_items"]})
    chart.set_x_axis({"name": w["axis_fraction"], "min": 0, "max": 1, "num_format": "0%",
                      "major_unit": 0.25})
    chart.set_y_axis({"reverse": True})
    chart.set_legend({"position": "bottom"})
    chart.set_size({"width": 720, "height": max(420, 28 * len(assignment.items) + 120)})
    ws.insert_chart(2, 6, chart)

    dist = book.add_worksheet(w["report_totals"])
    dist.write(0, 0, w["chart_totals"], styles.title)
    for col, word in enumerate(["col_from", "col_to", "col_students"]):
        dist.write(2, col, w[word], styles.header)
    bins = [0] * 10
    for g in graded:
        share = g.score / assignment.max_score if assignment.max_score else 0
        bins[min(int(share * 10), 9)] += 1
    for i, count in enumerate(bins):
        dist.write_number(3 + i, 0, i * 10)
        dist.write_number(3 + i, 1, (i + 1) * 10)
        dist.write_number(3 + i, 2, count)
        dist.write_string(3 + i, 3, f"{i * 10}–{(i + 1) * 10} %")
    hist = book.add_chart({"type": "column"})
    hist.add_series({"name": w["col_students"], "categories": [w["report_totals"], 3, 3, 12, 3],
                     "values": [w["report_totals"], 3, 2, 12, 2], "gap": 20,
                     "data_labels": {"value": True}})
    hist.set_title({"name": w["chart_totals"]})
    hist.set_x_axis({"name": w["axis_score"]})
    hist.set_y_axis({"name": w["axis_students"], "min": 0, "major_unit": 1,
                     "max": max(bins) + 1, "num_format": "0"})
    hist.set_legend({"none": True})
    dist.insert_chart(2, 5, hist)

    students = book.add_worksheet(w["report_students"])
    notes = {g.student_id: "; ".join(say(w, word, **fields) for word, fields in g.notes)
             + (("; " if g.notes else "") + g.problem if g.problem else "") for g in grades}
    for col, word in enumerate(["col_student_id", "col_name", "col_status", "col_score",
                                "col_flags", "col_notes"]):
        students.write(0, col, w[word], styles.header)
    students.set_column(0, 0, _width([g.student_id for g in grades], 12))
    students.set_column(1, 1, _width([g.name for g in grades], 12))
    students.set_column(2, 4, 14)
    students.set_column(5, 5, _width(notes.values(), 20, 90), styles.text)
    for row, g in enumerate(grades, start=1):
        students.write_string(row, 0, g.student_id)
        students.write_string(row, 1, g.name)
        students.write_string(row, 2, {"graded": w["status_graded"], "missing": w["status_missing"]}
                              .get(g.status, g.status))
        if g.status == "graded":
            students.write_number(row, 3, round(g.score, 2))
        students.write_string(row, 4, ";".join(g.flags))
        students.write_string(row, 5, notes[g.student_id])
    students.freeze_panes(1, 2)
    for sheet in book.worksheets():
        landscape_page(sheet)
    book.close()
