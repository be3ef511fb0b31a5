"""Parameter values: presets, class groups, overrides and the input rules.

The same bounds and rules are the workbook's data validation and input checks, so
the command line, the API and the spreadsheet refuse the same inputs.  A rule is
a quantity (formula and calc function); here its calc function decides.
"""
import difflib
import math
import re

import numpy as np

from crankbook.support import resources
from crankbook.errors import (GeometryError, LayoutError, ParameterValueError, SpecError,
                              UnknownGroupError, UnknownParameterError, UnknownPresetError)
from crankbook.spec.evaluate import axis_sizes, evaluate
from crankbook.spec.loader import load as load_spec

PRESETS = "presets"
GROUPS = "groups"
# Plain ASCII decimal numbers only: no full-width or Arabic-Indic digits, no 1_000,
# no inf or nan (Python's float() takes all of those).
NUMBER = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?\Z")


def preset_names():
    return resources.names(PRESETS)


def read_preset(name):
    if not resources.is_safe_name(name) or not resources.exists(PRESETS, f"{name}.toml"):
        raise UnknownPresetError(f"unknown preset {name!r}; choose one of: "
                                 f"{', '.join(preset_names())}")
    return resources.read_toml(PRESETS, f"{name}.toml")


def load_preset(name):
    """(spec, values, preset table) of a preset: the template's defaults, then the
    preset's values (per-item parameters as lists, choices as 1-based indices)."""
    data = read_preset(name)
    meta = dict(data["preset"])
    spec = load_spec(meta["template"])
    values = {p.key: (list(p.default) if p.axis else p.default) for p in spec.parameters}
    chain, base = [data], meta.get("base")
    while base:                   # a preset may start from another (base = "thesis")
        if len(chain) > 8 or base == name:
            raise SpecError(f"{PRESETS}/{name}.toml", "base", "presets based on each other")
        chain.insert(0, read_preset(base))
        base = chain[0]["preset"].get("base")
    given = {key: value for link in chain for key, value in link.get("values", {}).items()}
    for key, value in given.items():
        if key not in spec.parameter:
            raise SpecError(f"{PRESETS}/{name}.toml", key, "sets an unknown parameter")
        values[key] = value
    values = {key: coerce(spec.parameter[key], value, f"preset {name}") for key, value in
              values.items()}
    return spec, values, meta


def group_numbers(preset):
    table = preset.get("groups")
    if table is None:
        return []
    return sorted(g["number"] for g in resources.read_toml(GROUPS, f"{table}.toml")["group"])


def apply_group(spec, values, preset, number):
    """Values with class group ``number`` of the preset's group table applied."""
    table = preset.get("groups")
    if table is None:
        raise UnknownGroupError(f"--group: preset {preset['name']!r} has no table of groups")
    groups = {g["number"]: g for g in resources.read_toml(GROUPS, f"{table}.toml")["group"]}
    if isinstance(number, bool) or not isinstance(number, int) or number not in groups:
        raise UnknownGroupError(f"--group {number}: no such group in preset {preset['name']!r}; "
                                f"groups are {min(groups)}–{max(groups)}")
    values = dict(values)
    for key, value in groups[number].items():
        if key != "number":
            if key not in spec.parameter:
                raise SpecError(f"{GROUPS}/{table}.toml", key,
                                f"group {number} sets an unknown parameter")
            values[key] = coerce(spec.parameter[key], value, f"group {number}")
    return values


def parse_number(key, text):
    """A finite float from a plain ASCII decimal ``text``, or ParameterValueError."""
    if isinstance(text, bool):
        raise ParameterValueError(f"parameter {key}: {text!r} is not a number")
    if isinstance(text, (int, float, np.integer, np.floating)):
        value = float(text)
    else:
        stripped = str(text).strip()
        if not NUMBER.match(stripped):
            raise ParameterValueError(f"parameter {key}: {str(text)[:40]!r} is not a number "
                                      f"(plain digits, '.', an optional exponent)")
        value = float(stripped)
    if not math.isfinite(value):
        raise ParameterValueError(f"parameter {key}: {text!r} is not a finite number")
    return value


def coerce(parameter, value, where=""):
    """A parameter value in its canonical form: float, 1-based choice index, or a
    list of floats for a per-item parameter."""
    if parameter.axis:
        if isinstance(value, str):
            parts = [p for p in value.split(",")]
            if any(not p.strip() for p in parts):
                raise ParameterValueError(f"{parameter.key}: {value!r}: give one number per "
                                          f"{parameter.axis}, separated by commas")
            value = parts
        elif not isinstance(value, (list, tuple, np.ndarray)):
            value = [value]
        if not 1 <= len(value) <= 64:
            raise ParameterValueError(f"{parameter.key}: give 1 to 64 values, not {len(value)}")
        return [parse_number(parameter.key, v) for v in value]
    if parameter.kind == "choice":
        number = parameter.choice_number(value.strip()) if isinstance(value, str) else None
        if number is not None:
            return float(number)
        if isinstance(value, (int, float)) and not isinstance(value, bool) and \
                float(value).is_integer() and 1 <= value <= len(parameter.choices):
            return float(value)
        raise ParameterValueError(f"parameter {parameter.key} = {str(value)[:40]!r}: must be "
                                  f"one of {', '.join(parameter.choices)}")
    return parse_number(parameter.key, value)


def _did_you_mean(key, known):
    """' (did you mean a, b?)' for the keys a slip of ``key`` could be: a close spelling
    ('sped'), or a key that contains it or that it contains ('rod' → rod_length, …)."""
    key = str(key)
    close = difflib.get_close_matches(key, known, n=3, cutoff=0.75)
    if len(key) >= 3:
        close += [k for k in known if (key in k or k in key) and k not in close][:5 - len(close)]
    return f" (did you mean {', '.join(close)}?)" if close else ""


def apply_overrides(spec, values, overrides):
    """Values with each key → value of ``overrides`` applied (values as typed: text
    from the command line, or Python numbers, lists and words from the API)."""
    values = dict(values)
    for key, value in overrides.items():
        if key not in spec.parameter:
            raise UnknownParameterError(f"unknown parameter {str(key)[:80]!r}"
                                        f"{_did_you_mean(key, spec.parameter)}; "
                                        f"'crankbook parameters --preset PRESET' lists them")
        values[key] = coerce(spec.parameter[key], value, "--set")
    return values


def parse_assignments(assignments):
    """``KEY=VALUE`` strings (the command line's --set) as an ordered dict."""
    out = {}
    for assignment in assignments:
        key, sep, text = assignment.partition("=")
        if not sep or not key.strip():
            raise ParameterValueError(f"--set {assignment[:60]!r}: expected KEY=VALUE")
        out[key.strip()] = text.strip()
    return out


def _describe(spec, keys, values, item=None):
    """``key = value`` of each of ``keys`` (of item ``item``, 1-based, for per-item ones)."""
    def show(key):
        p = spec.parameter[key]
        unit = "" if p.unit in ("-", "count") else f" {p.unit}"
        value = values[key]
        if p.axis and item is not None:
            return f"{key} = {value[item - 1]:g}{unit}"
        if p.kind == "choice":
            return f"{key} = {p.choices[int(value) - 1]}"
        if p.axis:
            return f"{key} = " + ",".join(f"{v:g}" for v in value) + unit
        return f"{key} = {value:g}{unit}"
    return ", ".join(show(k) for k in keys if k in spec.parameter)


def all_digits(value):
    """A number with every digit it has (2000.0000001, not 2000: a bound's message must
    show why the value breaks it)."""
    text = repr(float(value))
    return text[:-2] if text.endswith(".0") else text


def validate(spec, values, trace_points=0, tables=None, grids=None, layout=None):
    """Raise the first error a user would need to fix; return the values.

    Bounds first (each parameter on its own), then the per-item tables' shapes,
    then every input rule through its calc function (on ``grids``, the workbook's
    numeric grids, where a rule reads one; default: the template's default steps).
    """
    values = dict(values)
    for parameter in spec.parameters:
        value = values[parameter.key]
        items = value if parameter.axis else [value]
        for number, item in enumerate(items, start=1):
            item = parse_number(parameter.key, item)
            if parameter.breaks_bounds(item):
                where = f" of {spec.axis[parameter.axis].label_en.lower()} {number}" \
                    if parameter.axis else ""
                shown = parameter.choices[int(item) - 1] if parameter.kind == "choice" and \
                    float(item).is_integer() and 1 <= item <= len(parameter.choices) \
                    else all_digits(item)
                raise ParameterValueError(f"parameter {parameter.key}{where} = {shown}: must be "
                                          f"{parameter.bounds_text()}")
    sizes = axis_sizes(spec, values)
    values = fit_derived_items(spec, values, sizes)
    for axis in spec.axes:
        if sizes[axis.key] > axis.max:
            noun = axis.label_en.lower()
            raise LayoutError(f"{sizes[axis.key]} {noun}{'' if noun.endswith('s') else 's'}: "
                              f"at most {axis.max}")
        if sizes[axis.key] < 1:
            raise LayoutError(f"the {axis.en.lower()} table needs at least one "
                              f"{axis.label_en.lower()}")
    if not spec.rules:
        return values
    tables = dict(tables or {})
    if trace_points and not tables:
        tables = {c: np.zeros(trace_points) for c in spec.table_column}
    flags = evaluate(spec, values, tables, grids, keys=[r.key for r in spec.rules],
                     layout=layout)
    for rule in spec.rules:
        flag = np.atleast_1d(flags[rule.key])
        if np.any(flag != 0):
            where, first = "", None
            if rule.items:
                first = int(np.flatnonzero(flag)[0]) + 1
                where = f"{spec.axis[rule.items].label_en.lower()} {first}: "
            raise GeometryError(f"{where}{_describe(spec, rule.names, values, first)}: "
                                f"{rule.en}")
    return values


def fit_derived_items(spec, values, sizes):
    """Per-item parameters of an axis sized by other inputs (a typed inertia per
    station, whose count follows the throws; a ``fill`` column beside the one that sets
    its axis): left at their default, one value per item; typed, exactly one per item,
    else a LayoutError naming the parameter."""
    values = dict(values)
    for parameter in spec.parameters:
        axis = spec.axis.get(parameter.axis) if parameter.axis else None
        if axis is None or not (axis.size_calc or parameter.fill):
            continue
        given, count = list(values[parameter.key]), sizes[axis.key]
        if len(given) == count:
            continue
        if given == list(parameter.default):
            values[parameter.key] = [parameter.default[0]] * count
            continue
        label = axis.label_en.lower()
        raise LayoutError(f"parameter {parameter.key} has {len(given)} values, one per "
                          f"{label}: this workbook has {count} ({label} 1 … {count})")
    return values
