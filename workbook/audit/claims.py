"""Document claims (templates/claims/*.toml) and their recomputation.

Each claim is one number a source document prints — ``reported``, found at ``line``
of the seed file, its ``quote`` verbatim at character ``offset`` of that line
(``printed`` where the number is not a plain decimal, e.g. "1/3"; ``extracted``
where the PDF extraction garbled it, e.g. "45974.72" for 72.45974) — with the inputs
it depends on, the recomputation as an Excel formula template ({input}
placeholders) and as a Python expression over the same inputs in the document's
units (it may call calc/ through the helpers below), and a note.  A number the audit
needs on the way is a ``derived`` value with its own formula.  Where the document
prints a formula or a statement but no number (``reported`` left out), the claim
compares its ``derived`` value with the recomputation.

Tolerance (``tolerance_used``): half a unit of the last printed digit; plus, for
inputs the document itself prints rounded (``rounded = {name = half unit}``), the
effect of that rounding; a printed formula or statement agrees to rounding; a rule
has none; ``tolerance`` with ``tolerance_reason`` overrides (a graphical method).

Words (note, model, missing, the derived value's ``what``) are templates: every
number in them is a placeholder filled at run time (:func:`render`), never typed
(:func:`typed_numbers` finds any that is; the tests refuse them).

One verdict per outcome, the same for every claim (VERDICTS defines them):

* ``ok``              — the recomputation agrees within the tolerance
* ``mismatch``        — kind ``value``: arithmetic that does not follow from the
                        document's own numbers
* ``inconsistent``    — kind ``consistency``: another statement of the document
                        (``other``, verbatim at ``other_line``) contradicts it
* ``model-disagrees`` — kind ``model``: an independent engineering model crankbook
                        computes (``model`` names it and its assumptions) disagrees
* ``outside-rule``    — kind ``rule``: the value lies outside a design rule the
                        document quotes; the recomputation is the nearest value
                        inside the rule and the margin is given in %
* ``unverifiable``    — kind ``unverifiable``: ``missing`` says what is not stated
* ``comparison``      — kind ``comparison``: crankbook's workbook computed for another
                        design than the document's (``model`` says which); shown
                        beside the audit, never counted as a finding

A wrong formula is a ``mismatch`` like wrong arithmetic: the recomputation applies
the right formula to the document's own inputs, and ``derived`` shows the
document's own arithmetic (the thesis's journal-to-pin arm, the report's s_a2).
A number the document derives from another printed number that its own inputs do
not give is judged against the chain its inputs give — a discrepancy the note
reports is the verdict, never a note under an ok (the report's a′23, y23, Δy23).
A rule is ok when its value lies inside the rule to rounding.

A ``[[table]]`` of a claims file is a printed table: one claim per entry, its rows
setting one input (e.g. the crank angle), each ``[[table.column]]`` giving the
printed values (as printed, with their ``offsets``) and that column's
recomputation; its ``[[table.fit]]``s make one finding above the entries — which
values of the inputs the printed columns follow (:class:`TableFit`); ``[table.let]``
names expressions its fits, derived values and notes share (:class:`Names`).  ``[document]
audited`` names the line ranges whose every number is accounted for (:func:`coverage`):
inside a claim's quote, or left out by its form (NUMBERING) or by an ``[[omitted]]``
entry (``line`` with ``quote`` or ``span``, or ``lines``) with ``why``.
"""
import math
import re
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np

from crankbook.calc import (cam, compressor, crankshaft, cycle, forces, gears, kinematics,
                            mechanism, multicylinder, optimization)
from crankbook.support.toml_files import names_in, read_named

CLAIMS = "claims"
INPUT = re.compile(r"\{([A-Za-z_][A-Za-z_0-9]*)\}")      # {name} of a claim's input
STATUS_OF_KIND = {"value": "mismatch", "consistency": "inconsistent",
                  "model": "model-disagrees", "rule": "outside-rule",
                  "comparison": "comparison"}
VERDICTS = {
    "ok": "the recomputation agrees with the printed number within the tolerance",
    "mismatch": "the document's own inputs give another number, by its own formula or by "
                "the right one where it used a wrong one (derived: its own arithmetic)",
    "inconsistent": "two statements of the document contradict each other (both quoted)",
    "model-disagrees": "an independent engineering model (named, with its assumptions) "
                       "disagrees with the printed number",
    "outside-rule": "the printed value lies outside a design rule the document itself "
                    "quotes (margin in %)",
    "unverifiable": "the document does not state what a recomputation needs (said what)",
    "comparison": "crankbook's own workbook, computed for another design than the "
                  "document's, gives another number: a comparison beside the audit, not a "
                  "finding against the document",
}
REQUIRED_BY_KIND = {"consistency": ("other", "other_line"), "model": ("model",),
                    "comparison": ("model",),
                    "unverifiable": ("missing",)}
FORMULA_AGREEMENT = 1e-9           # relative: a formula evaluated twice agrees to rounding
NOISE_FLOOR = 1e-12                # absolute, for values near 0 (floating-point noise)
HALF_UNIT = "half a unit of the last printed digit"
AGREEMENT = (f"a printed formula or statement and its recomputation agree to rounding "
             f"({FORMULA_AGREEMENT:g} relative, {NOISE_FLOOR:g} near 0)")
RULE = "a rule: the printed value lies inside the rule the document quotes, or it does not"


@lru_cache(maxsize=None)
def _computed(preset, overrides):
    from crankbook.results import compute
    return compute(preset, **dict(overrides))


def parameter(preset, key, **overrides):
    """A parameter of a preset's workbook, as the workbook holds it (a claim's words
    name a model's inputs through it)."""
    return workbook(preset, **overrides).parameters[key]


def workbook(preset, **overrides):
    """A preset's workbook computed by crankbook (cached): a model claim reads its
    recomputation from the same calc functions the workbook's formulas mirror."""
    return _computed(preset, tuple(sorted(overrides.items())))


def claim_value(document, key):
    """Another claim's recomputation (a note that compares two claims names it)."""
    claim = next((c for c in load(document).claims if c.key == key), None)
    if claim is None:
        raise ValueError(f"{document}: no claim {key!r}")
    return claim.recompute()


def cranks(firing_order, interval):
    """Crank angles (deg, 0 to 360) of cylinders 1, 2, … along the shaft for a firing
    order such as "1-3-4-2" at ``interval`` degrees: the k-th cylinder to fire leads
    the first by k intervals."""
    order = [int(c) for c in firing_order.split("-")]
    angles = [0.0] * len(order)
    for k, cylinder in enumerate(order):
        angles[cylinder - 1] = (-k * interval) % 360.0
    return angles


@lru_cache(maxsize=None)
def table_fit(document, table, column, parameter=None):
    """The value a printed column follows (of ``parameter``, where its fit has
    several), from its table's fit row (a derived value that shows the column's
    pattern uses it, so the two always say the same)."""
    fit_key = f"{table}_fit"
    for claim in load(document).claims:
        if claim.key == fit_key:
            for fit in claim.fits:
                if fit.column == column:
                    result = fit.result()
                    if parameter is None:
                        return result["fitted"]
                    if parameter in result["values"]:
                        return result["values"][parameter]
                    raise ValueError(f"{document}: the fit of column {column!r} has no "
                                     f"parameter {parameter!r}")
    raise ValueError(f"{document}: table {table!r} has no fit of column {column!r}")


def moment_sum(angles, order):
    """|Σ zᵢ·exp(j·order·θᵢ)| of cranks at ``angles`` (deg) at equal pitch, zᵢ measured
    from the shaft's middle: an order's unbalanced moment in units of the pitch times
    one cylinder's force of that order."""
    middle = (len(angles) - 1) / 2
    return abs(sum((i - middle) * np.exp(1j * order * np.radians(a))
                   for i, a in enumerate(angles)))


HELPERS = {
    "__builtins__": {}, "abs": abs, "min": min, "max": max, "round": round, "sum": sum,
    "float": float, "enumerate": enumerate, "len": len,
    "pi": math.pi, "sqrt": math.sqrt, "sin": math.sin, "cos": math.cos, "tan": math.tan,
    "asin": math.asin, "acos": math.acos, "atan": math.atan, "radians": math.radians,
    "degrees": math.degrees, "log10": math.log10, "exp": math.exp,
    "np": np, "kinematics": kinematics, "forces": forces, "mechanism": mechanism,
    "optimization": optimization, "cycle": cycle, "multicylinder": multicylinder,
    "gears": gears, "cam": cam, "compressor": compressor, "crankshaft": crankshaft,
    "workbook": workbook, "parameter": parameter, "cranks": cranks, "moment_sum": moment_sum,
    "table_fit": table_fit,
    "claim_value": lambda document, key: claim_value(document, key),
}


class Names(dict):
    """What an expression of a claim or a fit can name: the inputs, and the names its
    table's ``let`` defines (expressions over the inputs, the row input, the helpers
    and each other), each computed on first use — lazily, so that a fit's own
    expression may sit beside names that use its result."""

    def __init__(self, values, let=None, helpers=None):
        super().__init__(values)
        self.let, self.helpers = let or {}, helpers or HELPERS

    def __missing__(self, name):
        if name not in self.let:
            raise KeyError(name)
        self[name] = value = eval(_compiled(self.let[name]), self.helpers,  # noqa: S307
                                  self)
        return value


@lru_cache(maxsize=None)
def _compiled(expression):
    return compile(expression, "<let>", "eval")


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
    tolerance: float | None = None     # absolute, in ``unit``; None: half a unit of the last
                                       # printed digit (a formula claim: agreement to rounding)
    tolerance_reason: str = ""         # why a wider tolerance (a graphical method, rounded
                                       # inputs); required with ``tolerance``
    note: str = ""
    quote: str = ""                    # verbatim from the document: a substring of ``line``
    offset: int | None = None          # where the quote starts in that line (0-based)
    rounded: dict = field(default_factory=dict)   # inputs the document prints rounded:
                                       # name -> half a unit of their last printed digit
    fits: list = field(default_factory=list)      # a table's fit row: [TableFit, ...]
    let: dict = field(default_factory=dict)        # a table's named expressions (Names)
    group: str = ""                    # a printed table: its entries share a root cause

    def texts(self):
        """The claim's own words — note, model, missing, the derived value's meaning —
        as templates: every number in them is a placeholder (see :func:`render`)."""
        return {"note": self.note, "model": self.model, "missing": self.missing,
                "derived_what": (self.derived or {}).get("what", ""),
                "tolerance_reason": self.tolerance_reason}

    def values(self, recomputed=None, derived=None):
        """What a text's placeholders can name: the inputs, the printed, recomputed and
        derived values, the deviation and the tolerance, the lines."""
        compared = self.compared()
        out = dict(self.inputs, reported=compared, recomputed=recomputed, derived=derived,
                   line=self.line, other_line=self.other_line)
        if compared is not None and recomputed is not None:
            out["deviation"] = compared - recomputed
            out["deviation_percent"] = deviation_percent(compared, recomputed)
            tolerance = self.tolerance_used(recomputed)[0]
            out["tolerance"] = tolerance
            decimals = self.printed_decimals()
            out["units_of_last_digit"] = (compared - recomputed) * 10.0 ** decimals \
                if decimals is not None else None
        return out

    def render(self, text, recomputed=None, derived=None):
        """``text`` with its placeholders filled: {name} or {name:format} of
        :meth:`values`, {=expression} or {=expression:format} evaluated like ``python``."""
        if not text:
            return text
        names = Names(self.values(recomputed, derived), self.let)

        def fill(match):
            computed, body, fmt = match.group(1), match.group(2), match.group(3)
            value = eval(body, HELPERS, names) if computed \
                else names[body]  # noqa: S307 (our data)
            return shown(value, fmt)
        return PLACEHOLDER.sub(fill, text)

    def recompute(self, inputs=None):
        """The recomputed value in the document's unit, or None (unverifiable)."""
        if self.kind == "unverifiable" or self.python is None:
            return None
        return float(eval(self.python, HELPERS,  # noqa: S307 (our data)
                          Names(inputs or self.inputs, self.let)))

    def derived_value(self, inputs=None):
        if self.fits:
            return self.fits[0].result()["fitted"]
        if not self.derived:
            return None
        return float(eval(self.derived["python"], HELPERS,  # noqa: S307 (our data)
                          Names(inputs or self.inputs, self.let)))

    def rounding_effect(self):
        """How far the rounding of the printed inputs in ``rounded`` can move the
        comparison (recomputation and, for a claim on a formula, the derived value):
        the sum over those inputs of the larger change when one moves by its half
        unit."""
        if not self.rounded:
            return 0.0
        base_rec, base_der = self.recompute(), self.derived_value()
        uses_derived = self.reported is None and self.printed is None
        total = 0.0
        for name, half in self.rounded.items():
            if name not in self.inputs:
                raise ValueError(f"claim {self.key!r}: rounded input {name!r} is not an input")
            change = 0.0
            for sign in (1, -1):
                moved = dict(self.inputs, **{name: self.inputs[name] + sign * half})
                step = abs(self.recompute(moved) - base_rec) if base_rec is not None else 0.0
                if uses_derived and base_der is not None:
                    step += abs(self.derived_value(moved) - base_der)
                change = max(change, step)
            total += change
        return total

    def compared(self):
        """What the recomputation is compared with: the printed number (a printed
        fraction exactly), or for a claim on a printed formula or statement its derived
        value."""
        if self.printed is not None and "/" in self.printed:
            return printed_value(self.printed)
        if self.reported is not None:
            return self.reported
        return self.derived_value() if self.kind != "unverifiable" else None

    def printed_decimals(self):
        """Decimal places the document prints the number with, or None (a fraction, a
        statement, a formula)."""
        text = self.printed if self.printed is not None else \
            (None if self.reported is None else _shortest(self.reported))
        if text is None or "/" in text:
            return None
        mantissa = normalise(text).lower().partition("e")[0]
        return len(mantissa.partition(".")[2])

    def tolerance_used(self, recomputed=None):
        """(absolute tolerance in the claim's unit, why): the claim's own, else half a
        unit of the last printed digit, else (a formula or a fraction) agreement to
        rounding."""
        if self.tolerance is not None:
            return self.tolerance, self.tolerance_reason
        if self.fits:
            fit = self.fits[0]
            return fit.result()["uncertainty"], (
                f"the change of {fit.whats[0]} that moves the printed {fit.column} column by half a "
                f"unit of its last digit (rms): a fit cannot tell values closer than that")
        if self.kind == "rule":
            # inside the rule to rounding: a value on its bound computed twice (Python's
            # derived value, Excel's live clamp) is inside, whatever the last bit
            scale = abs(recomputed) if recomputed is not None else abs(self.compared() or 0.0)
            return FORMULA_AGREEMENT * scale + NOISE_FLOOR, RULE
        decimals = self.printed_decimals()
        if decimals is not None and self.reported is not None:
            base, reason = 0.5 * 10.0 ** -decimals, HALF_UNIT
        else:
            scale = abs(recomputed) if recomputed is not None else abs(self.compared() or 0.0)
            base, reason = FORMULA_AGREEMENT * scale + NOISE_FLOOR, AGREEMENT
        effect = self.rounding_effect()
        if effect:
            names = ", ".join(f"{name} (±{shown(half)})" for name, half in self.rounded.items())
            reason += (f", plus {shown(effect, '.2g')} {self.unit} from the rounding of the "
                       f"printed {names}")
        return base + effect, reason

    def within(self, recomputed):
        limit, _ = self.tolerance_used(recomputed)
        return abs(self.compared() - recomputed) <= limit * (1 + 1e-12)

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


def deviation_percent(compared, recomputed):
    """(compared − recomputed)/recomputed in %, or None where the recomputation is 0 to
    rounding (a percentage of floating-point noise means nothing)."""
    if abs(recomputed) <= FORMULA_AGREEMENT * abs(compared) + NOISE_FLOOR:
        return None
    return (compared - recomputed) / recomputed * 100


NUMPY_HELPERS = {**HELPERS, "sin": np.sin, "cos": np.cos, "tan": np.tan, "asin": np.arcsin,
                 "acos": np.arccos, "atan": np.arctan, "radians": np.radians,
                 "degrees": np.degrees, "sqrt": np.sqrt, "exp": np.exp, "abs": np.abs}
FIT_FIELDS = {"column", "parameter", "python", "stated", "what", "range", "unit"}


@dataclass
class TableFit:
    """Which values of its inputs a printed column follows: the least-squares fit of
    ``python`` (the column as a function of ``parameter``, the table's inputs and its
    row input) to the printed entries, each weighted by its last printed digit,
    searched over ``range``; ``stated`` is what the document's own inputs give.

    ``parameter`` is one name or a list of names (then ``what``, ``stated``, ``range``
    and ``unit`` are lists of the same length): several parameters are fitted
    together — a grid search on each in turn from the stated values, then
    Gauss–Newton steps on all of them — because a column that scales with one input
    and bends with another (v with ω1 and λ) fits neither alone."""
    column: str
    parameter: str | list
    python: str
    stated: str | list
    what: str | list
    range: list
    unit: str | list = "-"
    rows: list = field(default_factory=list)         # the row input's values
    row: str = ""                                     # the row input's name
    printed: list = field(default_factory=list)      # the column's printed texts
    inputs: dict = field(default_factory=dict)       # the table's inputs
    let: dict = field(default_factory=dict)          # the table's named expressions

    def __post_init__(self):
        many = isinstance(self.parameter, list)
        self.names = list(self.parameter) if many else [self.parameter]
        self.whats = list(self.what) if many else [self.what]
        self.stateds = list(self.stated) if many else [self.stated]
        self.ranges = [list(map(float, r)) for r in self.range] if many else \
            [list(map(float, self.range))]
        self.units = (list(self.unit) if isinstance(self.unit, list)
                      else [self.unit] * len(self.names))
        lengths = {len(x) for x in (self.names, self.whats, self.stateds, self.ranges,
                                    self.units)}
        if lengths != {len(self.names)} or any(len(r) != 2 for r in self.ranges):
            raise ValueError(f"fit of column {self.column!r}: parameter, what, stated, "
                             f"range (a [low, high] each) and unit must match in length")
        self.code = compile(self.python, f"<fit of {self.column}>", "eval")

    def column_for(self, point):
        """The column for the parameters ``point`` (one value each, or one a column
        of trial values: then one row per trial)."""
        names = Names(dict(self.inputs, **{self.row: np.asarray(self.rows, float)},
                           **dict(zip(self.names, point))),
                      self.let, NUMPY_HELPERS)
        return np.asarray(eval(self.code, NUMPY_HELPERS, names), float)  # noqa: S307

    @lru_cache(maxsize=None)
    def result(self):
        """{fitted, stated, uncertainty} of the first parameter, {values, stated_values,
        uncertainties} of all by name, and rms (in units of the last printed digit) at
        the fit and at the stated values."""
        values = np.array([printed_value(t) for t in self.printed])
        digit = np.array([10.0 ** -_decimals(t) for t in self.printed])

        def misfit(point):
            return float(np.sqrt(np.mean(((self.column_for(point) - values) / digit) ** 2)))

        stated = np.array([float(eval(text, HELPERS, dict(self.inputs)))  # noqa: S307
                           for text in self.stateds])
        point = np.clip(stated, *np.array(self.ranges).T)
        for i, (low, high) in enumerate(self.ranges):
            point[i] = self._line_search(misfit, point, i, low, high, values, digit)
        if len(point) > 1:
            point = self._gauss_newton(values, digit, point, misfit)
        slopes = self._slopes(point)
        # the change of each parameter that moves the column by half a unit of its last
        # digit (rms): a fit cannot tell values closer than that
        uncertainty = [1.0 / s if s else math.inf for s in
                       (float(np.sqrt(np.mean((slope / (digit / 2)) ** 2))) for slope in slopes)]
        return {"fitted": float(point[0]), "stated": float(stated[0]),
                "values": dict(zip(self.names, map(float, point))),
                "stated_values": dict(zip(self.names, map(float, stated))),
                "rms": misfit(point), "rms_stated": misfit(stated),
                "uncertainty": uncertainty[0],
                "uncertainties": dict(zip(self.names, uncertainty))}

    __hash__ = object.__hash__

    def _line_search(self, misfit, point, i, low, high, values, digit):
        """The best value of parameter i, the others held: a grid (evaluated at once,
        one row per trial value), then golden section on the grid step around its
        best."""
        def at(value):
            return misfit(np.concatenate([point[:i], [value], point[i + 1:]]))
        grid = np.linspace(low, high, 2001)
        trial = [grid[:, None] if j == i else p for j, p in enumerate(point)]
        columns = np.broadcast_to(self.column_for(trial), (grid.size, values.size))
        best = grid[int(np.argmin(np.sqrt(np.mean(((columns - values) / digit) ** 2,
                                                  axis=1))))]
        step = (high - low) / 2000
        a, b = max(low, best - step), min(high, best + step)
        ratio = (math.sqrt(5) - 1) / 2
        for _ in range(80):
            c, d = b - ratio * (b - a), a + ratio * (b - a)
            a, b = (a, d) if at(c) < at(d) else (c, b)
        return (a + b) / 2

    def _slopes(self, point):
        out = []
        for i in range(len(point)):
            delta = 1e-6 * max(abs(point[i]), 1.0)
            up, down = point.copy(), point.copy()
            up[i] += delta
            down[i] -= delta
            out.append((self.column_for(up) - self.column_for(down)) / (2 * delta))
        return out

    def _gauss_newton(self, values, digit, point, misfit):
        """Joint refinement of several parameters (weighted least squares), kept in
        their ranges; a step that lowers the misfit by no halving ends it."""
        low, high = np.array(self.ranges).T
        for _ in range(50):
            residual = (self.column_for(point) - values) / digit
            jacobian = np.array(self._slopes(point)).T / digit[:, None]
            step = np.linalg.lstsq(jacobian, -residual, rcond=None)[0]
            for _ in range(30):                      # halve a step that overshoots
                trial = np.clip(point + step, low, high)
                if misfit(trial) < misfit(point):
                    break
                step = step / 2
            else:
                return point
            point = trial
        return point

    def sentence(self):
        r = self.result()
        fitted = " and ".join(f"{what} = {shown(r['values'][name], '.4g')} "
                              f"(± {shown(r['uncertainties'][name], '.2g')})"
                              for what, name in zip(self.whats, self.names))
        stated = " and ".join(shown(r["stated_values"][name], ".4g") for name in self.names)
        values = "value" if len(self.names) == 1 else "values"
        return (f"the {self.column} column follows {fitted} (the document's own inputs "
                f"give {stated}), with an rms residual of {shown(r['rms'], '.2g')} units of "
                f"its last printed digit ({shown(r['rms_stated'], '.3g')} with the stated "
                f"{values})")


def _decimals(text):
    mantissa = normalise(str(text)).lower().partition("e")[0]
    return len(mantissa.partition(".")[2])


@dataclass
class Document:
    key: str
    file: str
    title: str
    claims: list
    omitted: list = field(default_factory=list)    # [{section, what, why}]: coverage
    audited: list = field(default_factory=list)    # [[first, last], ...]: audited lines
    row_labels: list = field(default_factory=list)  # [(line, offset, text)] of tables' rows
    caveat: str = ""               # what every row's inputs are (illustrative values)

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
            words = {k: claim.render(v, recomputed, derived) for k, v in claim.texts().items()}
            if claim.fits:
                text = "; ".join(fit.sentence() for fit in claim.fits)
                words["note"] = text[0].upper() + text[1:] + "."
            status = claim.status(recomputed)
            compared = claim.compared()
            reported_display, recomputed_display = displays(claim, compared, recomputed, status)
            deviation = None if compared is None or recomputed is None else compared - recomputed
            deviation_pct = deviation_percent(claim.compared(), recomputed) \
                if deviation is not None else None
            tolerance = claim.tolerance_used(recomputed)[0]
            out.append({"document": self.key, "key": claim.key, "section": claim.section,
                        "line": claim.line, "claim": claim.claim,
                        "reported": claim.reported, "printed": claim.printed or "",
                        "unit": claim.unit, "kind": claim.kind,
                        "derived": derived, "derived_what": words["derived_what"],
                        "recomputed": recomputed, "status": status,
                        "margin_percent": claim.margin_percent(recomputed),
                        "tolerance": claim.tolerance_used(recomputed)[0],
                        "tolerance_reason": claim.render(claim.tolerance_used(recomputed)[1],
                                                         recomputed, derived),
                        "other": claim.other, "other_line": claim.other_line,
                        "model": words["model"], "missing": words["missing"],
                        "note": words["note"], "quote": claim.quote, "offset": claim.offset,
                        "reported_display": reported_display,
                        "recomputed_display": recomputed_display,
                        "deviation": deviation,
                        # relative to the value: −1.8 % is 1.8 % smaller in magnitude
                        "deviation_percent": deviation_pct,
                        "materiality": materiality(claim, status, deviation, deviation_pct,
                                                   tolerance),
                        "caveat": self.caveat,
                        "group": claim.group})
        return out


EXTRA_DIGITS = 2          # an ok row shows its recomputation this much finer than printed
MATERIALITY = {
    "rounding": "within one unit of the last printed digit beyond the tolerance: a "
                "rounding or transcription slip, nothing an engineer would act on",
    "minor": "less than 1 % from the recomputation",
    "material": "1 % or more from the recomputation",
}
MINOR_PERCENT = 1.0


def materiality(claim, status, deviation, deviation_pct, tolerance):
    """How much a finding that is not ok matters (MATERIALITY), or "" (ok, or nothing
    to measure: unverifiable)."""
    if status in ("ok", "unverifiable", "comparison") or deviation is None:
        return ""
    decimals = claim.printed_decimals()
    unit = 10.0 ** -decimals if decimals is not None else 0.0
    if abs(deviation) <= tolerance + unit:
        return "rounding"
    if deviation_pct is not None and abs(deviation_pct) < MINOR_PERCENT:
        return "minor"
    return "material"


def unit_of_last_digit(claim):
    """One unit of the last digit the document prints (0 where it prints no number)."""
    decimals = claim.printed_decimals()
    return 10.0 ** -decimals if decimals is not None else 0.0


def root_causes(findings):
    """Findings that are not ok, one per root cause: a printed table's entries with one
    verdict are one, with their count.  [(first finding, count)]."""
    groups = {}
    for f in findings:
        if f["status"] in ("ok", "comparison"):
            continue
        key = (f.get("group") or f["key"], f["status"])
        if key in groups:
            groups[key][1] += 1
        else:
            groups[key] = [f, 1]
    return [tuple(v) for v in groups.values()]


def displays(claim, compared, recomputed, status):
    """(reported, recomputed) as the audit shows them: the printed text as printed,
    the recomputation with two more decimals than the document prints (six
    significant digits where it prints a formula or a fraction) and, on a row that
    is not ok, as many more as it takes for the two to differ."""
    if claim.printed is not None:
        reported = claim.printed
    elif claim.reported is not None:
        reported = _shortest(claim.reported)
    else:
        reported = "—" if compared is None else shown(compared)
    if reported.startswith("-"):
        reported = "−" + reported[1:]            # the minus sign shown() writes
    if recomputed is None:
        return reported, "—"
    decimals = claim.printed_decimals()
    if decimals is None:
        magnitude = math.floor(math.log10(abs(recomputed))) if recomputed else 0
        decimals = max(5 - magnitude, 0)
    else:
        decimals += EXTRA_DIGITS
    if status not in ("ok", "unverifiable") and compared is not None:
        while decimals < 15 and round(compared, decimals) == round(recomputed, decimals):
            decimals += 1
    return reported, shown(recomputed, f".{min(decimals, 15)}f")


PLACEHOLDER = re.compile(r"\{(=?)([^{}:]+?)(?::([^{}:]+))?\}")


def shown(value, fmt=None):
    """A number in a text: with ``fmt`` (a format spec such as '.4f'); else as typed
    where it is short (an input: 175.9783), six significant digits where it is not (a
    computed value); a sign in the text's minus sign."""
    if value is None:
        return "—"
    if isinstance(value, str):
        return value
    if isinstance(value, (list, tuple, np.ndarray)):
        return "/".join(shown(float(v), fmt) for v in value)
    short = repr(float(value))
    if fmt:
        text = format(value, fmt)
    elif float(value).is_integer() and abs(value) < 1e15:
        text = str(int(value))
    elif "e" not in short and len(short.replace("-", "").replace(".", "").lstrip("0")) <= 10:
        text = short                 # a number as typed (an input): all its digits
    else:
        text = f"{value:.6g}"
    return "−" + text[1:] if text.startswith("-") else text


def _shortest(value):
    """A reported value as the shortest decimal text ('515', '0.11765')."""
    text = repr(float(value))
    return text[:-2] if text.endswith(".0") else text


NUMBER = re.compile(r"\d+(?:\.\d+)?")
# What a claim's own words may print as digits: references and names, never a value
# (values are placeholders).  A digit after a letter is a symbol's index (m1, Δy12).
REFERENCE = re.compile(
    r"§\s?[\d.]+|eqs?\.\s?[\d.]+(?:[–-][\d.]+)?|[Ss]eed \d+|[Tt]able \d+(?:\.\d+)?|"
    r"表\s?[\d.-]+|图\s?[\d.-]+|[Ff]ig(?:ure)?\.? ?\d+|附表\d|R0\d|[Cc]hapter \d+|"
    r"ch(?:apters?)?\.? \d+(?:[–-]\d+)?|\d(?:st|nd|rd|th)\b|lines? \d+(?:[–-]\d+)?|"
    r"\d(?:-\d){3,}|[A-Za-zΑ-Ωα-ωΔθψβλεσμτ′_*]\d+|第\d+页|p\. \d+|"
    r"gears? \d+(?: and \d+)?|[Ss]ections? \d+(?:\.\d+)*|[Ss]tages? \d|mesh \d[–-]\d")


FORMULA_SPAN = re.compile(r"`[^`]*`")


def typed_numbers(template):
    """Numbers a template prints literally (not a placeholder, not a reference): what
    the note-arithmetic test refuses."""
    literal = PLACEHOLDER.sub(" ", template or "")
    literal = FORMULA_SPAN.sub(" ", literal)           # `a formula`: its constants are not values
    literal = REFERENCE.sub(" ", literal)
    return NUMBER.findall(literal)
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
    if claim.quote and claim.offset is not None and \
            lines[claim.line - 1][claim.offset:claim.offset + len(claim.quote)] != claim.quote:
        return f"the quote {claim.quote!r} is not at offset {claim.offset} of line {claim.line}"
    if claim.other and claim.other_line and claim.other not in lines[claim.other_line - 1]:
        return f"the other statement {claim.other!r} is not at line {claim.other_line}"
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


TABLE_FIELDS = {"key", "section", "line", "claim", "row", "rows", "inputs", "column", "note",
                "fit", "row_offsets", "quote", "offset", "let"}
COLUMN_FIELDS = {"key", "label", "unit", "values", "python", "formula", "derived", "kind",
                 "tolerance", "tolerance_reason", "note", "model", "other", "other_line",
                 "quotes", "offsets"}


def _table_claims(name, table):
    """One claim per printed entry of a [[table]]: its rows set the input ``row``
    (e.g. the crank angle), each [[table.column]] gives the printed values (a
    number, or the printed text where the extraction runs it into its neighbour)
    and the recomputation of that column."""
    where = f"{name}: table {table.get('key', '?')!r}"
    unknown = set(table) - TABLE_FIELDS
    if unknown:
        raise ValueError(f"{where}: unknown field(s) {', '.join(sorted(unknown))}")
    out = _table_fit(name, table, where)
    for column in table["column"]:
        unknown = set(column) - COLUMN_FIELDS
        if unknown:
            raise ValueError(f"{where}: column {column.get('key')!r}: unknown field(s) "
                             f"{', '.join(sorted(unknown))}")
        if len(column["values"]) != len(table["rows"]):
            raise ValueError(f"{where}: column {column['key']!r} has {len(column['values'])} "
                             f"values for {len(table['rows'])} rows")
        offsets = column.get("offsets", [None] * len(table["rows"]))
        for row, value, offset in zip(table["rows"], column["values"], offsets):
            printed = value if isinstance(value, str) else None
            extra = {k: column[k] for k in ("formula", "derived", "model", "other",
                                            "other_line", "tolerance", "tolerance_reason")
                     if k in column}
            out.append(Claim(
                key=f"{table['key']}_{column['key']}_{row:g}", section=table["section"],
                line=table["line"],
                claim=table["claim"].format(label=column["label"], row=f"{row:g}"),
                unit=column["unit"], reported=printed_value(value) if printed else float(value),
                printed=printed, kind=column.get("kind", "value"),
                inputs={**table.get("inputs", {}), table["row"]: float(row)},
                let=dict(table.get("let", {})),
                python=column["python"], note=column.get("note", table.get("note", "")),
                quote=printed or "", offset=offset, group=table["key"],
                **extra))
    return out


def _table_fit(name, table, where):
    """The table's fit row (one finding above its entries) from its [[table.fit]]s."""
    if not table.get("fit"):
        return []
    columns = {c["key"]: c for c in table["column"]}
    fits = []
    for entry in table["fit"]:
        unknown = set(entry) - FIT_FIELDS
        if unknown:
            raise ValueError(f"{where}: fit: unknown field(s) {', '.join(sorted(unknown))}")
        if entry.get("column") not in columns:
            raise ValueError(f"{where}: fit names no column of the table: {entry.get('column')!r}")
        column = columns[entry["column"]]
        try:
            fits.append(TableFit(**entry, rows=list(table["rows"]), row=table["row"],
                                 printed=[v if isinstance(v, str) else repr(float(v))
                                          for v in column["values"]],
                                 inputs=dict(table.get("inputs", {})),
                                 let=dict(table.get("let", {}))))
        except (TypeError, ValueError) as error:
            raise ValueError(f"{where}: {error}") from None
    head = fits[0]
    return [Claim(key=f"{table['key']}_fit", section=table["section"], line=table["line"],
                  quote=table.get("quote", ""), offset=table.get("offset"),
                  claim=f"the printed table as a whole: {head.whats[0]} its columns follow",
                  unit=head.units[0], kind="value", inputs=dict(table.get("inputs", {})),
                  let=dict(table.get("let", {})),
                  python=head.stateds[0], fits=fits,
                  derived={"what": f"{head.whats[0]} the printed {head.column} column "
                                   f"follows (least squares)", "python": "0",
                           "unit": head.units[0]})]


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
    for entry in data.get("omitted", []):
        unknown = set(entry) - OMITTED_FIELDS
        if unknown or not {"section", "what", "why"} <= set(entry):
            raise ValueError(f"{name}: omitted {entry.get('what', '?')!r} needs section, what, "
                             f"why (and may have line with quote, or lines)")
    row_labels = [(table["line"], offset, f"{row:g}") for table in data.get("table", [])
                  for row, offset in zip(table["rows"], table.get("row_offsets", []))]
    return Document(key=head["key"], file=head["file"], title=head["title"], claims=claims,
                    caveat=head.get("caveat", ""),
                    omitted=data.get("omitted", []), audited=head.get("audited", []),
                    row_labels=row_labels)


# ------------------------------------------------------------------ coverage
OMITTED_FIELDS = {"section", "what", "why", "line", "quote", "span", "lines"}
ROW_LABEL = "a printed table's row label: the input of the entries beside it"
TOKEN = re.compile(r"\d+(?:\.\d+)*")        # a numeric token of a seed line ("3.1.2" is one)
# Numbers that are never claims, told apart by their form (the reason is the name).
NUMBERING = {
    "a heading's number": re.compile(
        r"^\s*\d+(?:\.\d+)*(?=\s?[\u4e00-\u9fff])|\d+(?:\.\d+){2,}(?=\s?[\u4e00-\u9fff])"),
    "a list item's number": re.compile(r"(?<![\d.])\d{1,2}(?=\s?[)）、])|[(（]\d{1,2}[)）]"),
    "a figure, table or equation number": re.compile(
        r"[图表式圖]\s?\d+(?:[.\-－]\d+)*|[(（]\d+[.\-－]\d+[)）]"),
    "a symbol's index or exponent (m1, v², D2)": re.compile(
        r"(?<=[A-Za-zα-ωΔ])\s?\d{1,2}(?![\d.])|<su[bp]>\d+</su[bp]>|[_^]\{?\d+"),
    "a constant of a printed formula (a formula, not a value)": re.compile(r"^\$\$.*\$\$$"),
}


def _spans(line_text, pattern):
    return [m.span() for m in pattern.finditer(line_text)]


def coverage(document, lines):
    """The numbers of the document's audited lines (``[document] audited``) and what
    became of each: inside a claim's quote (claimed), or left out — by its form
    (NUMBERING) or by an [[omitted]] entry with ``line`` and ``quote`` (or ``lines``)
    — with the reason; ``unaccounted`` lists the rest (a test requires it empty)."""
    claimed_at, omitted_at = {}, {}
    for claim in document.claims:
        if claim.quote and claim.offset is not None:
            claimed_at.setdefault(claim.line, []).append(
                (claim.offset, claim.offset + len(claim.quote)))
        if claim.other and claim.other_line and claim.other_line <= len(lines):
            at = lines[claim.other_line - 1].find(claim.other)
            if at >= 0:
                claimed_at.setdefault(claim.other_line, []).append((at, at + len(claim.other)))
    for line, offset, text in document.row_labels:
        omitted_at.setdefault(line, []).append(((offset, offset + len(text)), ROW_LABEL))
    for entry in document.omitted:
        if "lines" in entry:
            first, last = entry["lines"]
            for number in range(first, last + 1):
                omitted_at.setdefault(number, []).append(((0, 10 ** 9), entry["why"]))
        elif "span" in entry:                  # characters [start, end) of one line
            omitted_at.setdefault(entry["line"], []).append((tuple(entry["span"]), entry["why"]))
        elif "line" in entry:
            text = lines[entry["line"] - 1] if entry["line"] <= len(lines) else ""
            start = 0
            while (at := text.find(entry["quote"], start)) >= 0:     # every occurrence
                omitted_at.setdefault(entry["line"], []).append(
                    ((at, at + len(entry["quote"])), entry["why"]))
                start = at + 1
    numbers = claimed = 0
    left_out, unaccounted = [], []
    for first, last in document.audited:
        for number in range(first, min(last, len(lines)) + 1):
            raw = lines[number - 1]
            text = raw.translate(FULL_WIDTH)           # same length: offsets hold
            forms = [(span, why) for why, pattern in NUMBERING.items()
                     for span in _spans(text, pattern)]
            for token in TOKEN.finditer(text):
                numbers += 1
                start, end = token.span()
                inside = [why for (a, b), why in
                          [(span, None) for span in claimed_at.get(number, [])]
                          + omitted_at.get(number, []) + forms
                          if a < end and start < b]
                if inside and inside[0] is None:
                    claimed += 1
                elif inside:
                    left_out.append({"line": number, "offset": start, "number": token.group(),
                                     "reason": inside[0]})
                else:
                    unaccounted.append({"line": number, "offset": start,
                                        "number": token.group(),
                                        "context": raw[max(0, start - 20):end + 20]})
    return {"audited": [list(r) for r in document.audited], "numbers": numbers,
            "claimed": claimed, "left_out": len(left_out), "left_out_numbers": left_out,
            "unaccounted": unaccounted}
