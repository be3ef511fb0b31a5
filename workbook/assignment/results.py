"""Grading results in the class's language: gradebook, LMS import, per-student
feedback, the teacher's integrity report and the class report.

Teacher side (may name students and flags):

* ``gradebook.csv`` (UTF-8 with BOM, text quoted): student_id, name, the roster's
  other columns (班级, …), status (a token: graded, missing, unreadable),
  status_text, score, max_score, flags (tokens), flags_text, one column of points
  per item (headed by the item's name in words and its ``a_`` key), notes.
* ``gradebook.xlsx``: the same table as Excel opens it, ids stored as text.
* ``integrity.xlsx``: one row per suspected pair (who, whom, what, evidence,
  suggested action), then the other flags.
* ``grades.json``: every cell of every student, for the next round's ``--previous``.
* ``class-report.xlsx``: per item, per class, the distribution of totals, the students.

Student side (never a flag, a suspicion or another student's id):

* ``lms-import.csv`` (identifier, grade, feedback): the feedback self-contained text;
  a missing student's grade blank (an LMS records no submission, not a zero) unless
  ``missing_as_zero``.
* ``feedback/<id>.md``: ``full`` (every value with the expected one, rounded to the
  item's precision), ``hints`` (which cells are wrong and why, no expected values)
  or ``score-only``.

Every CSV field is made safe for spreadsheets (crankbook.support.csv_safety).
"""
import math
from pathlib import Path

import xlsxwriter

from crankbook.support import resources
from crankbook.assignment import rounds
from crankbook.support.csv_safety import csv_text, kept_text
from crankbook.writer.build import FIXED_TIME
from crankbook.writer.layout import unit_text
from crankbook.writer.print_setup import landscape_page, row_points, wide_table_page
from crankbook.writer.styles import Styles

FEEDBACK_MODES = ("full", "hints", "score-only")
WORKBOOK_OPTIONS = {"strings_to_formulas": False, "strings_to_numbers": False,
                    "strings_to_urls": False}


def words(lang):
    return resources.read_toml("words", "grading.toml")[lang]


def reason_text(problem, lang):
    """Why a file is unreadable, in the class's language (templates/words/grading.toml
    [[reason]]); the reader's own words where no pattern matches."""
    import re
    for entry in resources.read_toml("words", "grading.toml").get("reason", []):
        match = re.search(entry["pattern"], problem or "")
        if match and lang in entry:
            return entry[lang].format(None, *match.groups())
    return problem


def say(w, word, **fields):
    text = w.get(word, word)
    for name in ("rule", "what"):
        if name in fields:
            fields = dict(fields, **{name: w.get(fields[name], fields[name])})
    fields = {name: w["list"].join(map(str, value)) if isinstance(value, list) else value
              for name, value in fields.items()}
    return text.format(**fields)


def shown(value, item=None, typed=False):
    """A number as a person reads it: rounded to the item's precision (a digit finer
    than its absolute floor), 0 as 0, no float noise; a student's ``typed`` number
    keeps at least four significant digits (0.0362 typed for 36.2 is not "0")."""
    if value is None or value == "":
        return "—"
    if not isinstance(value, (int, float)):
        return str(value).replace("|", "\\|").replace("\n", " ")[:40]
    if not math.isfinite(value):
        return "—"
    floor = getattr(item, "abs_floor", 0.0) or 0.0
    decimals = max(0, math.ceil(-math.log10(floor)) + 1) if floor > 0 else 6
    if typed and value and abs(value) < TINY:
        return _powers_of_ten(value)
    if typed and value:
        decimals = min(12, max(decimals, 3 - math.floor(math.log10(abs(value)))))
    text = f"{value:.{decimals}f}"
    if "." in text:
        text = text.rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


TINY = 1e-4                       # a typed number below this is shown as a × 10⁻ⁿ
SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def _powers_of_ten(value):
    """A tiny typed number as a person reads it: "−2 × 10⁻⁷", not "-0.0000002"
    (nor "2e-07"), four significant digits at most."""
    mantissa, exponent = f"{value:.3e}".split("e")
    mantissa = mantissa.rstrip("0").rstrip(".").replace("-", "−")
    return f"{mantissa} × 10{str(int(exponent)).translate(SUPERSCRIPT)}"


def _points(x):
    return f"{x:.2f}".rstrip("0").rstrip(".")


# flags whose notes name or hint at another student: the teacher's files only
TEACHER_ONLY_FLAGS = ("copy-suspect", "wrong-student", "path-names-other",
                      "multiple-submissions", "leaked-key")


def student_notes(g):
    return [(word, fields) for word, fields, private in g.notes if not private]


def write_results(output, assignment, spec, lang, grades, unmatched, feedback="full",
                  missing_as_zero=False, suspicions=()):
    output = Path(output)
    w = words(lang)
    table = gradebook_rows(assignment, lang, grades, unmatched, missing_as_zero)
    (output / "gradebook.csv").write_text(csv_text(table), encoding="utf-8-sig", newline="")
    write_gradebook_xlsx(output / "gradebook.xlsx", table, w)

    lms = [["identifier", "grade", "feedback"]]
    for g in grades:
        grade = round(g.score, 2) if g.status == "graded" else \
            (0 if missing_as_zero else "")
        lms.append([g.student_id, grade, lms_text(g, assignment, lang, feedback)])
    (output / "lms-import.csv").write_text(csv_text(lms), encoding="utf-8-sig", newline="")

    (output / "feedback").mkdir()
    for g in grades:
        (output / "feedback" / f"{g.student_id}.md").write_text(
            feedback_text(g, assignment, lang, feedback), encoding="utf-8")
    write_integrity_report(output / "integrity.xlsx", lang, grades, suspicions,
                           {sheet.key: (sheet.zh if lang == "zh" else sheet.en)
                            for sheet in assignment.sheets})
    rounds.save(output / rounds.FILE, grades, assignment, suspicions)
    write_class_report(output / "class-report.xlsx", assignment, lang, grades)


def gradebook_rows(assignment, lang, grades, unmatched, missing_as_zero):
    w = words(lang)
    items = assignment.items
    extra = list(grades[0].extra) if grades else []
    # fixed machine names (a second round and scripts read them), then words
    header = ["student_id", "name", *extra, "status", "status_text", "score", "max_score",
              "flags", "flags_text", *[f"{i.label(lang)} (a_{i.key})" for i in items], "notes",
              "overrides"]
    rows = [header]
    for g in grades:
        notes = [say(w, word, **fields) for word, fields, _ in g.notes]
        if g.problem:
            notes.append(say(w, "status_unreadable", reason=reason_text(g.problem, lang)))
        graded = g.status == "graded"
        rows.append([kept_text(g.student_id), g.name,
                     *[kept_text(g.extra.get(f, "")) for f in extra], g.status,
                     w.get(f"state_{g.status}", g.status),
                     round(g.score, 2) if graded else (0 if missing_as_zero else ""),
                     assignment.max_score, ";".join(g.flags),
                     w["separator"].join(w.get(f"flag_{f}", f) for f in g.flags),
                     *[round(g.items[i.key][0], 2) if i.key in g.items else "" for i in items],
                     w["separator"].join(notes), " | ".join(g.overrides)])
    for sub in unmatched:
        note = say(w, "unmatched", file=sub.relative)
        if sub.inside_id:
            note += say(w, "unmatched_inside", inside=sub.inside_id)
        if getattr(sub, "ambiguous", None):
            note += say(w, "unmatched_ambiguous", ids=", ".join(sub.ambiguous))
        if sub.problem:
            note += w["separator"] + say(w, "status_unreadable",
                                         reason=reason_text(sub.problem, lang))
        rows.append(["", "", *["" for _ in extra], "unmatched", w["state_unmatched"], "",
                     assignment.max_score, "", "", *["" for _ in items], note, ""])
    return rows


GRADEBOOK_HEADINGS = {"student_id": "col_student_id", "name": "col_name",
                      "status": "col_status_code", "status_text": "col_status",
                      "score": "col_score", "max_score": "col_points",
                      "flags": "col_flags_code", "flags_text": "col_flags",
                      "notes": "col_notes", "overrides": "col_overrides"}
GRADEBOOK_NOTES_WIDTH = 60         # characters: the notes and overrides columns, wrapped


def write_gradebook_xlsx(path, table, w):
    """The gradebook as Excel opens it: ids and names as text (leading zeros and 12-digit
    学号 intact), points as numbers."""
    book = xlsxwriter.Workbook(str(path), WORKBOOK_OPTIONS)
    book.set_properties({"title": w["gradebook_title"], "author": "crankbook",
                         "created": FIXED_TIME})
    styles = Styles(book)
    ws = book.add_worksheet(w["gradebook_sheet"])
    header = table[0]
    text_columns = {i for i, name in enumerate(header)
                    if name not in ("score", "max_score") and "(a_" not in name}
    # a number under a wrapped header; words as wide as they are, the notes wrapped:
    # a column as wide as its longest header or note printed the class microscopic
    widths = [_width((row[col] for row in table[1:] if col < len(row)), 8,
                     GRADEBOOK_NOTES_WIDTH if name in ("notes", "overrides") else 18)
              if col in text_columns else 9 for col, name in enumerate(header)]
    # the class's words over the columns (the CSV keeps the fixed names scripts read)
    shown = [w.get(GRADEBOOK_HEADINGS.get(name, ""), name) for name in header]
    for col, name in enumerate(shown):
        ws.write_string(0, col, name, styles.header)
        ws.set_column(col, col, widths[col], styles.top)
    ws.set_row(0, row_points(zip(shown, widths), bold=True))
    for r, row in enumerate(table[1:], start=1):
        for col, value in enumerate(row):
            if value == "" or value is None:
                continue
            if col in text_columns or not isinstance(value, (int, float)):
                ws.write_string(r, col, str(value), styles.text)
            else:
                ws.write_number(r, col, float(value), styles.top)
        ws.set_row(r, row_points([(str(v), widths[c]) for c, v in enumerate(row)
                                  if c in text_columns and v not in ("", None)] or [("", 9)]))
    ws.freeze_panes(1, 2)
    ws.autofilter(0, 0, len(table) - 1, len(header) - 1)
    wide_table_page(ws, widths, who_columns=2)
    book.close()



def _item_summary(g, assignment, lang, mode):
    """Item lines a student reads: every item's points, and for the wrong cells what is
    wrong (``hints``) or the expected value too (``full``)."""
    w = words(lang)
    lines = []
    for item in assignment.items:
        if item.key not in g.items:
            continue
        points, cells = g.items[item.key]
        head = say(w, "item_heading", label=item.label(lang), unit=unit_text(item.unit),
                   points=_points(points), max_points=_points(item.points))
        wrong = [c for c in cells if c.fraction < 1]
        if mode == "score-only" or not wrong:
            lines.append((head, []))
            continue
        details = []
        for cell in wrong:
            label = cell.label or w["scalar_row"]
            reason = say(w, cell.reason, **cell.detail)
            if mode == "full":
                details.append(say(w, "cell_full", label=label,
                                   value=shown(cell.value, item, typed=True),
                                   expected=shown(cell.expected, item), reason=reason))
            else:
                details.append(say(w, "cell_hint", label=label,
                                   value=shown(cell.value, item, typed=True), reason=reason))
        lines.append((head, details))
    return lines


def lms_text(g, assignment, lang, mode, limit=4000):
    """The LMS's feedback field: self-contained text in the class's language (an LMS
    has no feedback files), nothing about other students; at most ``limit``
    characters, cut between sentences (never inside a number) and marked as cut."""
    w = words(lang)
    if g.status == "missing":
        return say(w, "lms_missing")
    if g.status != "graded":
        return say(w, "lms_unreadable", reason=reason_text(g.problem, lang))
    parts = [say(w, "lms_graded", score=_points(g.score), max_score=_points(assignment.max_score))]
    parts += [say(w, word, **fields) + w["stop"] for word, fields in student_notes(g)]
    for head, details in _item_summary(g, assignment, lang, mode):
        if details or mode == "score-only":
            parts.append(head + (w["colon"] + w["separator"].join(details[:6]) +
                                 (w["more"] if len(details) > 6 else "") if details else ""))
    return _clipped(parts, limit, w["lms_cut"])


def _clipped(parts, limit, more):
    """``parts`` joined by spaces, as many whole parts as fit with ``more`` after them."""
    text = " ".join(parts)
    if len(text) <= limit:
        return text
    kept = parts[0][:limit - len(more)]
    for part in parts[1:]:
        if len(kept) + 1 + len(part) + len(more) > limit:
            break
        kept += " " + part
    return kept + more


MARKDOWN_SIGNS = "\\`*_[]!#|~"       # a link, image, emphasis, code, cell or heading


def inert(text):
    """Text a student (or a roster) typed, made inert in Markdown: HTML escaped and
    every sign that could start a link, an image, emphasis, a table cell or a heading
    backslashed — it shows as typed and does nothing (the .html feedback escapes it
    too)."""
    import html
    text = html.escape(str(text), quote=False)
    return "".join("\\" + c if c in MARKDOWN_SIGNS else c for c in text)


def _inert_fields(fields):
    return {k: inert(v) if isinstance(v, str) else v for k, v in fields.items()}


def feedback_text(g, assignment, lang, mode):
    w = words(lang)
    lines = [f"# {say(w, 'title_feedback', assignment=assignment.name(lang), student_id=inert(g.student_id), name=inert(g.name))}",
             ""]
    if g.status != "graded":
        status = say(w, "status_missing") if g.status == "missing" else \
            say(w, "status_unreadable", reason=reason_text(g.problem, lang))
        return "\n".join(lines + [f"**{status}**", ""]) + "\n"
    lines += [say(w, "score", score=_points(g.score), max_score=_points(assignment.max_score)), ""]
    notes = student_notes(g)
    if notes:
        lines += [w["notes_heading"], ""] + [f"- {say(w, word, **_inert_fields(fields))}"
                                             for word, fields in notes]
        lines.append("")
    for item in assignment.items:
        if item.key not in g.items:
            continue
        points, cells = g.items[item.key]
        lines += [f"## {say(w, 'item_heading', label=item.label(lang), unit=unit_text(item.unit), points=_points(points), max_points=_points(item.points))}",
                  ""]
        if mode == "score-only":
            continue
        listed = cells if mode == "full" else [c for c in cells if c.fraction < 1]
        if not listed:
            lines += [w["all_right"], ""]
            continue
        if mode == "full":
            lines += [w["table_full"], "|---|---|---|---|---|"]
        else:
            lines += [w["table_hints"], "|---|---|---|---|"]
        for cell in listed:
            label = cell.label or w["scalar_row"]
            reason = say(w, cell.reason, **_inert_fields(cell.detail))
            typed = inert(shown(cell.value, item, typed=True))
            if mode == "full":
                lines.append(f"| {label} | {typed} | "
                             f"{shown(cell.expected, item)} | {cell.fraction:.0%} | {reason} |")
            else:
                lines.append(f"| {label} | {typed} | {cell.fraction:.0%} | {reason} |")
        lines.append("")
    return "\n".join(lines) + "\n"


def _width(texts, least=10, most=60):
    from crankbook.assignment.student_book import display_width
    return max(least, min(most, max((display_width(str(t)) for t in texts), default=0) + 2))


def write_integrity_report(path, lang, grades, suspicions, sections=None):
    """The teacher's integrity report: one row per suspected pair, then the flags that
    concern one student only."""
    w = words(lang)
    book = xlsxwriter.Workbook(str(path), WORKBOOK_OPTIONS)
    book.set_properties({"title": w["integrity_title"], "author": "crankbook",
                         "created": FIXED_TIME})
    styles = Styles(book)
    ws = book.add_worksheet(w["integrity_sheet"])
    ws.write(0, 0, w["integrity_title"], styles.title)
    ws.write(1, 0, w["integrity_note"], styles.subtitle)
    header = ["col_who", "col_whom", "col_what", "col_evidence", "col_action"]
    for col, word in enumerate(header):
        ws.write(3, col, w[word], styles.header)
    names = {g.student_id: g.name for g in grades}
    row = 4
    rows = []
    for s in suspicions:
        rows.append([f"{s.who} {names.get(s.who, '')}".strip(),
                     f"{s.whom} {names.get(s.whom, '')}".strip() if s.whom else "",
                     w["separator"].join(w.get(f"suspect_kind_{k}", k) for k in s.kinds),
                     _evidence(w, s, sections),
                     w["action_copier"] if s.source_known else w["action_unclear"]])
    for g in grades:
        for flag in g.flags:
            if flag in ("copy-suspect", "wrong-student"):
                continue
            notes = [say(w, word, **fields) for word, fields, _ in g.notes]
            rows.append([f"{g.student_id} {g.name}", "", w.get(f"flag_{flag}", flag),
                         w["separator"].join(notes), w.get(f"action_{flag}", "")])
    widths = [18, 18, 22, 70, 40]
    for values in rows:
        for col, value in enumerate(values):
            ws.write_string(row, col, value, styles.text)
        ws.set_row(row, row_points(zip(values, widths)))
        row += 1
    if not rows:
        ws.write(row, 0, w["integrity_none"], styles.text)
    for col, width in enumerate(widths):
        ws.set_column(col, col, width)
    ws.set_row(3, row_points(zip([w[word] for word in header], widths), bold=True))
    ws.freeze_panes(4, 1)
    landscape_page(ws)
    ws.repeat_rows(3)
    book.close()


def _evidence(w, s, sections=None):
    parts = []
    e = s.evidence
    if e.get("from_round"):
        parts.append(say(w, "evidence_from_round", round=e["from_round"]))
    if e.get("shared_by"):
        parts.append(say(w, "evidence_shared_by", count=e["shared_by"]))
    if e.get("section"):
        parts.append(say(w, "evidence_section", section=(sections or {}).get(e["section"],
                                                                            e["section"])))
    if e.get("fit_other") is not None:
        parts.append(say(w, "evidence_fit_other", share=f"{e['fit_other']:.0%}", whom=s.whom))
    if e.get("fit_own") is not None:
        parts.append(say(w, "evidence_fit_own", share=f"{e['fit_own']:.0%}"))
    if e.get("fit_of_other") is not None:
        parts.append(say(w, "evidence_fit_of_other", whom=s.whom,
                         share=f"{e['fit_of_other']:.0%}"))
    if e.get("earlier"):
        parts.append(say(w, "evidence_earlier", who=e["earlier"]))
    for sid, facts in e.get("files", {}).items():
        parts.append(f"{sid}: " + ", ".join(f"{w.get('fact_' + k, k)} {v}"
                                            for k, v in facts.items()))
    return w["separator"].join(parts)


def write_class_report(path, assignment, lang, grades):
    w = words(lang)
    graded = [g for g in grades if g.status == "graded"]
    book = xlsxwriter.Workbook(str(path), WORKBOOK_OPTIONS)
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
        ws.write_string(row, 0, item.label(lang), styles.top)
        ws.write_number(row, 1, item.points, styles.number("-", "General"))
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
    chart.set_y_axis({"reverse": True, "crossing": "max"})   # values stay at the bottom
    chart.set_legend({"position": "bottom"})
    chart.set_size({"width": 720, "height": max(420, 28 * len(assignment.items) + 120)})
    ws.insert_chart(2, 6, chart)

    dist = book.add_worksheet(w["report_totals"])
    dist.write(0, 0, w["chart_totals"], styles.title)
    # the band's words first: a count right-aligned against them read "10–10 %"
    for col, word in enumerate(["col_band", "col_from", "col_to", "col_students"]):
        dist.write(2, col, w[word], styles.header)
    dist.set_column(0, 3, 10)
    bins = [0] * 10
    for g in graded:
        share = g.score / assignment.max_score if assignment.max_score else 0
        bins[min(int(share * 10), 9)] += 1
    whole = styles.number("-", "0")
    for i, count in enumerate(bins):
        dist.write_string(3 + i, 0, f"{i * 10}–{(i + 1) * 10}", styles.top)   # % in the axis
        dist.write_number(3 + i, 1, i * 10, whole)
        dist.write_number(3 + i, 2, (i + 1) * 10, whole)
        dist.write_number(3 + i, 3, count, whole)
    hist = book.add_chart({"type": "column"})
    hist.add_series({"name": w["col_students"], "categories": [w["report_totals"], 3, 0, 12, 0],
                     "values": [w["report_totals"], 3, 3, 12, 3], "gap": 20,
                     "data_labels": {"value": True}})
    hist.set_title({"name": w["chart_totals"]})
    hist.set_x_axis({"name": w["axis_score"]})
    step = next(s for s in (1, 2, 5, 10, 20, 50, 100, 200, 500, 1000) if max(bins) < 10 * s)
    hist.set_y_axis({"name": w["axis_students"], "min": 0, "major_unit": step,
                     "max": step * (max(bins) // step + 1), "num_format": "0"})
    hist.set_legend({"none": True})
    dist.insert_chart(2, 5, hist)

    _class_statistics(book, w, assignment, grades, styles)
    _item_analysis(book, w, assignment, lang, graded, styles)

    students = book.add_worksheet(w["report_students"])
    # the sheet a teacher shows the class: what each student is told, never a
    # suspicion (those stay in integrity.xlsx and the gradebook)
    notes = {g.student_id: w["separator"].join(say(w, word, **fields)
                                               for word, fields in student_notes(g))
             + ((w["separator"] if student_notes(g) else "") + reason_text(g.problem, lang)
                if g.problem else "")
             + "".join(w["separator"] + w["override_note"].format(what=o) for o in g.overrides)
             for g in grades}
    for col, word in enumerate(["col_student_id", "col_name", "col_status", "col_score",
                                "col_flags", "col_notes"]):
        students.write(0, col, w[word], styles.header)
    students.set_column(0, 0, _width([g.student_id for g in grades], 12))
    students.set_column(1, 1, _width([g.name for g in grades], 12))
    students.set_column(2, 4, 14)
    notes_width = _width(notes.values(), 20, 90)
    students.set_column(5, 5, notes_width, styles.text)
    for row, g in enumerate(grades, start=1):
        students.write_string(row, 0, g.student_id, styles.top)
        students.write_string(row, 1, g.name, styles.top)
        students.write_string(row, 2, w.get(f"state_{g.status}", g.status), styles.top)
        if g.status == "graded":
            students.write_number(row, 3, round(g.score, 2), styles.top)
        flags = w["separator"].join(w.get(f"flag_{f}", f) for f in g.flags
                                    if f not in TEACHER_ONLY_FLAGS)
        students.write_string(row, 4, flags, styles.text)
        students.write_string(row, 5, notes[g.student_id], styles.text)
        students.set_row(row, row_points([(flags, 14), (notes[g.student_id], notes_width)]))
    students.freeze_panes(1, 2)
    for sheet in book.worksheets():
        landscape_page(sheet)
    book.close()


def _class_statistics(book, w, assignment, grades, styles):
    """Per class of the roster's 班级/class column (the whole class when there is
    none): students, graded, mean, median, lowest and highest total."""
    column = next((c for c in (grades[0].extra if grades else {})
                   if c.strip().lower() in ("班级", "class", "section", "group", "组号", "班")),
                  None)
    classes = {}
    for g in grades:
        classes.setdefault(g.extra.get(column, "") if column else "", []).append(g)
    ws = book.add_worksheet(w["report_classes"])
    ws.write(0, 0, w["report_classes_title"], styles.title)
    for col, word in enumerate(["col_class", "col_students", "col_graded", "col_mean",
                                "col_median", "col_lowest", "col_highest"]):
        ws.write(2, col, w[word], styles.header)
    ws.set_column(0, 0, _width(classes, 14))
    ws.set_column(1, 6, 12)
    for row, (name, members) in enumerate(sorted(classes.items()), start=3):
        totals = sorted(g.score for g in members if g.status == "graded")
        ws.write_string(row, 0, name or w["all_students"], styles.top)
        ws.write_number(row, 1, len(members), styles.number("-", "0"))
        ws.write_number(row, 2, len(totals), styles.number("-", "0"))
        if totals:
            middle = len(totals) // 2
            median = totals[middle] if len(totals) % 2 else (totals[middle - 1] + totals[middle]) / 2
            for col, value in enumerate((sum(totals) / len(totals), median, totals[0],
                                         totals[-1]), start=3):
                ws.write_number(row, col, round(value, 2), styles.number("-", "0.00"))


def _slips_chart(book, ws, w, last, col):
    """Beside the table, a stacked bar per item of its slips by kind (the items sheet
    already charts the share right): where the class lost points, not only how many."""
    chart = book.add_chart({"type": "bar", "subtype": "stacked"})
    colours = ("#F4B183", "#FFD966", "#A9D18E", "#B4A7D6", "#BFBFBF")
    for offset, (kind, colour) in enumerate(zip(SLIP_KINDS, colours)):
        chart.add_series({"name": w[f"col_{kind}"],
                          "categories": [ws.get_name(), 3, 0, last, 0],
                          "values": [ws.get_name(), 3, 3 + offset, last, 3 + offset],
                          "fill": {"color": colour}, "gap": 60})
    chart.set_title({"name": w["analysis_chart_title"], "name_font": {"size": 12}})
    chart.set_x_axis({"name": w["analysis_chart_axis"], "min": 0,
                      "major_gridlines": {"visible": True}})
    chart.set_y_axis({"reverse": True, "crossing": "max"})   # the table's order, top down
    chart.set_legend({"position": "bottom"})
    height = max(340, 22 * (last - 2) + 160)
    chart.set_size({"width": 620, "height": height})
    ws.insert_chart(2, col, chart)
    # the row below the chart: its header row (HEADER_POINTS) and then default rows
    return 3 + math.ceil((height - HEADER_POINTS * 4 / 3) / DEFAULT_ROW_PX)


HEADER_POINTS = 32           # the analysis table's header row: its words wrap
DEFAULT_ROW_PX = 20          # a default row (15 pt)


SLIP_KINDS = ("unit_slip", "sign_slip", "consequential", "not_a_number", "no_answer")


def item_statistics(assignment, graded):
    """Per item: difficulty (share of cells right), slips by kind, and discrimination
    (mean fraction of the top third by total minus that of the bottom third)."""
    ranked = sorted(graded, key=lambda g: g.score)
    third = max(1, len(ranked) // 3)
    low, high = ranked[:third], ranked[-third:]

    def share(group, item):
        """Mean fraction of the item's points in ``group``."""
        values = [g.items[item.key][0] / item.points for g in group if item.key in g.items]
        return sum(values) / len(values) if values and item.points else 0.0
    out = []
    for item in assignment.items:
        cells = [c for g in graded if item.key in g.items for c in g.items[item.key][1]]
        right = sum(c.fraction >= 1.0 for c in cells)
        slips = {kind: sum(c.reason == kind for c in cells) for kind in SLIP_KINDS}
        out.append({"item": item, "cells": len(cells),
                    "difficulty": right / len(cells) if cells else 0.0, "slips": slips,
                    "discrimination": share(high, item) - share(low, item)
                    if len(ranked) >= 3 else 0.0})
    return out


def _item_analysis(book, w, assignment, lang, graded, styles):
    """What the class did not understand: each item's difficulty, slips and
    discrimination, then a heat map of positions × quantities (share right)."""
    ws = book.add_worksheet(w["report_analysis"])
    ws.write(0, 0, w["report_analysis_title"], styles.title)
    header = ["col_item", "col_difficulty", "col_discrimination",
              *[f"col_{k}" for k in SLIP_KINDS]]
    wrapped = book.add_format({"bold": True, "text_wrap": True, "valign": "top",
                               "border": 1, "bg_color": "#DDEBF7"})
    for col, word in enumerate(header):
        ws.write(2, col, w[word], wrapped)
    ws.set_row(2, HEADER_POINTS)       # headers wrap in their column, never cut
    stats = item_statistics(assignment, graded)
    percent = styles.number("-", "0%")
    for row, entry in enumerate(stats, start=3):
        ws.write(row, 0, entry["item"].label(lang))
        ws.write_number(row, 1, entry["difficulty"], percent)
        ws.write_number(row, 2, entry["discrimination"], styles.number("-", "0.00"))
        for col, kind in enumerate(SLIP_KINDS, start=3):
            ws.write_number(row, col, entry["slips"][kind])
    last = 3 + len(stats) - 1
    ws.conditional_format(3, 1, last, 1, {"type": "3_color_scale", "min_color": "#F8696B",
                                          "mid_color": "#FFEB84", "max_color": "#63BE7B"})
    ws.set_column(0, 0, _width([e["item"].label(lang) for e in stats], 20))
    ws.set_column(1, len(header) - 1, 12)
    ws.write(last + 2, 0, w["analysis_note"], styles.text)
    below_chart = _slips_chart(book, ws, w, last, len(header) + 1) if stats else 0
    # positions × quantities: the share of students right at each position
    position_items = [s for s in assignment.sheets if s.rows == "positions"]
    if assignment.positions is None or not position_items or not graded:
        return
    keys = [k for s in position_items for k in s.items]
    labels = assignment.positions.labels(lang)
    top = max(last + 4, below_chart + 1)     # below the chart: the heat map is wider than the table
    ws.write(top, 0, w["heat_title"], styles.group)
    ws.write(top + 1, 0, w["col_position"], wrapped)
    for col, key in enumerate(keys, start=1):
        ws.write(top + 1, col, assignment.item[key].label(lang), wrapped)
    ws.set_row(top + 1, 46)
    ws.repeat_rows(top + 1)                  # a second page of positions keeps its quantities
    for row, label in enumerate(labels):
        ws.write(top + 2 + row, 0, label)
        for col, key in enumerate(keys, start=1):
            cells = [g.items[key][1][row] for g in graded
                     if key in g.items and row < len(g.items[key][1])]
            if cells:
                ws.write_number(top + 2 + row, col,
                                sum(c.fraction >= 1.0 for c in cells) / len(cells), percent)
    ws.conditional_format(top + 2, 1, top + 1 + len(labels), len(keys),
                          {"type": "3_color_scale", "min_color": "#F8696B",
                           "mid_color": "#FFEB84", "max_color": "#63BE7B",
                           "min_type": "num", "min_value": 0, "max_type": "num",
                           "max_value": 1, "mid_type": "num", "mid_value": 0.5})
