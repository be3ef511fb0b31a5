"""`crankbook check FILE`: a student's look at their workbook before handing it in.

The file is read exactly as `crankbook grade` reads it (the bounded reader, the
same answer blocks, the same placing of position rows) and what grading would
lose is listed in the file's language: a file that cannot be read, text in a
number cell, a unit the item cannot take, rows whose crank angle names no
position, blank answers.  It never says whether a number is right: no score, no
expected value — the positions are placed against the mechanism of the
parameters printed in the student's own file, the grader's rule for "which row is
which", not a verdict on the angles.
"""
from dataclasses import dataclass, field
from pathlib import Path

from crankbook.spec import params
from crankbook.assignment import template as templates
from crankbook.assignment.results import reason_text, say, words
from crankbook.assignment.student_book import TASK
from crankbook.errors import CrankbookError
from crankbook.reading.workbook_reader import parse_reference
from crankbook.reading.xlsx_reader import Unreadable, XlsxBook
from crankbook.support.paths import not_a_file

LOST = ("not_a_number", "wrong_unit", "machine_dependent", "ambiguous_number")          # cell reasons whose answer grading cannot use


@dataclass
class CheckReport:
    """What the grader would make of a file: ``lines`` in the file's language;
    ``complete`` when every answer would be read."""
    lang: str
    lines: list = field(default_factory=list)
    complete: bool = True
    blank: int = 0                 # answer cells left empty
    answered: int = 0

    def lose(self, text):
        self.lines.append(text)
        self.complete = False


def _file_facts(path):
    """(assignment key, lang, p_ values as typed) of a student workbook; Unreadable
    for anything else."""
    book = XlsxBook(path)
    try:
        role = book.custom_properties.get("crankbook_role")
        if role != "student":
            what = {"key": "an answer key", "workbook": "a crankbook workbook, not a task"}
            raise Unreadable(f"not a crankbook student workbook"
                             f"{' (' + what[role] + ')' if role in what else ''}")
        assignment = book.custom_properties.get("crankbook_assignment") or ""
        lang = book.custom_properties.get("crankbook_language") or \
            ("en" if TASK["en"] in book.sheetnames else "zh")
        sheets = set(book.sheetnames)
        typed = {}
        for name, text in book.defined_names.items():
            if name.startswith("p_"):
                found = parse_reference(name, text, sheets)
                typed[name[2:]] = book.values(found.sheet, found.min_row, found.min_col,
                                              found.max_row, found.max_col)
        return assignment, lang, typed
    finally:
        book.close()


def _values(spec, base, typed):
    """The file's parameters as the workbook's values (the preset's where the task does
    not print one: the pressure model behind the given table), or None if they do not
    make a mechanism (the student changed them)."""
    values = {}
    for p in spec.parameters:
        if p.key not in typed:
            values[p.key] = base[p.key]
            continue
        cells = [v for v in typed[p.key] if v is not None]
        try:
            values[p.key] = params.coerce(p, cells if p.axis else cells[0])
        except (CrankbookError, IndexError):
            return None
    try:
        return params.validate(spec, values)
    except CrankbookError:
        return None


def check(path):
    """The CheckReport of one returned workbook."""
    from crankbook.assignment.grade import answer_shapes, grade_submission
    from crankbook.assignment.submissions import Submission, read
    path = Path(path)
    reason = not_a_file(path)
    if reason:                          # a student's usage slip: said in both languages
        raise CrankbookError(f"{path}: {reason_text(reason, 'zh')} / {reason}")
    try:
        key, lang, typed = _file_facts(path)
    except (Unreadable, CrankbookError) as reason:     # no language to speak yet: both
        report = CheckReport("both")
        report.lose(" / ".join(say(words(lang), "check_unreadable",
                                   reason=reason_text(str(reason), lang)) for lang in ("zh", "en")))
        return report
    w = words(lang)
    report = CheckReport(lang)
    try:
        assignment = templates.load(key)
    except CrankbookError:
        report.lose(say(w, "check_unknown_assignment", assignment=key))
        return report
    spec, base, preset = params.load_preset(assignment.preset)
    values = _values(spec, base, typed)
    shapes = answer_shapes(assignment, lang, spec, values)
    sub = Submission(path=path, relative=path.name)
    read(sub, shapes)
    if sub.problem:
        report.lose(say(w, "check_unreadable", reason=reason_text(sub.problem, lang)))
        return report
    if sub.needs_recalc:
        report.lines.append(w["check_needs_recalc"])
    if values is None:
        report.lines.append(w["check_parameters_changed"])
        return _cells_only(report, w, assignment, sub, lang)
    row = {f"p_{k}": (",".join(repr(float(x)) for x in v) if isinstance(v, list) else repr(v))
           for k, v in values.items()}
    items, problems = grade_submission(sub, row, assignment, spec, preset, lang)
    for word, fields in problems:
        report.lines.append(say(w, word, **fields))
    for item in assignment.items:
        _, cells = items.get(item.key, (0, []))
        _report_cells(report, w, item, lang, [(c.label, c.value, c.reason, c.detail)
                                              for c in cells])
    return _summary(report, w)


def _cells_only(report, w, assignment, sub, lang):
    """Without a mechanism to place rows by: each answer cell as it stands."""
    from crankbook.assignment.scoring import read_answer, unread_reason
    for item in assignment.items:
        cells = []
        for number, value in enumerate(sub.answers.get(item.key, [])):
            parsed = read_answer(value)[0]
            reason = "no_answer" if value is None or value == "" else \
                "machine_dependent" if getattr(value, "machine_dependent", False) else \
                (unread_reason(value) if parsed is None else "number")
            cells.append((str(number + 1), value, reason, {}))
        _report_cells(report, w, item, lang, cells or [("", None, "no_answer", {})])
    return _summary(report, w)


def _report_cells(report, w, item, lang, cells):
    label = item.label(lang)
    empty = [c for c in cells if c[2] == "no_answer"]
    report.blank += len(empty)
    report.answered += len(cells) - len(empty)
    for row, value, reason, detail in cells:
        if reason in LOST:
            report.lose(say(w, "check_cell", item=label, row=row or w["scalar_row"],
                            value=str(value)[:40], reason=say(w, reason, **detail)))
    # numbers typed as text are read, but the student should know Excel will not use them
    texts = [str(c[0]) for c in cells if isinstance(c[1], str) and c[2] not in LOST and
             c[2] != "no_answer" and not getattr(c[1], "machine_dependent", False)]
    if texts:
        report.lines.append(say(w, "check_text_numbers", item=label, count=len(texts),
                                rows=", ".join(t or w["scalar_row"] for t in texts[:8]) +
                                (" …" if len(texts) > 8 else "")))
    if cells and len(empty) == len(cells):
        report.lose(say(w, "check_blank_item", item=label))
    elif empty:
        report.lose(say(w, "check_blank_cells", item=label, count=len(empty),
                        rows=", ".join(str(c[0]) for c in empty[:8]) +
                        (" …" if len(empty) > 8 else "")))


def _summary(report, w):
    report.lines.append(say(w, "check_complete" if report.complete else "check_incomplete",
                            answered=report.answered, blank=report.blank))
    return report

