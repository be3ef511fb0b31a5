"""Refuse a specification that cannot mean anything, naming its file and key.

A spec author's mistakes (an unknown reference, a calc function that does not
exist, a function Excel 2010 lacks, a rule that depends on what it guards, …)
raise SpecError when the template is loaded, never later in a user's build.
"""
import inspect
import re

from crankbook.spec import placeholders

from crankbook.spec import units
from crankbook.spec.excel_traps import unary_minus_power
from crankbook.errors import SpecError
from crankbook.spec.placeholders import Ref, Special, Sum, TemplateSyntaxError

# Functions newer than Excel 2010 or volatile: a workbook must open in Excel 2010,
# LibreOffice, Gnumeric and WPS and recompute the same everywhere.
FORBIDDEN = re.compile(r"\b(FILTER|SORT|SORTBY|UNIQUE|XLOOKUP|XMATCH|LET|LAMBDA|SEQUENCE|"
                       r"IFS|SWITCH|CONCAT|TEXTJOIN|MAXIFS|MINIFS|RANDARRAY|OFFSET|INDIRECT|"
                       r"NOW|TODAY|RAND|RANDBETWEEN|CELL|INFO)\s*\(")


def check(spec):
    """Raise SpecError for the first thing in ``spec`` that cannot be meant."""
    _unique_keys(spec)
    known = set(spec.parameter) | set(spec.table_column) | set(spec.quantity) | \
        set(spec.constant)
    homes = {s.grid for s in spec.sheets if s.kind == "series"}
    for sheet in spec.sheets:
        stray = set(sheet.report or ()) - {q.key for q in sheet.columns}
        if stray:
            raise SpecError(spec.file, sheet.key, f"report names no column of the sheet: "
                                                  f"{', '.join(sorted(stray))}")
    for g in spec.grids:
        if g.key not in homes:
            raise SpecError(g.source, g.key, "grid is on no sheet")
    for p in spec.parameters:
        if p.axis and p.axis not in spec.axis:
            raise SpecError(spec.file, p.key, f"unknown axis {p.axis!r}")
        if p.axis and not isinstance(p.default, list):
            raise SpecError(spec.file, p.key, "a per-item parameter's default is a list")
        if not units.known(p.unit):
            raise SpecError(spec.file, p.key, f"unit {p.unit!r} is not in units.toml")
        if p.kind == "choice" and not p.choices:
            raise SpecError(spec.file, p.key, "a choice parameter needs 'choices'")
    for a in spec.axes:
        if a.product:
            if len(a.product) != 2 or any(c not in spec.axis or spec.axis[c].product
                                          for c in a.product):
                raise SpecError(spec.file, a.key, "a product axis names two plain axes")
            continue
        if a.aligned is not None and (a.aligned not in spec.axis or a.aligned == a.key):
            raise SpecError(spec.file, a.key, f"aligned to unknown axis {a.aligned!r}")
        for key in a.live_keys:
            held = spec.quantity.get(key)
            if held is None or held.is_series or held.items or not held.discrete:
                raise SpecError(spec.file, a.key, f"an item's name holds {{{key}}}: it must "
                                "be a result of one whole number (a discrete scalar)")
        if a.size_calc is None and not spec.item_parameters(a.key):
            raise SpecError(spec.file, a.key, "an axis needs per-item parameters or a size_calc")
    for column in spec.table_column.values():
        if column.items and column.items not in spec.axis:
            raise SpecError(spec.file, column.key, f"unknown axis {column.items!r}")
    for q in spec.quantities():
        _check_quantity(spec, q, known)
    for s in spec.sheets:
        for chart in s.charts:
            if chart.x_each and len(chart.x_each) != len(chart.y):
                raise SpecError(spec.file, s.key, "x_each needs one x per y")
            if chart.emphasis is not None:
                first = spec.quantity.get(chart.y[0])
                marked = spec.quantity.get(chart.emphasis)
                if marked is None or first is None or not first.items or \
                        marked.items != first.items or marked.is_series:
                    raise SpecError(spec.file, s.key, f"chart: emphasis {chart.emphasis!r} "
                                    f"must be one value per item of {chart.y[0]!r}'s axis")
            if set(chart.heavy) - set(chart.y):
                raise SpecError(spec.file, s.key, "chart: heavy names a key the chart does "
                                "not draw")
            for key in chart.y + ((chart.x,) if chart.x else ()) + chart.x_each:
                q = spec.quantity.get(key)
                if q is None and key in spec.parameter:     # an items sheet's own input
                    q = spec.parameter[key]
                    on_items = s.kind == "items" and q.axis == s.axis
                    q = q if on_items else None
                else:
                    on_items = s.kind == "items" and q is not None and q.items == s.axis
                if q is None or not (on_items or q.is_series):
                    raise SpecError(spec.file, s.key, f"chart lists {key!r}, not a series "
                                    f"(or, on an items sheet, a value per item)")
            if chart.x is None and any(spec.quantity[k].grid != s.grid for k in chart.y
                                       if k in spec.quantity):
                raise SpecError(spec.file, s.key, "a chart over the sheet's grid lists a series "
                                                  "of another grid")
        if s.kind == "items" and s.axis not in spec.axis:
            raise SpecError(spec.file, s.key, f"items sheet of unknown axis {s.axis!r}")
    _rules_are_unguarded(spec)


def _unique_keys(spec):
    seen = set()
    keys = [p.key for p in spec.parameters] + list(spec.table_column) + \
        [c.key for c in spec.constants] + [q.key for q in spec.quantities()]
    for key in keys:
        if key in seen:
            raise SpecError(spec.file, key, "defined twice")
        seen.add(key)


def _check_quantity(spec, q, known):
    where = q.source or spec.file
    if not units.known(q.unit):
        raise SpecError(where, q.key, f"unit {q.unit!r} is not in units.toml")
    if q.items and q.items not in spec.axis:
        raise SpecError(where, q.key, f"unknown axis {q.items!r}")
    if isinstance(q.target, str) and q.target not in known:
        raise SpecError(where, q.key, f"target {q.target!r} is not a key of this workbook")
    if q.is_numeric_grid:
        return
    for text in (q.formula, q.first):
        if text is None:
            continue
        bad = FORBIDDEN.search(text)
        if bad:
            raise SpecError(where, q.key, f"uses {bad.group(1)}, which Excel 2010 lacks or "
                                          f"which is volatile")
        trap = unary_minus_power(text)
        if trap:
            raise SpecError(where, q.key, f"writes a unary minus before '^' ({trap!r}): a "
                                          f"spreadsheet squares the minus too; write -(x^2)")
        try:
            nodes = placeholders.parse(text)
        except TemplateSyntaxError as error:
            raise SpecError(where, q.key, str(error)) from None
        _check_nodes(spec, q, nodes, known, where, sums=())
    if q.formula is None and q.kind not in ("scalar",):
        raise SpecError(where, q.key, "needs a formula")
    if q.calc is None:
        raise SpecError(where, q.key, "needs a calc function (one source of truth: the "
                                      "formula and the calc function side by side)")
    try:
        arguments = q.calc_arguments()
    except (ImportError, AttributeError):
        raise SpecError(where, q.key, f"calc {q.calc!r} is not a function of "
                                      f"crankbook.calc") from None
    for name, source in arguments.items():
        default = inspect.signature(q.calc_function()).parameters[name].default
        if source not in known and default is inspect.Parameter.empty:
            raise SpecError(where, q.key, f"calc {q.calc} argument {name!r} maps to unknown "
                                          f"{source!r}")


def _check_nodes(spec, q, nodes, known, where, sums):
    for node in nodes:
        if isinstance(node, Special):
            if node.name == "item" and not q.items:
                raise SpecError(where, q.key, "{item} outside a per-item quantity")
            if node.axis and node.axis not in spec.components(q.items):
                raise SpecError(where, q.key, f"{{item:{node.axis}}}: {node.axis!r} is not "
                                              f"an axis of {q.items!r}")
            if node.name == "index" and not sums:
                raise SpecError(where, q.key, "{index} outside {sum:…}")
        elif isinstance(node, Sum):
            if node.axis not in spec.axis:
                raise SpecError(where, q.key, f"{{sum:{node.axis}…}}: unknown axis")
            _check_nodes(spec, q, node.body, known, where, sums + (node.axis,))
        elif isinstance(node, Ref):
            if node.key not in known:
                raise SpecError(where, q.key, f"refers to unknown {node.key!r}")
            if node.unit:
                source = spec.unit_of(node.key)
                if not units.known(node.unit) or not units.convertible(source, node.unit):
                    raise SpecError(where, q.key, f"{{{node.key}|{node.unit}}}: cannot convert "
                                                  f"{source} to {node.unit}")
            if node.part == "at":
                target = spec.quantity.get(node.key)
                grid = spec.quantity.get(target.grid) if target and target.is_series else None
                if grid is None or grid.period is None:
                    raise SpecError(where, q.key, f"{{{node.key}:at(…)}} needs a series on a "
                                                  f"periodic grid")
            if node.part == "rows":
                target = spec.quantity.get(node.key)
                if target is None or not target.is_series:
                    raise SpecError(where, q.key, f"{{{node.key}:rows}} needs a grid or a "
                                                  f"series on one")
            if node.part in ("items", "item"):
                owner = spec.parameter.get(node.key) or spec.quantity.get(node.key)
                axis = getattr(owner, "axis", None) if node.key in spec.parameter \
                    else getattr(owner, "items", None)
                if not axis:
                    raise SpecError(where, q.key, f"{{{node.key}:{node.part}}} needs a "
                                                  f"per-item quantity")
            if node.argument:
                _check_nodes(spec, q, node.argument, known, where, sums)


def _rules_are_unguarded(spec):
    """A rule decides q_inputs_valid, so it may not depend on a guarded quantity
    (that would be a circular reference in the workbook)."""
    def guarded_dependency(key, seen):
        q = spec.quantity.get(key)
        if q is None or key in seen or q.is_grid:
            return None
        if q.guard:
            return key
        seen.add(key)
        for ref in q.references():
            found = guarded_dependency(ref, seen)
            if found:
                return found
        return None
    for rule in spec.rules:
        for ref in rule.references():
            found = guarded_dependency(ref, set())
            if found:
                raise SpecError(rule.source, rule.key,
                                f"depends on {found!r}, which is guarded by the rules "
                                f"themselves; mark it guard = false")
