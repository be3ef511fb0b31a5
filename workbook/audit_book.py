"""The audit outputs: a workbook with one live sheet per document, JSON, Markdown."""
import json
from pathlib import Path

import xlsxwriter
from xlsxwriter.utility import xl_col_to_name

from crankbook.atomic import atomic_path
from crankbook.claims import INPUT
from crankbook.writer.build import FIXED_TIME
from crankbook.writer.styles import Styles

COLUMNS = [("key", 16), ("section", 10), ("claim", 60), ("reported", 13), ("unit", 8),
           ("recomputed", 13), ("status", 13), ("tolerance", 10), ("kind", 12),
           ("note", 70)]
INPUTS_AT = len(COLUMNS)            # input name/value pairs start in this column
STATUSES = ["ok", "mismatch", "inconsistent", "unverifiable"]
COLOURS = {"ok": "#C6EFCE", "mismatch": "#FFC7CE", "inconsistent": "#FFEB9C",
           "unverifiable": "#D9D9D9"}
FINDING_FIELDS = ["document", "section", "claim", "reported", "unit", "recomputed", "status",
                  "note"]


def _atomic(path, write):
    with atomic_path(path) as temporary:
        write(temporary)


def write_json(documents, path):
    findings = [{k: f[k] for k in FINDING_FIELDS} for d in documents for f in d.findings()]

    def write(temporary):
        with open(temporary, "w", encoding="utf-8") as handle:
            json.dump({"findings": findings}, handle, ensure_ascii=False, indent=1)
    _atomic(path, write)


def write_markdown(documents, path):
    lines = ["# Audit of the source documents", "",
             "Every number the documents state, beside an independent recomputation "
             "(`crankbook audit`). Status: ok, mismatch (differs beyond the tolerance), "
             "inconsistent (contradicts another statement of the same document), "
             "unverifiable (too little stated to recompute).", ""]
    lines += ["| document | ok | mismatch | inconsistent | unverifiable |", "|---|---|---|---|---|"]
    for d in documents:
        counts = [sum(f["status"] == s for f in d.findings()) for s in STATUSES]
        lines.append(f"| {d.key} | " + " | ".join(map(str, counts)) + " |")
    for d in documents:
        lines += ["", f"## {d.key}: {d.title}", "", f"Source: `{d.file}`", "",
                  "| § | claim | reported | recomputed | unit | status | note |",
                  "|---|---|---|---|---|---|---|"]
        for f in d.findings():
            def num(x):
                return "—" if x is None else f"{x:.6g}"
            cells = [f["section"], f["claim"], num(f["reported"]), num(f["recomputed"]),
                     f["unit"], f"**{f['status']}**" if f["status"] != "ok" else "ok", f["note"]]
            lines.append("| " + " | ".join(str(c).replace("|", "\\|").replace("\n", " ")
                                           for c in cells) + " |")

    def write(temporary):
        Path(temporary).write_text("\n".join(lines) + "\n", encoding="utf-8")
    _atomic(path, write)


def write_audit_workbook(documents, path):
    _atomic(path, lambda temporary: _write_book(documents, temporary))


def _write_book(documents, filename):
    book = xlsxwriter.Workbook(filename)
    book.set_properties({"title": "crankbook audit", "author": "crankbook",
                         "created": FIXED_TIME})
    styles = Styles(book)
    summary = book.add_worksheet("Summary")
    status_formats = {s: book.add_format({"bg_color": c}) for s, c in COLOURS.items()}
    sheet_names = {}
    for document in documents:
        name = document.key[:31]
        sheet_names[document.key] = name
        _write_document_sheet(book, document, name, styles, status_formats)
    summary.write(0, 0, "Audit summary: verdicts per document (formulas over the sheets)",
                  styles.title)
    summary.write(2, 0, "document", styles.header)
    for col, status in enumerate(STATUSES, start=1):
        summary.write(2, col, status, styles.header)
    summary.write(2, len(STATUSES) + 1, "total", styles.header)
    summary.set_column(0, 0, 18)
    summary.set_column(1, len(STATUSES) + 1, 13)
    status_col = xl_col_to_name([c for c, _ in COLUMNS].index("status"))
    for row, document in enumerate(documents, start=3):
        summary.write(row, 0, document.key)
        findings = document.findings()
        ref = f"'{sheet_names[document.key]}'!${status_col}:${status_col}"
        for col, status in enumerate(STATUSES, start=1):
            summary.write_formula(row, col, f'=COUNTIF({ref},"{status}")', None,
                                  sum(f["status"] == status for f in findings))
        summary.write_formula(row, len(STATUSES) + 1,
                              f"=SUM(B{row + 1}:{xl_col_to_name(len(STATUSES))}{row + 1})",
                              None, len(findings))
    chart = book.add_chart({"type": "bar", "subtype": "stacked"})
    last = 3 + len(documents) - 1
    for col, status in enumerate(STATUSES, start=1):
        chart.add_series({"name": ["Summary", 2, col], "categories": ["Summary", 3, 0, last, 0],
                          "values": ["Summary", 3, col, last, col],
                          "fill": {"color": COLOURS[status]}, "border": {"color": "#808080"}})
    chart.set_title({"name": "Verdicts per document"})
    chart.set_x_axis({"name": "claims"})
    chart.set_size({"width": 640, "height": 300})
    summary.insert_chart(last + 3, 0, chart)
    for ws in book.worksheets():
        ws.set_paper(9)
        ws.set_landscape()
        ws.fit_to_pages(1, 0)
    summary.activate()
    book.close()


def _write_document_sheet(book, document, name, styles, status_formats):
    ws = book.add_worksheet(name)
    ws.write(0, 0, f"{document.key}: {document.title}", styles.title)
    ws.write(1, 0, f"Source: {document.file}. Recomputations are live formulas on the input "
                   f"cells to the right: change an input and the verdict follows.",
             styles.subtitle)
    for col, (label, width) in enumerate(COLUMNS):
        ws.write(3, col, label, styles.header)
        ws.set_column(col, col, width)
    ws.write(3, INPUTS_AT, "inputs (name, value, …)", styles.header)
    ws.set_column(INPUTS_AT, INPUTS_AT + 16, 12)
    col_of = {label: i for i, (label, _) in enumerate(COLUMNS)}
    for row, (claim, finding) in enumerate(zip(document.claims, document.findings()), start=4):
        excel_row = row + 1
        cells = {}
        for i, (input_name, value) in enumerate(claim.inputs.items()):
            ws.write(row, INPUTS_AT + 2 * i, input_name, styles.key)
            ws.write_number(row, INPUTS_AT + 2 * i + 1, float(value),
                            styles.number("-", "General", role="input"))
            cells[input_name] = f"${xl_col_to_name(INPUTS_AT + 2 * i + 1)}${excel_row}"
        ws.write(row, col_of["key"], claim.key, styles.key)
        ws.write(row, col_of["section"], claim.section)
        ws.write(row, col_of["claim"], claim.claim, styles.text)
        if claim.reported is not None:
            ws.write_number(row, col_of["reported"], claim.reported)
        ws.write(row, col_of["unit"], claim.unit)
        recomputed = finding["recomputed"]
        if claim.formula and recomputed is not None:
            formula = "=" + INPUT.sub(lambda m: cells[m.group(1)], claim.formula)
            ws.write_formula(row, col_of["recomputed"], formula, None, recomputed)
        elif recomputed is not None:
            ws.write_number(row, col_of["recomputed"], recomputed)
        rep = f"{xl_col_to_name(col_of['reported'])}{excel_row}"
        rec = f"{xl_col_to_name(col_of['recomputed'])}{excel_row}"
        tol = f"{xl_col_to_name(col_of['tolerance'])}{excel_row}"
        differs = {"consistency": "inconsistent"}.get(claim.kind, "mismatch")
        ws.write_number(row, col_of["tolerance"], claim.tolerance)
        ws.write(row, col_of["kind"], claim.kind)
        ws.write_formula(
            row, col_of["status"],
            f'=IF(OR({rep}="",{rec}=""),"unverifiable",IF(ABS({rep}-{rec})<=MAX({tol}*ABS({rec}),'
            f'{claim.abs_tolerance!r}),"ok","{differs}"))', None, finding["status"])
        ws.write(row, col_of["note"], claim.note, styles.text)
    last = 4 + len(document.claims)
    for status, fmt in status_formats.items():
        ws.conditional_format(4, col_of["status"], last, col_of["status"],
                              {"type": "cell", "criteria": "==", "value": f'"{status}"',
                               "format": fmt})
    ws.freeze_panes(4, 3)
    ws.autofilter(3, 0, last, len(COLUMNS) - 1)
