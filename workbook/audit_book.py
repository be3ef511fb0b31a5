"""The audit outputs: a workbook with one live sheet per document, JSON, Markdown.

Every row is one claim: the number the document prints (with its line in the seed
file), a derived value where the audit needs one on the way, the recomputation (a
live formula on the input cells where the claim has one) and the verdict, whose
meaning is the same in every row (claims.VERDICTS, repeated on the Summary sheet).
"""
import json
import math
from collections import Counter
from pathlib import Path

import xlsxwriter
from xlsxwriter.utility import xl_col_to_name

from crankbook.atomic import atomic_path
from crankbook.claims import INPUT, STATUS_OF_KIND, VERDICTS
from crankbook.writer.build import FIXED_TIME
from crankbook.writer.styles import Styles

# (label, width in characters, wrapped)
COLUMNS = [("key", 14, False), ("section", 9, True), ("line", 5, False),
           ("claim", 40, True), ("reported", 10, False), ("unit", 6, False),
           ("derived", 10, False), ("derived: what", 18, True), ("recomputed", 11, False),
           ("verdict", 12, True), ("tolerance", 7, False), ("margin %", 7, False),
           ("kind", 9, False), ("basis", 30, True), ("note", 40, True)]
COL = {label: i for i, (label, _, _) in enumerate(COLUMNS)}
INPUTS_AT = len(COLUMNS)            # input name/value pairs start in this column
STATUSES = list(VERDICTS)
COLOURS = {"ok": "#C6EFCE", "mismatch": "#FFC7CE", "inconsistent": "#FFEB9C",
           "model-disagrees": "#F8CBAD", "outside-rule": "#DDEBF7", "unverifiable": "#D9D9D9"}
FINDING_FIELDS = ["document", "key", "section", "line", "claim", "reported", "printed", "unit",
                  "derived", "derived_what", "recomputed", "status", "kind", "tolerance_percent",
                  "margin_percent", "other", "other_line", "model", "missing", "note"]
HEADER_ROW = 3
LINE_HEIGHT = 12.75                  # points per wrapped line (10-point Arial)


def _atomic(path, write):
    with atomic_path(path) as temporary:
        write(temporary)


def _clean(value):
    return None if isinstance(value, float) and not math.isfinite(value) else value


def write_json(documents, path):
    findings = [{k: _clean(f[k]) for k in FINDING_FIELDS}
                for d in documents for f in d.findings()]
    coverage = {d.key: coverage_of(d) for d in documents}

    def write(temporary):
        with open(temporary, "w", encoding="utf-8") as handle:
            json.dump({"verdicts": VERDICTS, "findings": findings, "coverage": coverage},
                      handle, ensure_ascii=False, indent=1)
    _atomic(path, write)


def coverage_of(document):
    """Claims per section and the numbers left out, with why."""
    sections = Counter(c.section for c in document.claims)
    return {"claims": len(document.claims), "sections": dict(sections),
            "omitted": [dict(o) for o in document.omitted]}


def decimals_of(claim):
    """Decimal places the document prints the number with (for the recomputation's
    display): from ``printed`` or the reported value; five significant digits where
    it prints a fraction or no number."""
    if claim.printed and "/" not in claim.printed:
        return min(len(claim.printed.partition(".")[2]), 6)
    if claim.reported is not None and not claim.printed:
        return decimals_of_value(claim.reported)
    value = claim.reported if claim.reported is not None else claim.derived_value()
    if not value:
        return 4
    return int(min(max(4 - math.floor(math.log10(abs(value))), 0), 8))


def _basis(claim):
    """What a verdict rests on besides the recomputation, in words."""
    if claim.kind == "consistency":
        return f"other statement (line {claim.other_line}): {claim.other}"
    if claim.kind == "model":
        return f"model: {claim.model}"
    if claim.kind == "unverifiable":
        return f"missing: {claim.missing}"
    if claim.kind == "rule":
        return "rule quoted by the document; recomputed = the nearest value inside it"
    return "the document's own inputs and formula"


def _number(x, digits):
    if x is None:
        return "—"
    return f"{x:.{digits}f}" if abs(x) < 1e15 else f"{x:.6g}"


def write_markdown(documents, path):
    lines = ["# Audit of the source documents", "",
             "Every number the documents print, beside an independent recomputation "
             "(`crankbook audit`). `line` is the line of the seed file where the number "
             "is printed. Verdicts — one meaning each:", ""]
    lines += [f"- **{status}**: {meaning}" for status, meaning in VERDICTS.items()]
    lines += ["", "| document | claims | " + " | ".join(STATUSES) + " |",
              "|---|---|" + "---|" * len(STATUSES)]
    for d in documents:
        counts = Counter(f["status"] for f in d.findings())
        lines.append(f"| {d.key} | {len(d.claims)} | "
                     + " | ".join(str(counts.get(s, 0)) for s in STATUSES) + " |")
    for d in documents:
        lines += ["", f"## {d.key}: {d.title}", "", f"Source: `{d.file}`", "",
                  "| § | line | claim | reported | derived | recomputed | unit | verdict | basis | note |",
                  "|---|---|---|---|---|---|---|---|---|---|"]
        for claim, f in zip(d.claims, d.findings()):
            digits = decimals_of(claim)
            reported = claim.printed or _number(f["reported"], digits)
            derived = "—" if f["derived"] is None else \
                f"{_number(f['derived'], digits)} ({f['derived_what']})"
            verdict = f["status"] if f["status"] == "ok" else f"**{f['status']}**"
            if f["margin_percent"] is not None:
                verdict += f" ({f['margin_percent']:+.1f} %)"
            cells = [f["section"], f["line"], f["claim"], reported, derived,
                     _number(f["recomputed"], digits), f["unit"], verdict, _basis(claim),
                     f["note"]]
            lines.append("| " + " | ".join(str(c).replace("|", "\\|").replace("\n", " ")
                                           for c in cells) + " |")
        coverage = coverage_of(d)
        lines += ["", f"### Coverage of {d.key}", "",
                  "Claims per section: " + ", ".join(f"{s} ({n})"
                                                     for s, n in coverage["sections"].items())
                  + "."]
        if d.omitted:
            lines += ["", "Left out:", ""]
            lines += [f"- {o['section']}: {o['what']} — {o['why']}" for o in d.omitted]

    def write(temporary):
        Path(temporary).write_text("\n".join(lines) + "\n", encoding="utf-8")
    _atomic(path, write)


def write_audit_workbook(documents, path):
    _atomic(path, lambda temporary: _write_book(documents, temporary))


class _Formats:
    """The audit workbook's formats: Styles plus wrapped, percent and precision."""

    def __init__(self, book):
        self.styles = Styles(book)
        self.book = book
        self.wrap = book.add_format({"font_name": "Arial", "font_size": 10, "text_wrap": True,
                                     "valign": "top"})
        self.plain = book.add_format({"font_name": "Arial", "font_size": 10, "valign": "top"})
        self.centred = book.add_format({"font_name": "Arial", "font_size": 10, "valign": "top",
                                        "align": "center"})
        self.key = book.add_format({"font_name": "Consolas", "font_size": 10,
                                    "font_color": "#1F3864", "valign": "top"})
        self.percent = book.add_format({"font_name": "Arial", "font_size": 10,
                                        "num_format": "0.###%", "valign": "top"})
        self.margin = book.add_format({"font_name": "Arial", "font_size": 10,
                                       "num_format": "+0.0;-0.0;0", "valign": "top"})
        self.verdict = book.add_format({"font_name": "Arial", "font_size": 10, "bold": True,
                                        "valign": "top", "text_wrap": True})
        self.link = book.add_format({"font_name": "Arial", "font_size": 10,
                                     "font_color": "#0563C1", "underline": 1})
        self._numbers = {}

    def number(self, digits, role="output"):
        key = (digits, role)
        if key not in self._numbers:
            fmt = "0" if digits == 0 else "0." + "0" * digits
            props = {"font_name": "Arial", "font_size": 10, "num_format": fmt, "valign": "top"}
            if role == "input":
                props.update(bg_color="#FFF2CC", font_color="#0000CC", border=1,
                             border_color="#BF9000")
            self._numbers[key] = self.book.add_format(props)
        return self._numbers[key]


def _write_book(documents, filename):
    book = xlsxwriter.Workbook(filename)
    book.set_properties({"title": "crankbook audit", "author": "crankbook",
                         "created": FIXED_TIME})
    formats = _Formats(book)
    summary = book.add_worksheet("Summary")
    status_formats = {s: book.add_format({"bg_color": c}) for s, c in COLOURS.items()}
    names = {d.key: d.key[:31] for d in documents}
    for document in documents:
        _write_document_sheet(book, document, names[document.key], formats, status_formats)
    _write_summary(book, summary, documents, names, formats, status_formats)
    summary.activate()
    book.close()


def _write_summary(book, ws, documents, names, formats, status_formats):
    styles = formats.styles
    ws.write(0, 0, "Audit summary: verdicts per document (formulas over the sheets)", styles.title)
    ws.write(1, 0, "Each document's sheet lists every number it prints with its line in the "
                   "seed file; click a name to open the sheet.", styles.subtitle)
    ws.write(HEADER_ROW, 0, "document", styles.header)
    for col, status in enumerate(STATUSES, start=1):
        ws.write(HEADER_ROW, col, status, styles.header)
    total_col = len(STATUSES) + 1
    ws.write(HEADER_ROW, total_col, "total", styles.header)
    ws.set_column(0, 0, 18)
    ws.set_column(1, total_col, 13)
    verdict_col = xl_col_to_name(COL["verdict"])
    for row, document in enumerate(documents, start=HEADER_ROW + 1):
        name = names[document.key]
        ws.write_url(row, 0, f"internal:'{name}'!A1", formats.link, document.key)
        counts = Counter(f["status"] for f in document.findings())
        ref = f"'{name}'!${verdict_col}:${verdict_col}"
        for col, status in enumerate(STATUSES, start=1):
            ws.write_formula(row, col, f'=COUNTIF({ref},"{status}")', None, counts.get(status, 0))
        ws.write_formula(row, total_col,
                         f"=SUM(B{row + 1}:{xl_col_to_name(len(STATUSES))}{row + 1})",
                         None, len(document.claims))
    last = HEADER_ROW + len(documents)
    for col, status in enumerate(STATUSES, start=1):
        ws.conditional_format(HEADER_ROW, col, HEADER_ROW, col,
                              {"type": "no_errors", "format": status_formats[status]})
    chart = book.add_chart({"type": "bar", "subtype": "stacked"})
    for col, status in enumerate(STATUSES, start=1):
        chart.add_series({"name": ["Summary", HEADER_ROW, col],
                          "categories": ["Summary", HEADER_ROW + 1, 0, last, 0],
                          "values": ["Summary", HEADER_ROW + 1, col, last, col],
                          "fill": {"color": COLOURS[status]}, "border": {"color": "#808080"}})
    chart.set_title({"name": "Verdicts per document"})
    chart.set_x_axis({"name": "claims"})
    chart.set_legend({"position": "bottom"})
    chart.set_size({"width": 720, "height": 300})
    ws.insert_chart(last + 2, 0, chart)
    row = last + 19
    ws.write(row, 0, "Verdicts", styles.group)
    for status, meaning in VERDICTS.items():
        row += 1
        ws.write(row, 0, status, status_formats[status])
        ws.merge_range(row, 1, row, total_col + 3, meaning, formats.wrap)
    row += 2
    ws.write(row, 0, "Coverage", styles.group)
    for document in documents:
        coverage = coverage_of(document)
        row += 1
        ws.write(row, 0, document.key, formats.plain)
        text = "; ".join(f"{s}: {n}" for s, n in coverage["sections"].items())
        ws.merge_range(row, 1, row, total_col + 3, f"claims per section — {text}", formats.wrap)
        ws.set_row(row, LINE_HEIGHT * _lines(text, 100))
        for omitted in document.omitted:
            row += 1
            text = f"left out ({omitted['section']}): {omitted['what']} — {omitted['why']}"
            ws.merge_range(row, 1, row, total_col + 3, text, formats.wrap)
            ws.set_row(row, LINE_HEIGHT * _lines(text, 100))
    ws.set_paper(9)
    ws.set_landscape()
    ws.fit_to_pages(1, 0)


def _width(text):
    """Display width in characters: CJK characters take two."""
    return sum(1.8 if ord(ch) > 0x2E7F else 1 for ch in str(text))


def _lines(text, width):
    """Wrapped lines of ``text`` in a column ``width`` characters wide."""
    per_line = max(width * 1.15, 1)      # text is narrower than the '0' a width counts
    return max(1, sum(math.ceil(max(_width(part), 1) / per_line)
                      for part in str(text).split("\n")))


def _write_document_sheet(book, document, name, formats, status_formats):
    styles = formats.styles
    ws = book.add_worksheet(name)
    ws.write(0, 0, f"{document.key}: {document.title}", styles.title)
    ws.write(1, 0, f"Source: {document.file} (line = its line). Recomputations are live "
                   f"formulas on the yellow input cells to the right: change an input and "
                   f"the verdict follows. Verdicts: see the Summary sheet.", styles.subtitle)
    for col, (label, width, _) in enumerate(COLUMNS):
        ws.write(HEADER_ROW, col, label, styles.header)
        ws.set_column(col, col, width)
    ws.write(HEADER_ROW, INPUTS_AT, "inputs (name, value, …)", styles.header)
    ws.set_column(INPUTS_AT, INPUTS_AT + 16, 11)
    for row, (claim, finding) in enumerate(zip(document.claims, document.findings()),
                                           start=HEADER_ROW + 1):
        _write_claim_row(ws, row, claim, finding, formats)
    last = HEADER_ROW + len(document.claims)
    for status, fmt in status_formats.items():
        ws.conditional_format(HEADER_ROW + 1, COL["verdict"], last, COL["verdict"],
                              {"type": "cell", "criteria": "==", "value": f'"{status}"',
                               "format": fmt})
    ws.freeze_panes(HEADER_ROW + 1, 3)
    ws.autofilter(HEADER_ROW, 0, last, len(COLUMNS) - 1)
    ws.repeat_rows(HEADER_ROW)
    ws.print_area(0, 0, last, len(COLUMNS) - 1)
    ws.set_paper(9)
    ws.set_landscape()
    ws.set_margins(left=0.4, right=0.4, top=0.5, bottom=0.5)
    ws.fit_to_pages(1, 0)
    ws.set_footer("&L&A&R&P / &N")


def _write_claim_row(ws, row, claim, finding, formats):
    excel_row = row + 1
    digits = decimals_of(claim)
    cells = {}
    for i, (input_name, value) in enumerate(claim.inputs.items()):
        ws.write(row, INPUTS_AT + 2 * i, input_name, formats.key)
        ws.write_number(row, INPUTS_AT + 2 * i + 1, float(value),
                        formats.number(decimals_of_value(value), role="input"))
        cells[input_name] = f"${xl_col_to_name(INPUTS_AT + 2 * i + 1)}${excel_row}"
    ws.write(row, COL["key"], claim.key, formats.key)
    ws.write(row, COL["section"], claim.section, formats.wrap)
    ws.write_number(row, COL["line"], claim.line, formats.centred)
    ws.write(row, COL["claim"], claim.claim, formats.wrap)
    if claim.reported is not None:
        ws.write_number(row, COL["reported"], claim.reported, formats.number(digits))
    else:
        ws.write(row, COL["reported"], "(formula)", formats.plain)
    ws.write(row, COL["unit"], claim.unit, formats.plain)
    if finding["derived"] is not None:
        ws.write_number(row, COL["derived"], finding["derived"], formats.number(digits))
        ws.write(row, COL["derived: what"], finding["derived_what"], formats.wrap)
    recomputed = finding["recomputed"]
    if claim.formula and recomputed is not None:
        formula = "=" + INPUT.sub(lambda m: cells[m.group(1)], claim.formula)
        ws.write_formula(row, COL["recomputed"], formula, formats.number(digits), recomputed)
    elif recomputed is not None:
        ws.write_number(row, COL["recomputed"], recomputed, formats.number(digits))
    compared = f"{xl_col_to_name(COL['reported' if claim.reported is not None else 'derived'])}" \
               f"{excel_row}"
    rec = f"{xl_col_to_name(COL['recomputed'])}{excel_row}"
    tol = f"{xl_col_to_name(COL['tolerance'])}{excel_row}"
    differs = STATUS_OF_KIND.get(claim.kind, "unverifiable")
    ws.write_number(row, COL["tolerance"], claim.tolerance, formats.percent)
    verdict = (f'=IF(OR({compared}="",{rec}=""),"unverifiable",IF(ABS({compared}-{rec})<='
               f'MAX({tol}*ABS({rec}),{claim.abs_tolerance!r}),"ok","{differs}"))')
    ws.write_formula(row, COL["verdict"], verdict, formats.verdict, finding["status"])
    if claim.kind == "rule":
        margin = (f'=IF({xl_col_to_name(COL["verdict"])}{excel_row}="outside-rule",'
                  f'({compared}-{rec})/ABS({rec})*100,"")')
        ws.write_formula(row, COL["margin %"], margin, formats.margin,
                         finding["margin_percent"] if finding["margin_percent"] is not None
                         else "")
    ws.write(row, COL["kind"], claim.kind, formats.plain)
    ws.write(row, COL["basis"], _basis(claim), formats.wrap)
    ws.write(row, COL["note"], claim.note, formats.wrap)
    texts = {"section": claim.section, "claim": claim.claim,
             "derived: what": finding["derived_what"], "basis": _basis(claim),
             "note": claim.note}
    height = max(_lines(text, COLUMNS[COL[label]][1]) for label, text in texts.items())
    ws.set_row(row, LINE_HEIGHT * height + 2)


def decimals_of_value(value):
    """Decimal places of a number as Python writes it shortest (at most 6)."""
    text = repr(float(value))
    if "e" in text:
        return 6
    return min(len(text.partition(".")[2].rstrip("0")), 6)
