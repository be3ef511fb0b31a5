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

from crankbook.support.atomic import atomic_path
from crankbook.audit.claims import (FORMULA_AGREEMENT, INPUT, MATERIALITY, MINOR_PERCENT,
                                    NOISE_FLOOR, STATUS_OF_KIND, VERDICTS, coverage,
                                    root_causes, shown, unit_of_last_digit)
from crankbook.writer.build import FIXED_TIME
from crankbook.writer.print_setup import (A4, READABLE_SCALE, print_scale, row_height,
                                          row_points)
from crankbook.writer.styles import Styles

# (label, width in characters, wrapped).  The columns an auditor signs come first and
# print as one document (the key repeated on every page); the explanations follow on
# pages of their own after it.
SIGNED = [("key", 22, True), ("claim", 32, True),
          ("quote (line, offset)", 20, True), ("reported", 10, False), ("unit", 6, False),
          ("recomputed", 12, False), ("deviation", 11, False), ("deviation %", 9, False),
          ("tolerance", 9, False), ("verdict", 12, True), ("materiality", 10, False),
          ("note", 40, True)]
# a page of their own after the signed columns, at their scale: wide enough that
# their words do not make the rows taller than the signed columns need
EXPLAINED = [("section", 9, True), ("line", 5, False), ("derived", 12, False),
             ("derived: what", 30, True), ("tolerance: why", 34, True), ("margin %", 9, False),
             ("kind", 9, False), ("basis", 48, True)]
COLUMNS = SIGNED + EXPLAINED
COL = {label: i for i, (label, _, _) in enumerate(COLUMNS)}
INPUTS_AT = len(COLUMNS)            # input name/value pairs start in this column
STATUSES = list(VERDICTS)
COLOURS = {"ok": "#C6EFCE", "mismatch": "#FFC7CE", "inconsistent": "#FFEB9C",
           "model-disagrees": "#F8CBAD", "outside-rule": "#DDEBF7", "unverifiable": "#D9D9D9",
           "comparison": "#EDE7F6"}
FINDING_FIELDS = ["document", "key", "section", "line", "offset", "quote", "claim", "reported",
                  "printed", "unit", "derived", "derived_what", "recomputed", "status", "kind",
                  "tolerance", "tolerance_reason", "reported_display", "recomputed_display",
                  "deviation", "deviation_percent", "margin_percent", "materiality", "group",
                  "caveat",
                  "other", "other_line", "model", "missing", "note"]
HEADER_ROW = 3
NO_SOURCES = ("the seed texts were not given (--sources DIR or $CRANKBOOK_SEEDS): the "
              "numbers of the audited sections cannot be counted")


def _atomic(path, write):
    with atomic_path(path) as temporary:
        write(temporary)


def _clean(value):
    return None if isinstance(value, float) and not math.isfinite(value) else value


def write_json(documents, path, sources=None):
    findings = [{k: _clean(f[k]) for k in FINDING_FIELDS}
                for d in documents for f in d.findings()]
    coverage = {d.key: coverage_of(d, sources) for d in documents}

    def write(temporary):
        with open(temporary, "w", encoding="utf-8") as handle:
            json.dump({"verdicts": VERDICTS, "findings": findings, "coverage": coverage},
                      handle, ensure_ascii=False, indent=1)
    _atomic(path, write)


def coverage_of(document, sources=None):
    """The document's coverage: every number of its audited sections, claimed or left
    out with why (claims.coverage, from the seed text in ``sources``); the claims per
    section and the sections left out as a whole."""
    out = {"claims": len(document.claims),
           "sections": dict(Counter(c.section for c in document.claims)),
           "omitted_sections": [dict(o) for o in document.omitted
                                if "line" not in o and "lines" not in o]}
    if sources is None:
        out.update(numbers=None, claimed=None, left_out=None, why=NO_SOURCES)
        return out
    lines = (Path(sources) / document.file).read_text(encoding="utf-8").splitlines()
    out.update(coverage(document, lines))
    return out


def _basis(finding):
    """What a verdict rests on besides the recomputation, in words (and what the
    document's inputs are, where they are illustrative)."""
    basis = _basis_alone(finding)
    return f"{basis}; inputs: {finding['caveat']}" if finding.get("caveat") else basis


def _basis_alone(finding):
    if finding["kind"] == "consistency":
        return f"other statement (line {finding['other_line']}): {finding['other']}"
    if finding["kind"] in ("model", "comparison"):
        return f"model: {finding['model']}"
    if finding["kind"] == "unverifiable":
        return f"missing: {finding['missing']}"
    if finding["kind"] == "rule":
        return "rule quoted by the document; recomputed = the nearest value inside it"
    return "the document's own inputs and formula"


def _deviation(finding):
    if finding["deviation"] is None:
        return "—"
    text = shown(finding["deviation"], ".3g")
    if finding["deviation_percent"] is not None:
        text += f" ({shown(finding['deviation_percent'], '+.3g')} %)"
    return text


def _quote(finding):
    return f"{finding['line']}:{finding['offset']} “{finding['quote']}”"


def write_markdown(documents, path, sources=None):
    lines = ["# Audit of the source documents", "",
             "Every number the documents print, beside an independent recomputation "
             "(`crankbook audit`). `line:offset` locates the quote in the seed file "
             "(character offset within the line, from 0). **ok** means within the "
             "tolerance of the row (half a unit of the last printed digit unless the row "
             "says why wider). Verdicts — one meaning each:", ""]
    lines += [f"- **{status}**: {meaning}" for status, meaning in VERDICTS.items()]
    lines += ["", "Each finding that is not ok has a materiality — one meaning each:", ""]
    lines += [f"- **{kind}**: {meaning}" for kind, meaning in MATERIALITY.items()]
    lines += ["", "A table's entries with one root cause (one table, one verdict) are one "
              "finding: *findings* counts root causes, the verdict columns count entries.",
              "", "| document | claims | " + " | ".join(STATUSES) + " | findings | "
              + " | ".join(MATERIALITY) + " |",
              "|---|---|" + "---|" * (len(STATUSES) + 1 + len(MATERIALITY))]
    for d in documents:
        counts = Counter(f["status"] for f in d.findings())
        material = Counter(f["materiality"] for f in d.findings())
        lines.append(f"| {d.key} | {len(d.claims)} | "
                     + " | ".join(str(counts.get(s, 0)) for s in STATUSES)
                     + f" | {len(root_causes(d.findings()))} | "
                     + " | ".join(str(material.get(m, 0)) for m in MATERIALITY) + " |")
    for d in documents:
        causes = [(f, n) for f, n in root_causes(d.findings()) if n > 1]
        grouped = ["", "Root causes shared by several entries:", ""] + [
            f"- {f['group']}: **{f['status']}** in {n} entries (the first: {f['key']}, "
            f"{f['materiality']})" for f, n in causes] if causes else []
        lines += ["", f"## {d.key}: {d.title}", "", f"Source: `{d.file}`"] + \
            (["", f"Inputs: {d.caveat}"] if d.caveat else []) + grouped + ["",
                  "| § | quote (line:offset) | claim | reported | recomputed | unit | deviation "
                  "| tolerance | verdict | basis | note |",
                  "|---|---|---|---|---|---|---|---|---|---|---|"]
        for f in d.findings():
            verdict = f["status"] if f["status"] == "ok" else f"**{f['status']}**"
            if f["margin_percent"] is not None:
                verdict += f" ({f['margin_percent']:+.1f} %)"
            if f["materiality"]:
                verdict += f", {f['materiality']}"
            derived = "" if f["derived"] is None else \
                f" — derived: {shown(f['derived'], '.6g')} ({f['derived_what']})"
            cells = [f["section"], _quote(f), f["claim"], f["reported_display"],
                     f["recomputed_display"] + derived, f["unit"], _deviation(f),
                     f"±{shown(f['tolerance'], '.2g')} ({f['tolerance_reason']})", verdict,
                     _basis(f), f["note"]]
            lines.append("| " + " | ".join(str(c).replace("|", "\\|").replace("\n", " ")
                                           for c in cells) + " |")
        lines += ["", f"### Coverage of {d.key}", ""] + _coverage_lines(coverage_of(d, sources))

    def write(temporary):
        Path(temporary).write_text("\n".join(lines) + "\n", encoding="utf-8")
    _atomic(path, write)


def _coverage_lines(coverage):
    out = ["Claims per section: " + ", ".join(f"{s} ({n})"
                                              for s, n in coverage["sections"].items()) + "."]
    if coverage["numbers"] is None:
        out += ["", coverage["why"] + "."]
    else:
        ranges = ", ".join(f"{a}–{b}" for a, b in coverage["audited"])
        out += ["", f"Audited lines {ranges}: {coverage['numbers']} numbers, "
                    f"{coverage['claimed']} in a claim's quote, {coverage['left_out']} left out "
                    f"(below, by reason), {len(coverage['unaccounted'])} unaccounted."]
        reasons = Counter(n["reason"] for n in coverage["left_out_numbers"])
        out += [""] + [f"- {n} × {reason}" for reason, n in reasons.most_common()]
    if coverage["omitted_sections"]:
        out += ["", "Left out as a whole:", ""]
        out += [f"- {o['section']}: {o['what']} — {o['why']}" for o in coverage["omitted_sections"]]
    return out


def write_audit_workbook(documents, path, sources=None):
    _atomic(path, lambda temporary: _write_book(documents, temporary, sources))


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
                                    "font_color": "#1F3864", "valign": "top",
                                    "text_wrap": True})
        self.percent = book.add_format({"font_name": "Arial", "font_size": 10,
                                        "num_format": "0.###%", "valign": "top"})
        self.margin = book.add_format({"font_name": "Arial", "font_size": 10,
                                       "num_format": "+0.00;-0.00;0", "valign": "top"})
        self.general = book.add_format({"font_name": "Arial", "font_size": 10,
                                        "num_format": "General", "valign": "top"})
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


def _write_book(documents, filename, sources=None):
    book = xlsxwriter.Workbook(filename)
    book.set_properties({"title": "crankbook audit", "author": "crankbook",
                         "created": FIXED_TIME})
    book.formats[0].set_font_name("Arial")        # the width of a column's character
    book.formats[0].set_font_size(10)              # is the Normal style's
    formats = _Formats(book)
    summary = book.add_worksheet("Summary")
    status_formats = {s: book.add_format({"bg_color": c}) for s, c in COLOURS.items()}
    names = {d.key: d.key[:31] for d in documents}
    for document in documents:
        _write_document_sheet(book, document, names[document.key], formats, status_formats)
    _write_summary(book, summary, documents, names, formats, status_formats, sources)
    summary.activate()
    book.close()


def _write_summary(book, ws, documents, names, formats, status_formats, sources):
    styles = formats.styles
    ws.write(0, 0, "Audit summary: verdicts per document (formulas over the sheets)", styles.title)
    ws.write(1, 0, "Each document's sheet lists every number it prints with its line in the "
                   "seed file; click a name to open the sheet.", styles.subtitle)
    ws.write(HEADER_ROW, 0, "document", styles.header)
    for col, status in enumerate(STATUSES, start=1):
        ws.write(HEADER_ROW, col, status, styles.header)
    total_col = len(STATUSES) + 1
    ws.write(HEADER_ROW, total_col, "total", styles.header)
    extra = ["findings", *MATERIALITY]        # root causes, then materiality counts
    for offset, label in enumerate(extra, start=1):
        ws.write(HEADER_ROW, total_col + offset, label, styles.header)
    ws.set_column(0, 0, 18)
    ws.set_column(1, total_col + 4, 13)
    ws.set_row(HEADER_ROW, row_points([(status, 13) for status in STATUSES], bold=True))
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
        # root causes: a table column's entries with one verdict count once
        ws.write_number(row, total_col + 1, len(root_causes(document.findings())))
        material = Counter(f["materiality"] for f in document.findings())
        column = xl_col_to_name(COL["materiality"])
        for offset, kind in enumerate(MATERIALITY, start=2):
            ws.write_formula(row, total_col + offset,
                             f"=COUNTIF('{name}'!${column}:${column},\"{kind}\")", None,
                             material.get(kind, 0))
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
    chart.set_legend({"position": "right"})     # below, it would squeeze out bar labels
    chart.set_size({"width": 720, "height": 240})           # 12 rows of 20 px
    ws.insert_chart(last + 2, 0, chart)
    row = last + 15
    ws.write(row, 0, "Verdicts", styles.group)
    for status, meaning in VERDICTS.items():
        row += 1
        ws.write(row, 0, status, status_formats[status])
        ws.merge_range(row, 1, row, total_col + 3, meaning, formats.wrap)
    row += 2
    ws.write(row, 0, "Materiality (findings that are not ok)", styles.group)
    for kind, meaning in MATERIALITY.items():
        row += 1
        ws.write(row, 0, kind, formats.plain)
        ws.merge_range(row, 1, row, total_col + 3, meaning, formats.wrap)
    row += 1
    ws.merge_range(row, 0, row, total_col + 3,
                   "findings: root causes — a table's entries with one cause (one table, "
                   "one verdict) count once; the verdict columns count entries",
                   formats.wrap)
    row += 2
    ws.set_h_pagebreaks([row])        # the table, chart and key on one page; coverage next
    ws.write(row, 0, "Coverage", styles.group)
    for document in documents:
        for text in _coverage_lines(coverage_of(document, sources)):
            if not text:
                continue
            row += 1
            if text.startswith("Claims per section"):
                ws.write(row, 0, document.key, formats.plain)
            ws.merge_range(row, 1, row, total_col + 3, text.lstrip("- "), formats.wrap)
            ws.set_row(row, row_points([(text, 100)]))
    ws.set_paper(A4)
    ws.set_landscape()
    ws.fit_to_pages(1, 0)


def _write_document_sheet(book, document, name, formats, status_formats):
    styles = formats.styles
    ws = book.add_worksheet(name)
    ws.write(0, 0, f"{document.key}: {document.title}", styles.title)
    ws.write(1, 0, f"Source: {document.file} (line = its line). Recomputations are live "
                   f"formulas on the yellow input cells to the right: change an input and "
                   f"the verdict follows. Verdicts: see the Summary sheet.", styles.subtitle)
    if document.caveat:               # a line of its own, wrapped across the signed columns
        ws.merge_range(2, 0, 2, COL["note"], f"Inputs: {document.caveat}.", formats.wrap)
        ws.set_row(2, row_points([(document.caveat, sum(w for _, w, _ in SIGNED))]))
    for col, (label, width, _) in enumerate(COLUMNS):
        ws.write(HEADER_ROW, col, label, styles.header)
        ws.set_column(col, col, width)
    ws.set_row(HEADER_ROW, row_points([(label, width) for label, width, _ in COLUMNS],
                                      bold=True))
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
    _page_setup(ws, last)


def _page_setup(ws, last):
    """A4 landscape: the signed columns across one page at the scale that fits them,
    all of their pages first, then the explanations (a fixed scale, because Excel
    ignores a page break under fit-to-page)."""
    ws.repeat_rows(HEADER_ROW)
    ws.repeat_columns(COL["key"])
    ws.print_area(0, 0, last, len(COLUMNS) - 1)
    ws.set_paper(A4)
    ws.set_landscape()
    ws.set_margins(left=0.4, right=0.4, top=0.5, bottom=0.5)
    ws.set_v_pagebreaks([len(SIGNED)])
    scale = print_scale([w for _, w, _ in SIGNED], 842 - 2 * 0.4 * 72)
    ws.set_print_scale(_no_page_of_a_few_rows(ws, last, scale))
    ws.set_footer("&L&A&R&P / &N")


PAGE_POINTS = 595 - 2 * 0.5 * 72       # A4 landscape less the top and bottom margins


def _no_page_of_a_few_rows(ws, last, scale):
    """The print scale (%): ``scale``, or the largest up to a sixth smaller (never
    under READABLE_SCALE) at which the last page holds a third of the claims of the
    fullest (the balancing ring's ninth claim printed alone).  The rows' heights are
    set, so this pagination is the engines'."""
    height = lambda row: row_height(ws, row, 15)
    header, top = height(HEADER_ROW), sum(height(r) for r in range(HEADER_ROW + 1))
    rows = [height(r) for r in range(HEADER_ROW + 1, last + 1)]

    def claims_per_page(fraction):
        used, counts = top, [0]
        for row in rows:                      # the header repeats on every page
            if (used + row) * fraction > PAGE_POINTS and counts[-1]:
                used, counts = header, counts + [0]
            used += row
            counts[-1] += 1
        return counts
    start = int(100 * scale)               # a print scale is a whole percentage
    for percent in range(start, math.ceil(100 * max(scale * 5 / 6, READABLE_SCALE)) - 1, -1):
        counts = claims_per_page(percent / 100)
        if len(counts) == 1 or counts[-1] * 3 >= max(counts):
            return percent
    return start


def _digits(display):
    """Decimal places of a displayed number ('70.40' → 2)."""
    mantissa = display.lower().partition("e")[0]
    return len(mantissa.partition(".")[2]) if "/" not in display else 6


def _write_claim_row(ws, row, claim, finding, formats):
    excel_row = row + 1
    shown_digits = _digits(finding["recomputed_display"])
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
    ws.write(row, COL["quote (line, offset)"], _quote(finding), formats.wrap)
    compared = claim.compared()
    if claim.reported is not None:
        ws.write_number(row, COL["reported"], compared,
                        formats.number(_digits(finding["reported_display"])))
    else:
        ws.write(row, COL["reported"], "(formula)", formats.plain)
    ws.write(row, COL["unit"], claim.unit, formats.plain)
    if finding["derived"] is not None:
        ws.write_number(row, COL["derived"], finding["derived"], formats.number(shown_digits))
        ws.write(row, COL["derived: what"], finding["derived_what"], formats.wrap)
    recomputed = finding["recomputed"]
    if claim.formula and recomputed is not None:
        formula = "=" + INPUT.sub(lambda m: cells[m.group(1)], claim.formula)
        ws.write_formula(row, COL["recomputed"], formula, formats.number(shown_digits),
                         recomputed)
    elif recomputed is not None:
        ws.write_number(row, COL["recomputed"], recomputed, formats.number(shown_digits))
    compared_cell = f"{xl_col_to_name(COL['reported' if claim.reported is not None else 'derived'])}" \
                    f"{excel_row}"
    rec = f"{xl_col_to_name(COL['recomputed'])}{excel_row}"
    tol = f"{xl_col_to_name(COL['tolerance'])}{excel_row}"
    if finding["deviation"] is not None:
        ws.write_formula(row, COL["deviation"], f"={compared_cell}-{rec}",
                         formats.number(shown_digits), finding["deviation"])
        if finding["deviation_percent"] is not None:
            ws.write_formula(row, COL["deviation %"],
                             f'=IF(ABS({rec})<={FORMULA_AGREEMENT:G}*ABS({compared_cell})'
                             f'+{NOISE_FLOOR:G},"",({compared_cell}-{rec})/{rec}*100)',
                             formats.margin, finding["deviation_percent"])
    differs = STATUS_OF_KIND.get(claim.kind, "unverifiable")
    ws.write_number(row, COL["tolerance"], finding["tolerance"], formats.general)
    ws.write(row, COL["tolerance: why"], finding["tolerance_reason"], formats.wrap)
    # the same test as claims.Claim.within: |compared − recomputed| ≤ tolerance
    verdict = (f'=IF(OR({compared_cell}="",{rec}=""),"unverifiable",'
               f'IF(ABS({compared_cell}-{rec})<={tol}*(1+1E-12),"ok","{differs}"))')
    ws.write_formula(row, COL["verdict"], verdict, formats.verdict, finding["status"])
    # the same classes as claims.materiality, live on the same cells
    verdict_cell = f"{xl_col_to_name(COL['verdict'])}{excel_row}"
    dev = f"{xl_col_to_name(COL['deviation'])}{excel_row}"
    pct = f"{xl_col_to_name(COL['deviation %'])}{excel_row}"
    if finding["deviation"] is not None:
        ws.write_formula(
            row, COL["materiality"],
            f'=IF(OR({verdict_cell}="ok",{verdict_cell}="unverifiable",'
            f'{verdict_cell}="comparison"),"",'
            f'IF(ABS({dev})<={tol}+{unit_of_last_digit(claim):G},"rounding",'
            f'IF({pct}="","material",IF(ABS({pct})<{MINOR_PERCENT:G},"minor","material"))))',
            formats.plain, finding["materiality"])
    if claim.kind == "rule":
        margin = (f'=IF({xl_col_to_name(COL["verdict"])}{excel_row}="outside-rule",'
                  f'({compared_cell}-{rec})/ABS({rec})*100,"")')
        ws.write_formula(row, COL["margin %"], margin, formats.margin,
                         finding["margin_percent"] if finding["margin_percent"] is not None
                         else "")
    ws.write(row, COL["kind"], claim.kind, formats.plain)
    ws.write(row, COL["basis"], _basis(finding), formats.wrap)
    ws.write(row, COL["note"], finding["note"], formats.wrap)
    texts = {"key": claim.key, "section": claim.section, "claim": claim.claim,
             "quote (line, offset)": _quote(finding),
             "derived: what": finding["derived_what"], "basis": _basis(finding),
             "tolerance: why": finding["tolerance_reason"], "note": finding["note"]}
    ws.set_row(row, row_points([(text, COLUMNS[COL[label]][1])
                                for label, text in texts.items()]))


def decimals_of_value(value):
    """Decimal places of a number as Python writes it shortest (at most 6)."""
    text = repr(float(value))
    if "e" in text:
        return 6
    return min(len(text.partition(".")[2].rstrip("0")), 6)
