"""Document claims (templates/claims/*.toml) and their recomputation.

Each claim is one number a source document prints — ``reported``, found at ``line``
of the seed file (verbatim in ``printed`` where it is not a plain decimal, e.g.
"1/3"; ``extracted`` where the PDF extraction garbled it, e.g. "45974.72" for
72.45974) — with the inputs it depends on, the recomputation as an Excel formula
template ({input} placeholders) and as a Python expression over the same inputs in
the document's units (it may call calc/ through the helpers below), a tolerance and
a note.  A number the audit needs on the way (an area, an evaluated formula) is a
``derived`` value with its own formula, never the ``reported`` one.  Where the
document prints a formula or a statement but no number (``reported`` left out), the
claim compares its ``derived`` value — the printed formula evaluated, or the value
the statement is about — with the recomputation.

One verdict per outcome, the same for every claim (VERDICTS defines them):

* ``ok``              — the recomputation agrees within the tolerance
* ``mismatch``        — kind ``value``: the document's own inputs and formula give
                        another number
* ``inconsistent``    — kind ``consistency``: another statement of the document
                        (``other``, at ``other_line``) contradicts it
* ``model-disagrees`` — kind ``model``: an independent engineering model crankbook
                        computes (``model`` names it and its assumptions) disagrees
* ``outside-rule``    — kind ``rule``: the value lies outside a design rule the
                        document quotes; the recomputation is the nearest value
                        inside the rule and the margin is given in %
* ``unverifiable``    — kind ``unverifiable``: ``missing`` says what is not stated

A ``[[table]]`` of a claims file is a printed table: one claim per entry, its rows
setting one input (e.g. the crank angle), each ``[[table.column]]`` giving the
printed values and that column's recomputation.  ``[[omitted]]`` lists what a
document prints that is not a claim, and why (the coverage).
"""
import math
import re
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np

from crankbook.calc import (cam, compressor, crankshaft, cycle, forces, gears, kinematics,
                            mechanism, multicylinder, optimization)
from crankbook.toml_files import names_in, read_named

CLAIMS = "claims"
INPUT = re.compile(r"\{([A-Za-z_][A-Za-z_0-9]*)\}")      # {name} of a claim's input
STATUS_OF_KIND = {"value": "mismatch", "consistency": "inconsistent",
                  "model": "model-disagrees", "rule": "outside-rule"}
VERDICTS = {
    "ok": "the recomputation agrees with the printed number within the tolerance",
    "mismatch": "the document's own inputs and formula give another number",
    "inconsistent": "two statements of the document contradict each other (both quoted)",
    "model-disagrees": "an independent engineering model (named, with its assumptions) "
                       "disagrees with the printed number",
    "outside-rule": "the printed value lies outside a design rule the document itself "
                    "quotes (margin in %)",
    "unverifiable": "the document does not state what a recomputation needs (said what)",
}
REQUIRED_BY_KIND = {"consistency": ("other", "other_line"), "model": ("model",),
                    "unverifiable": ("missing",)}
DEFAULT_TOLERANCE = 0.005          # relative: documents print 3–4 significant digits


@lru_cache(maxsize=None)
def _computed(preset, overrides):
    from crankbook.api import compute
    return compute(preset, **dict(overrides))


def workbook(preset, **overrides):
    """A preset's workbook computed by crankbook (cached): a model claim reads its
    recomputation from the same calc functions the workbook's formulas mirror."""
    return _computed(preset, tuple(sorted(overrides.items())))


HELPERS = {
    "__builtins__": {}, "abs": abs, "min": min, "max": max, "round": round, "sum": sum,
    "float": float,
    "pi": math.pi, "sqrt": math.sqrt, "sin": math.sin, "cos": math.cos, "tan": math.tan,
    "asin": math.asin, "acos": math.acos, "atan": math.atan, "radians": math.radians,
    "degrees": math.degrees, "log10": math.log10, "exp": math.exp,
    "np": np, "kinematics": kinematics, "forces": forces, "mechanism": mechanism,
    "optimization": optimization, "cycle": cycle, "multicylinder": multicylinder,
    "gears": gears, "cam": cam, "compressor": compressor, "crankshaft": crankshaft,
    "workbook": workbook,
}


@dataclass
class Claim:
    key: str
    section: str
    line: int                          # line of the seed file where ``reported`` is printed
    claim: str
    unit: str
    reported: float | None = None      # None where the extraction lost the number
    printed: str | None = None         # verbatim, where not a plain decimal ("1/3")
    extracted: str | None = None       # as the garbled extraction carries it
    kind: str = "value"
    inputs: dict = field(default_factory=dict)
    formula: str | None = None
    python: str | None = None
    derived: dict | None = None        # {what, python, unit}: a number met on the way
    other: str = ""                    # consistency: the contradicting statement, quoted
    other_line: int | None = None
    model: str = ""                    # model: the model and its assumptions
    missing: str = ""                  # unverifiable: what the document does not state
    tolerance: float = DEFAULT_TOLERANCE
    abs_tolerance: float = 0.0
    note: str = ""

    def recompute(self):
        """The recomputed value in the document's unit, or None (unverifiable)."""
        if self.kind == "unverifiable" or self.python is None:
            return None
        return float(eval(self.python, HELPERS, dict(self.inputs)))  # noqa: S307 (our data)

    def derived_value(self):
        if not self.derived:
            return None
        return float(eval(self.derived["python"], HELPERS, dict(self.inputs)))  # noqa: S307

    def compared(self):
        """What the recomputation is compared with: the printed number, or for a
        claim on a printed formula or statement its derived value."""
        if self.reported is not None:
            return self.reported
        return self.derived_value() if self.kind != "unverifiable" else None

    def within(self, recomputed):
        limit = max(self.tolerance * abs(recomputed), self.abs_tolerance)
        return abs(self.compared() - recomputed) <= limit

    def status(self, recomputed):
        if recomputed is None or self.compared() is None:
            return "unverifiable"
        return "ok" if self.within(recomputed) else STATUS_OF_KIND[self.kind]

    def margin_percent(self, recomputed):
        """How far a rule claim's value lies outside its rule, in % of the limit."""
        if self.kind != "rule" or recomputed is None or self.compared() is None or \
                not recomputed or self.within(recomputed):
            return None
        return (self.compared() - recomputed) / abs(recomputed) * 100


@dataclass
class Document:
    key: str
    file: str
    title: str
    claims: list
    omitted: list = field(default_factory=list)    # [{section, what, why}]: coverage

    def findings(self):
        """One dict per claim (computed once: the workbook, the report and the JSON
        all read them)."""
        if getattr(self, "_findings", None) is None:
            self._findings = self._compute_findings()
        return self._findings

    def _compute_findings(self):
        out = []
        for claim in self.claims:
            recomputed = claim.recompute()
            derived = claim.derived_value()
            out.append({"document": self.key, "key": claim.key, "section": claim.section,
                        "line": claim.line, "claim": claim.claim,
                        "reported": claim.reported, "printed": claim.printed or "",
                        "unit": claim.unit, "kind": claim.kind,
                        "derived": derived,
                        "derived_what": (claim.derived or {}).get("what", ""),
                        "recomputed": recomputed, "status": claim.status(recomputed),
                        "margin_percent": claim.margin_percent(recomputed),
                        "tolerance_percent": claim.tolerance * 100,
                        "other": claim.other, "other_line": claim.other_line,
                        "model": claim.model, "missing": claim.missing,
                        "note": claim.note})
        return out


NUMBER = re.compile(r"\d+(?:\.\d+)?")
THOUSANDS = re.compile(r"(?<![\d.])\d{1,3}(?:[ ,]\d{3})+(?![\d.])")   # 26 391, 1,500
FULL_WIDTH = str.maketrans("０１２３４５６７８９．，／－−–", "0123456789.,/---")


def normalise(text):
    """Digits and separators as ASCII, thousands separators dropped: how a printed
    number is looked up in a seed line."""
    text = text.translate(FULL_WIDTH)
    return THOUSANDS.sub(lambda m: re.sub(r"[ ,]", "", m.group(0)), text)


def printed_value(text):
    """The value of a printed number: a decimal or a fraction a/b."""
    numerator, _, denominator = normalise(text).partition("/")
    return float(numerator) / float(denominator) if denominator else float(numerator)


def anchor_problem(claim, lines):
    """Why ``claim``'s reported number is not printed at its line of the seed
    ``lines`` (a list of str), or None when it is."""
    if claim.line > len(lines):
        return f"line {claim.line} is beyond the file's {len(lines)} lines"
    if claim.other_line is not None and not 1 <= claim.other_line <= len(lines):
        return f"other_line {claim.other_line} is beyond the file"
    if claim.reported is None:
        return None
    line = normalise(lines[claim.line - 1])
    token = claim.extracted or claim.printed
    if claim.printed is not None:
        value = printed_value(claim.printed)
        if abs(value - claim.reported) > 1e-6 * max(1.0, abs(value)):
            return f"printed {claim.printed!r} is {value:g}, not the reported {claim.reported:g}"
    if token is not None:
        return None if normalise(token) in line else \
            f"{token!r} does not occur at line {claim.line}"
    target = abs(claim.reported)
    if any(abs(float(n) - target) <= 1e-9 * max(1.0, target) for n in NUMBER.findall(line)):
        return None
    return f"{claim.reported:g} does not occur at line {claim.line}"


def anchor_problems(document, folder):
    """(claim key, problem) for every claim whose number is not at its line of the
    document's seed file in ``folder``."""
    path = Path(folder) / document.file
    lines = path.read_text(encoding="utf-8").splitlines()
    return [(c.key, problem) for c in document.claims
            if (problem := anchor_problem(c, lines)) is not None]


def document_names():
    return names_in(CLAIMS)


TABLE_FIELDS = {"key", "section", "line", "claim", "row", "rows", "inputs", "column", "note"}
COLUMN_FIELDS = {"key", "label", "unit", "values", "python", "formula", "derived", "kind",
                 "tolerance", "abs_tolerance", "note", "model", "other", "other_line"}


def _table_claims(name, table):
    """One claim per printed entry of a [[table]]: its rows set the input ``row``
    (e.g. the crank angle), each [[table.column]] gives the printed values (a
    number, or the printed text where the extraction runs it into its neighbour)
    and the recomputation of that column."""
    where = f"{name}: table {table.get('key', '?')!r}"
    unknown = set(table) - TABLE_FIELDS
    if unknown:
        raise ValueError(f"{where}: unknown field(s) {', '.join(sorted(unknown))}")
    out = []
    for column in table["column"]:
        unknown = set(column) - COLUMN_FIELDS
        if unknown:
            raise ValueError(f"{where}: column {column.get('key')!r}: unknown field(s) "
                             f"{', '.join(sorted(unknown))}")
        if len(column["values"]) != len(table["rows"]):
            raise ValueError(f"{where}: column {column['key']!r} has {len(column['values'])} "
                             f"values for {len(table['rows'])} rows")
        for row, value in zip(table["rows"], column["values"]):
            printed = value if isinstance(value, str) else None
            extra = {k: column[k] for k in ("formula", "derived", "model", "other",
                                            "other_line", "tolerance", "abs_tolerance")
                     if k in column}
            out.append(Claim(
                key=f"{table['key']}_{column['key']}_{row:g}", section=table["section"],
                line=table["line"],
                claim=table["claim"].format(label=column["label"], row=f"{row:g}"),
                unit=column["unit"], reported=printed_value(value) if printed else float(value),
                printed=printed, kind=column.get("kind", "value"),
                inputs={**table.get("inputs", {}), table["row"]: float(row)},
                python=column["python"], note=column.get("note", table.get("note", "")),
                **extra))
    return out


def load(name):
    data = read_named(CLAIMS, name, "document", extra_choices=["all"])
    head = data["document"]
    claims = []
    for entry in data.get("claim", []):
        try:
            claims.append(Claim(**entry))
        except TypeError as error:
            raise ValueError(f"{name}: claim {entry.get('key', '?')!r}: {error}") from None
    for table in data.get("table", []):
        claims += _table_claims(name, table)
    seen = set()
    for claim in claims:
        where = f"{name}: claim {claim.key!r}"
        if claim.key in seen:
            raise ValueError(f"{name}: claim key {claim.key!r} twice")
        seen.add(claim.key)
        if claim.kind not in (*STATUS_OF_KIND, "unverifiable"):
            raise ValueError(f"{where} has unknown kind {claim.kind!r}")
        if not isinstance(claim.line, int) or claim.line < 1:
            raise ValueError(f"{where} needs the seed line where its number is printed")
        for needed in REQUIRED_BY_KIND.get(claim.kind, ()):
            if not getattr(claim, needed):
                raise ValueError(f"{where} of kind {claim.kind} needs {needed!r}")
        if claim.reported is None and not claim.derived and claim.kind != "unverifiable":
            raise ValueError(f"{where} prints no number: it needs a derived value to compare")
        if claim.derived and set(claim.derived) != {"what", "python", "unit"}:
            raise ValueError(f"{where}: derived needs exactly what, python, unit")
        for ref in INPUT.findall(claim.formula or ""):
            if ref not in claim.inputs:
                raise ValueError(f"{where}: formula uses unknown {ref!r}")
    return Document(key=head["key"], file=head["file"], title=head["title"], claims=claims,
                    omitted=data.get("omitted", []))
