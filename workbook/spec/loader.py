"""Read templates/<name>.toml (with its included libraries) into a WorkbookSpec.

Column sets are placed here: a member's key gets the placement's prefix (or its
rename), ``crank_angle`` stands for the grid it is placed on, each alias for the
key it names, and a reference to any member placed with the same prefix is that
placed member.  Every mistake raises SpecError naming the file and the key.
"""
from functools import lru_cache

from crankbook.spec import placeholders
from crankbook.spec.repeat import expanded

from crankbook.support import resources
from crankbook.errors import SpecError, UnknownPresetError
from crankbook.spec.model import (EACH, EXTREME_TOLERANCE, Axis, Chart, Constant, InputColumn,
                                  InputTable, Parameter, Quantity, Sheet, WorkbookSpec)
from crankbook.spec.check import check

LIST_SECTIONS = ("parameter", "axis", "constant", "input_table", "rule", "rulebook", "scalar",
                 "grid", "sheet", "columnset", "result", "use")
COMMON = "common"


def template_names():
    """Names of the workbook templates (not libraries, not data folders)."""
    return [n for n in resources.names() if n != "units"]


def _read(name, folder=None):
    parts = (folder, f"{name}.toml") if folder else (f"{name}.toml",)
    if not resources.is_safe_name(name) or not resources.exists(*parts):
        where = f"templates/{folder}" if folder else "templates"
        raise UnknownPresetError(f"workbook template {name!r} does not exist in {where}")
    return expanded(dict(resources.read_toml(*parts)), f"{folder}/{name}.toml" if folder
                    else f"{name}.toml")


def _merged(name):
    """The template's data with its libraries merged in (see :func:`_with_libraries`)."""
    file = f"{name}.toml"
    return _with_libraries(_read(name), file), file


def _with_libraries(data, file):
    """``data`` with the libraries of include = [...] merged in, each list entry
    remembering the file it comes from."""
    data = dict(data)
    own_defaults = data.pop("defaults", {})
    own_labels = data.pop("labels", {})
    _stamp(data, file)
    seen = set()
    queue = list(data.pop("include", []))
    while queue:
        library = queue.pop(0)
        if library in seen:
            continue
        seen.add(library)
        shared = _read(library, COMMON)
        queue += shared.pop("include", [])
        _stamp(shared, f"{COMMON}/{library}.toml")
        for key, value in shared.items():
            if isinstance(value, list):
                data[key] = data.get(key, []) + value
            elif isinstance(value, dict):
                data[key] = {**data.get(key, {}), **value}
    return _with_labels(_with_defaults(data, own_defaults, file), own_labels, file)


def _with_labels(data, labels, file):
    """The template's own [labels] (zh, en) for quantities its libraries define: a
    library's words suit the workbook it was first written for (the engine's mean
    torque is one cylinder's, the compressor's the shaft's)."""
    sections = ("result", "scalar", "columnset", "sheet")
    entries = {}
    for section in sections:
        for entry in data.get(section, []):
            for inner in entry.get("column", []) + entry.get("scalar", []) \
                    if section in ("columnset", "sheet") else [entry]:
                entries.setdefault(inner.get("key"), inner)
    for key, words in labels.items():
        if key not in entries:
            raise SpecError(file, key, "[labels] names a quantity no library defines")
        unknown = set(words) - {"zh", "en"}
        if unknown:
            raise SpecError(file, key, f"[labels] gives only zh and en, not "
                                       f"{', '.join(sorted(unknown))}")
        entries[key].update(words)
    return data


def _with_defaults(data, defaults, file):
    """The template's own [defaults] for parameters a library defines (a library's
    default suits the workbook it was first written for, not every one)."""
    known = {p["key"]: p for p in data.get("parameter", [])}
    for key, value in defaults.items():
        if key not in known:
            raise SpecError(file, key, "[defaults] names a parameter no library defines")
        known[key]["default"] = value
    return data


def _stamp(data, file):
    for section in LIST_SECTIONS:
        data[section] = [dict(entry, _file=file) for entry in data.get(section, [])]


def _need(entry, field, what):
    if field not in entry:
        raise SpecError(entry.get("_file", "?"), entry.get("key", what),
                        f"{what} needs '{field}'")
    return entry[field]


def _quantity(entry, kind, **extra):
    file = entry.get("_file", "?")
    for field in ("key", "unit", "zh", "en"):
        _need(entry, field, kind)
    known = {"key", "unit", "zh", "en", "formula", "calc", "args", "part", "summary", "format",
             "first",
             "guard", "array", "items", "_file", "_prefix", "names", "discrete", "must_pass",
             "item_word_zh", "item_word_en", "fold", "verdict", "target"}
    unknown = set(entry) - known
    if unknown:
        raise SpecError(file, entry["key"], f"unknown field(s) {', '.join(sorted(unknown))}")
    return Quantity(key=entry["key"], kind=kind, unit=entry["unit"], zh=entry["zh"],
                    en=entry["en"], formula=entry.get("formula"), calc=entry.get("calc"),
                    args=dict(entry.get("args", {})), part=entry.get("part"),
                    summary=entry.get("summary", False),
                    format=entry.get("format"), first=entry.get("first"),
                    guard=entry.get("guard", True), array=entry.get("array", False),
                    items=entry.get("items"), names=tuple(entry.get("names", ())),
                    item_word={lang: entry[f"item_word_{lang}"] for lang in ("zh", "en")
                               if f"item_word_{lang}" in entry},
                    discrete=entry.get("discrete", False),
                    must_pass=entry.get("must_pass", False),
                    fold=entry.get("fold", False),
                    verdict=entry.get("verdict", False),
                    target=entry.get("target"),
                    source=file, **extra)


def _grid(entry, period=None, step_option=None):
    start, stop = entry.get("start"), entry.get("stop")
    chart_range = tuple(entry.get("axis", (start, stop, 90.0)))
    return Quantity(key=entry["key"], kind="series", unit=entry.get("unit", "deg"),
                    zh=entry["zh"], en=entry["en"], formula=entry.get("formula"),
                    calc=entry.get("calc"), args=dict(entry.get("args", {})),
                    format=entry.get("format", "0.0"), grid=entry["key"], start=start,
                    stop=stop, step=entry.get("step"), rows=entry.get("rows"),
                    period=entry.get("period", period),
                    step_option=entry.get("step_option", step_option),
                    chart_range=chart_range, discrete=entry.get("discrete", False),
                    source=entry.get("_file", "?"))


def _parameter(entry):
    file = entry.get("_file", "?")
    known = {"key", "group", "unit", "zh", "en", "default", "kind", "min", "max", "min_open",
             "max_open", "choices", "axis", "fill", "_file"}
    unknown = set(entry) - known
    if unknown:
        raise SpecError(file, entry.get("key", "?"),
                        f"unknown field(s) {', '.join(sorted(unknown))}")
    for field in ("key", "group", "unit", "zh", "en", "default"):
        _need(entry, field, "parameter")
    if entry.get("fill") and (not entry.get("axis") or not isinstance(entry["default"], list)
                              or len(entry["default"]) != 1):
        raise SpecError(file, entry["key"], "fill = true needs an axis and a one-value default "
                                            "list (it fills every item)")
    values = {k: v for k, v in entry.items() if k != "_file"}
    if "choices" in values:
        values["choices"] = tuple(values["choices"])
    return Parameter(**values)


class _Placer:
    """Places column-set members (as series on a grid, or as scalars), remembering
    under each prefix which member became which key."""

    def __init__(self, columnsets, inputs):
        self.columnsets = columnsets
        self.inputs = inputs      # parameters, table columns, constants: never renamed
        self.placed = {}          # prefix -> {member key: placed key}
        self.pending = []         # (entry, prefix, aliases, grid)

    def place(self, use, grid, file):
        name = _need(dict(use, _file=file), "columnset", "use")
        if name not in self.columnsets:
            raise SpecError(file, name, f"unknown column set; sets are "
                                        f"{', '.join(sorted(self.columnsets))}")
        members = self.columnsets[name]
        by_key = {m["key"]: m for m in members}
        prefix = use.get("prefix", "")
        rename = use.get("rename", {})
        chosen = use.get("columns") or [m["key"] for m in members]
        entries = []
        for member_key in chosen:
            if member_key not in by_key:
                raise SpecError(file, member_key, f"not a member of column set {name!r}")
            member = dict(by_key[member_key])
            placed_key = rename.get(member_key, prefix + member_key)
            self.placed.setdefault(prefix, {})[member_key] = placed_key
            entry = dict(member, key=placed_key,
                         summary=member.get("summary", False) and use.get("summary", False))
            entry.update(use.get("labels", {}).get(member_key, {}))
            for field in ("format", "guard", "discrete"):
                if field in use:
                    entry[field] = use[field]
            if use.get("items"):
                entry["items"] = use["items"]
            self.pending.append((entry, prefix, dict(use.get("aliases", {})), grid))
            entries.append(entry)
        return entries

    def resolve(self):
        """Rewrite the references of every placed member (after all placements)."""
        for entry, prefix, aliases, grid in self.pending:
            def rename(key, prefix=prefix, aliases=aliases, grid=grid):
                if key in aliases:
                    return aliases[key]
                if key == "crank_angle" and grid:
                    return grid
                if key in self.inputs:
                    return key
                return self.placed.get(prefix, {}).get(key, key)
            entry["formula"] = placeholders.rename(entry.get("formula"), rename)
            entry["first"] = placeholders.rename(entry.get("first"), rename)
            if entry.get("calc"):
                entry["_rename"] = rename


def _resolve_args(entry):
    """Calc arguments of a placed member, mapped through its placement."""
    rename = entry.pop("_rename", None)
    if rename is None or not entry.get("calc"):
        return entry
    from crankbook.spec.model import calc_function
    import inspect
    try:
        names = inspect.signature(calc_function(entry["calc"])).parameters
    except (ImportError, AttributeError):
        raise SpecError(entry.get("_file", "?"), entry["key"],
                        f"calc {entry['calc']!r} is not a function of crankbook.calc") from None
    args = dict(entry.get("args", {}))
    entry["args"] = {name: rename(args.get(name, name)) for name in names}
    return entry


def _summary_quantities(grids, series):
    """Max/min of each summary series and the first grid angle where it comes within
    EXTREME_TOLERANCE of the peak |value| of its extreme."""
    out = []
    for q in series:
        grid = grids[q.grid]
        for stat, zh, en in (("max", "最大值", "maximum"), ("min", "最小值", "minimum")):
            out.append(Quantity(
                key=f"{q.key}_{stat}", kind="summary", unit=q.unit, zh=f"{q.zh} {zh}",
                en=f"{q.en} {en}", formula=f"{stat.upper()}({{{q.key}}})",
                calc=f"calc.cycle.{en}", args={"values": q.key}, source=q.source))
        peak = f"MAX({{{q.key}_max}},-{{{q.key}_min}})"
        for stat, zh, en, test in (("max", "最大值", "maximum", ">="), ("min", "最小值", "minimum", "<=")):
            sign = "-" if stat == "max" else "+"
            out.append(Quantity(
                key=f"{q.key}_{stat}_angle", kind="summary", unit=grid.unit,
                zh=f"{q.zh} {zh}处{grid.zh.split()[0]}", en=f"{grid.en.split(' (')[0]} of {q.en} {en}",
                formula=(f"INDEX({{{q.grid}}},MATCH(1,ISNUMBER({{{q.key}}})*({{{q.key}}}{test}"
                         f"{{{q.key}_{stat}}}{sign}{EXTREME_TOLERANCE!r}*{peak}),0))"),
                calc=f"calc.cycle.angle_of_{en}", args={"crank_angle": q.grid, "values": q.key},
                array=True, discrete=True, source=q.source))
    return out


def _in_group_order(parameters, groups):
    """The parameters, those of a group with an ``order`` list in that order (the rest
    of the group after them): a group's inputs come from several libraries, and a
    document lists them in its own order (the thesis's D1, L1, D2, L2, h, b)."""
    out = list(parameters)
    for name, entry in groups.items():
        order = entry.get("order") if isinstance(entry, dict) else None
        if not order:
            continue
        rank = {key: n for n, key in enumerate(order)}
        slots = [i for i, p in enumerate(out) if p.group == name]
        members = sorted((out[i] for i in slots), key=lambda p: rank.get(p.key, len(order)))
        for i, p in zip(slots, members):
            out[i] = p
    return out


def _chart_log(entry, sheet_entry, file):
    log = entry.get("log", False)
    if log not in (True, False, "y"):
        raise SpecError(file, sheet_entry["key"], f"chart: log must be true, false or \"y\" "
                                                  f"(not {log!r})")
    return log


def _chart(entry, sheet_entry, file):
    if isinstance(entry, (list, tuple)):
        entry = {"y": list(entry)}
    known = {"y", "x", "x_each", "title_zh", "title_en", "axis_zh", "axis_en", "unit", "x_axis_zh",
             "x_axis_en", "x_unit", "equal_axes", "type", "log", "curve_zh", "curve_en", "curves",
             "live_names", "emphasis", "heavy", "rows_from"}
    unknown = set(entry) - known
    if unknown:
        raise SpecError(file, sheet_entry["key"], f"chart: unknown field(s) "
                                                  f"{', '.join(sorted(unknown))}")
    curves = entry.get("curves")
    if curves is not None and (type(curves) is not int or curves < 1):
        raise SpecError(file, sheet_entry["key"], f"chart: curves must be a whole number "
                                                  f"of items, at least 1 (not {curves!r})")
    rows_from = entry.get("rows_from")
    if rows_from is not None and (not isinstance(rows_from, (int, float)) or
                                  isinstance(rows_from, bool)):
        raise SpecError(file, sheet_entry["key"], f"chart: rows_from must be a value of the "
                                                  f"sheet's grid (not {rows_from!r})")
    return Chart(y=tuple(entry["y"]), x=entry.get("x"), x_each=tuple(entry.get("x_each", ())),
                 title_zh=entry.get("title_zh", sheet_entry.get("title_zh", "")),
                 title_en=entry.get("title_en", sheet_entry.get("title_en", "")),
                 axis_zh=entry.get("axis_zh", sheet_entry.get("axis_zh", "")),
                 axis_en=entry.get("axis_en", sheet_entry.get("axis_en", "")),
                 unit=entry.get("unit", sheet_entry.get("unit", "-")),
                 x_axis_zh=entry.get("x_axis_zh", ""), x_axis_en=entry.get("x_axis_en", ""),
                 x_unit=entry.get("x_unit"), equal_axes=entry.get("equal_axes", False),
                 type=entry.get("type", "scatter"), log=_chart_log(entry, sheet_entry, file),
                 curve_zh=entry.get("curve_zh", ""), curve_en=entry.get("curve_en", ""),
                 curves=entry.get("curves"), live_names=bool(entry.get("live_names", False)),
                 emphasis=entry.get("emphasis"), heavy=tuple(entry.get("heavy", ())),
                 rows_from=None if rows_from is None else float(rows_from))


def _adopted_rules(data):
    """The workbook's rules, those written ``from = "<rulebook key>"`` filled in from the
    libraries' rulebooks (their own names and messages, where given, win)."""
    book = {r["key"]: r for r in data["rulebook"]}
    rules = []
    for rule in data["rule"]:
        if "from" in rule:
            if rule["from"] not in book:
                raise SpecError(rule["_file"], rule["from"], "no such rule in the rulebooks")
            rule = {**book[rule["from"]], **{k: v for k, v in rule.items() if k != "from"}}
        rules.append(rule)
    return rules


@lru_cache(maxsize=None)
def load(name):
    """The workbook specification templates/<name>.toml (cached; read-only)."""
    data, file = _merged(name)
    return build(data, file)


def from_data(data, file="test.toml"):
    """A specification from parsed TOML (libraries in ``include`` are merged)."""
    return build(_with_libraries(expanded(data, file), file), file)


def build(data, file):
    """A specification from merged data (see :func:`load`)."""
    head = data.get("workbook")
    if head is None:
        raise SpecError(file, "workbook", "a template needs a [workbook] table")
    cycle = head.get("cycle")
    start = head.get("grid_start", 0.0)
    stop = head.get("grid_stop", start + cycle if cycle else None)
    main = _grid({"key": head["grid"], "zh": "曲轴转角 α", "en": "Crank angle α",
                  "start": start, "stop": stop, "step": head["grid_step"],
                  "axis": (start, stop, 90.0), "_file": file, **head.get("grid_labels", {})},
                 period=cycle, step_option="step")
    grids = [main] + [_grid(g) for g in data["grid"]]
    parameters = _in_group_order([_parameter(p) for p in data["parameter"]],
                                 data.get("groups", {}))
    axes = [Axis(key=a["key"], zh=a["zh"], en=a["en"], label_zh=a.get("label_zh", a["zh"]),
                 label_en=a.get("label_en", a["en"]), size_calc=a.get("size_calc"),
                 size_args=dict(a.get("size_args", {})), max=a.get("max", 64),
                 product=tuple(a.get("product", ())), aligned=a.get("aligned"),
                 value_key=a.get("value_key"), value_label_zh=a.get("value_label_zh", ""),
                 value_label_en=a.get("value_label_en", ""),
                 item_names_zh=tuple(a.get("item_names_zh", ())),
                 item_names_en=tuple(a.get("item_names_en", ())))
            for a in data["axis"]]
    for a in axes:
        if len(a.item_names_zh) != len(a.item_names_en):
            raise SpecError(file, a.key, "item_names_zh and item_names_en must name the same "
                            "items")
        runs = [[i for i, name in enumerate(names) if EACH in name]
                for names in (a.item_names_zh, a.item_names_en)]
        if len(runs[0]) > 1 or runs[0] != runs[1]:
            raise SpecError(file, a.key, f"item names hold {EACH} in one entry, the same in "
                            "both languages (it repeats for the items the others leave)")
    constants = [Constant(key=c["key"], unit=c["unit"], value=float(c["value"]),
                          zh=c.get("zh", ""), en=c.get("en", "")) for c in data["constant"]]
    if cycle is not None:
        constants.append(Constant(key="cycle", unit=main.unit, value=float(cycle),
                                  zh="工作循环曲轴转角", en="crank angle of one working cycle"))
    tables = [InputTable(key=t["key"], sheet=t["sheet"], capacity=t["capacity"],
                         columns=tuple(InputColumn(**c) for c in t["column"]))
              for t in data["input_table"]]
    columnsets = {c["key"]: [dict(m, _file=c["_file"]) for m in c["column"]]
                  for c in data["columnset"]}
    inputs = {p["key"] for p in data["parameter"]} | {c["key"] for c in data["constant"]} | \
        {c["key"] for t in data["input_table"] for c in t["column"]} | ({"cycle"} if cycle else set())
    placer = _Placer(columnsets, inputs)

    # derived scalars (Parameters sheet): their own entries and placed column sets
    scalar_entries = []
    for use in data["use"]:
        scalar_entries += placer.place(use, None, use["_file"])
    scalar_entries += [dict(s) for s in data["scalar"]]

    sheet_entries = []
    for s in data["sheet"]:
        kind = s.get("kind", "series")
        grid = s.get("grid", main.key) if kind == "series" else None
        entries = []
        for c in s.get("column", []) + s.get("scalar", []):
            if "columnset" in c:          # one member of a set, placed here in order
                member = c.get("member") or c.get("key")
                own = ("member", "key", "zh", "en", "summary", "format")
                use = {k: v for k, v in c.items() if k not in own}
                use["columns"] = [member]
                use["labels"] = {member: {k: c[k] for k in own[2:] if k in c}}
                if "key" in c and "member" in c:
                    use["rename"] = {member: c["key"]}
                entries += placer.place(use, grid, s["_file"])
            else:
                entries.append(dict(c, _file=s["_file"]))
        for use in s.get("use", []):
            entries += placer.place(use, grid, s["_file"])
        if kind == "items":
            for e in entries:
                e.setdefault("items", _need(s, "axis", "items sheet"))
        sheet_entries.append((s, kind, grid, entries))
    placer.resolve()

    sheets = []
    for s, kind, grid, entries in sheet_entries:
        entries = [_resolve_args(e) for e in entries]
        if kind == "series":
            columns = tuple(_quantity(e, "series", sheet=s["key"], grid=grid) for e in entries)
        else:
            columns = tuple(_quantity(e, "scalar", sheet=s["key"]) for e in entries)
        charts = [_chart(s["chart"], s, s["_file"])] if s.get("chart") else []
        charts += [_chart(c, s, s["_file"]) for c in s.get("charts", [])]
        sheets.append(Sheet(key=s["key"], zh=s["zh"], en=s["en"],
                            title_zh=s.get("title_zh", s["zh"]), title_en=s.get("title_en", s["en"]),
                            kind=kind, columns=columns, charts=tuple(charts), grid=grid,
                            axis=s.get("axis"), print_step=s.get("print_step"),
                            item_word={lang: s[f"item_word_{lang}"] for lang in ("zh", "en")
                                       if f"item_word_{lang}" in s},
                            report=tuple(s["report"]) if "report" in s else None))
    scalars = [_quantity(_resolve_args(e), "scalar") for e in scalar_entries]
    results = [_quantity(r, "result") for r in data["result"]]
    rules = [_quantity(dict(r, key=f"check_{r['key']}", unit=r.get("unit", "-"), guard=False),
                       "rule") for r in _adopted_rules(data)]
    by_grid = {g.key: g for g in grids}
    summary_series = [c for s in sheets if s.kind == "series" for c in s.columns
                      if c.summary and not c.items]
    spec = WorkbookSpec(
        key=head["key"], file=file, zh=head["zh"], en=head["en"], grid=main, grids=grids,
        groups=data.get("groups", {}), parameters=parameters, axes=axes, constants=constants,
        input_tables=tables, rules=rules, scalars=scalars, sheets=sheets, results=results,
        summary=_summary_quantities(by_grid, summary_series),
        highlights=tuple(head.get("highlights", ())), key_data=tuple(head.get("key_data", ())),
        print_step=head.get("print_step"), notes=tuple(head.get("notes", ())),
        coarse_step=head.get("coarse_step"))
    check(spec)
    return spec
