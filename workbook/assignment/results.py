"""Grading results: gradebook, LMS import, per-student feedback, class report.

Text from submissions is untrusted: every CSV field that a spreadsheet would read as
a formula (starting with = + - @ or a control character) is prefixed with '.
"""
import csv
import io
from pathlib import Path

import xlsxwriter

from crankbook.atomic import atomic_path
from crankbook.writer.build import FIXED_TIME
from crankbook.writer.layout import unit_text
from crankbook.writer.styles import Styles

FORMULA_START = ("=", "+", "-", "@", "\t", "\r", "\n")


def safe(value):
    """A CSV field that no spreadsheet will execute."""
    if isinstance(value, str) and value.startswith(FORMULA_START):
        return "'" + value
    return value


def _atomic_text(path, text):
    with atomic_path(path) as temporary:
        Path(temporary).write_text(text, encoding="utf-8", newline="")


def _csv(rows):
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    for row in rows:
        writer.writerow([safe(v) for v in row])
    return buffer.getvalue()


def _fmt(x):
    if x is None or x == "":
        return "—"
    if isinstance(x, float):
        return f"{x:.6g}"
    return str(x)


def write_results(output, assignment, spec, grades, unmatched):
    output = Path(output)
    output.mkdir(parents=True, exist_ok=True)
    items = [i.key for i in assignment.items]
    header = ["student_id", "name", "status", "score", "max_score", "flags", *items, "notes"]
    rows = [header]
    for g in grades:
        notes = g.details + ([g.problem] if g.problem else []) + \
            ([f"files: {', '.join(g.files)}"] if g.files else [])
        rows.append([g.student_id, g.name, g.status, round(g.score, 2), assignment.max_score,
                     ";".join(g.flags),
                     *[round(g.items[k][0], 2) if k in g.items else 0 for k in items],
                     "; ".join(notes)])
    for sub in unmatched:
        notes = [f"file {sub.relative} matches no roster student"
                 + (f" (it says {sub.inside_id})" if sub.inside_id else "")]
        if sub.problem:
            notes.append(sub.problem)
        rows.append(["", "", "unmatched", "", assignment.max_score, "", *["" for _ in items],
                     "; ".join(notes)])
    _atomic_text(output / "gradebook.csv", _csv(rows))

    lms = [["identifier", "grade", "feedback"]]
    for g in grades:
        summary = {"graded": f"{g.score:.1f}/{assignment.max_score:g}",
                   "missing": "no submission", "unreadable": f"unreadable: {g.problem}"}[g.status]
        flags = f" Flags: {', '.join(g.flags)} ({'; '.join(g.details)})." if g.flags else ""
        lms.append([g.student_id, round(g.score, 2) if g.status == "graded" else 0,
                    f"{summary}.{flags} See feedback/{g.student_id}.md."])
    _atomic_text(output / "lms-import.csv", _csv(lms))

    for g in grades:
        _atomic_text(output / "feedback" / f"{g.student_id}.md", _feedback(g, assignment, spec))
    _class_report(output / "class-report.xlsx", assignment, grades)


def _feedback(g, assignment, spec):
    lines = [f"# {assignment.en} — {g.student_id} {g.name}", ""]
    if g.status != "graded":
        lines += [f"Status: **{g.status}**" + (f" — {g.problem}" if g.problem else ""), ""]
        return "\n".join(lines) + "\n"
    lines += [f"Score: **{g.score:.2f} / {assignment.max_score:g}**", ""]
    if g.flags:
        lines += ["Flags: " + ", ".join(g.flags) + " — " + "; ".join(g.details), ""]
    for item in assignment.items:
        points, cells = g.items[item.key]
        quantity = spec.quantity[item.key]
        lines += [f"## a_{item.key}: {quantity.en} [{unit_text(quantity.unit)}] — "
                  f"{points:.2f} / {item.points:g} points", "",
                  "| # | your value | expected | credit | reason |", "|---|---|---|---|---|"]
        for n, cell in enumerate(cells, start=1):
            value = str(_fmt(cell.value)).replace("|", "\\|")
            lines.append(f"| {n} | {value} | {_fmt(float(cell.expected))} | "
                         f"{cell.fraction:.0%} | {cell.reason} |")
        lines.append("")
    return "\n".join(lines) + "\n"


def _class_report(path, assignment, grades):
    with atomic_path(path) as temporary:
        _write_class_report(temporary, assignment, grades)


def _write_class_report(temporary, assignment, grades):
    graded = [g for g in grades if g.status == "graded"]
    book = xlsxwriter.Workbook(temporary)
    book.set_properties({"title": "Class report", "author": "crankbook", "created": FIXED_TIME})
    styles = Styles(book)
    ws = book.add_worksheet("Items")
    ws.write(0, 0, f"{assignment.en}: class report ({len(graded)} graded of {len(grades)})",
             styles.title)
    for col, text in enumerate(["item", "points", "mean score", "mean %", "success rate"]):
        ws.write(2, col, text, styles.header)
    ws.set_column(0, 0, 30)
    ws.set_column(1, 4, 13)
    for row, item in enumerate(assignment.items, start=3):
        scores = [g.items[item.key][0] for g in graded]
        cells = [c for g in graded for c in g.items[item.key][1]]
        mean = sum(scores) / len(scores) if scores else 0.0
        success = sum(c.fraction == 1.0 for c in cells) / len(cells) if cells else 0.0
        ws.write(row, 0, f"a_{item.key}")
        ws.write_number(row, 1, item.points)
        ws.write_number(row, 2, mean, styles.number("-", "0.00"))
        ws.write_formula(row, 3, f"=IF(B{row + 1}=0,0,C{row + 1}/B{row + 1})",
                         styles.number("-", "0.0%"), mean / item.points if item.points else 0)
        ws.write_number(row, 4, success, styles.number("-", "0.0%"))
    last = 3 + len(assignment.items) - 1
    chart = book.add_chart({"type": "bar"})
    chart.add_series({"name": "mean % of points", "categories": ["Items", 3, 0, last, 0],
                      "values": ["Items", 3, 3, last, 3], "fill": {"color": "#4F81BD"}})
    chart.add_series({"name": "success rate (cells fully right)",
                      "categories": ["Items", 3, 0, last, 0], "values": ["Items", 3, 4, last, 4],
                      "fill": {"color": "#9BBB59"}})
    chart.set_title({"name": "Per-item results"})
    chart.set_x_axis({"name": "fraction", "min": 0, "max": 1, "num_format": "0%"})
    chart.set_size({"width": 720, "height": 420})
    ws.insert_chart(2, 6, chart)

    dist = book.add_worksheet("Totals")
    dist.write(0, 0, "Distribution of total scores", styles.title)
    for col, text in enumerate(["from %", "to %", "students"]):
        dist.write(2, col, text, styles.header)
    bins = [0] * 10
    for g in graded:
        share = g.score / assignment.max_score if assignment.max_score else 0
        bins[min(int(share * 10), 9)] += 1
    for i, count in enumerate(bins):
        dist.write_number(3 + i, 0, i * 10)
        dist.write_number(3 + i, 1, (i + 1) * 10)
        dist.write_number(3 + i, 2, count)
    hist = book.add_chart({"type": "column"})
    hist.add_series({"name": "students", "categories": ["Totals", 3, 1, 12, 1],
                     "values": ["Totals", 3, 2, 12, 2], "gap": 20})
    hist.set_title({"name": "Total scores (upper bin edge, %)"})
    hist.set_x_axis({"name": "score up to … % of the points"})
    hist.set_y_axis({"name": "students"})
    hist.set_legend({"none": True})
    dist.insert_chart(2, 4, hist)
    students = book.add_worksheet("Students")
    for col, text in enumerate(["student_id", "name", "status", "score", "flags", "notes"]):
        students.write(0, col, text, styles.header)
    for row, g in enumerate(grades, start=1):
        students.write_string(row, 0, g.student_id)
        students.write_string(row, 1, g.name)
        students.write_string(row, 2, g.status)
        students.write_number(row, 3, round(g.score, 2))
        students.write_string(row, 4, ";".join(g.flags))
        students.write_string(row, 5, "; ".join(g.details + ([g.problem] if g.problem else [])))
    for sheet in book.worksheets():
        sheet.set_paper(9)
        sheet.set_landscape()
        sheet.fit_to_pages(1, 0)
    book.close()
