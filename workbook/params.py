"""Parameter values: presets, ``--set`` overrides and the input rules.

The same bounds and rules also become the workbook's data validation and its
input checks, so the command line and the spreadsheet refuse the same inputs.
"""
import math
import tomllib

from workbook import spec as specs
from workbook.toml_files import names_in, read_named
from workbook.errors import (GeometryError, ParameterValueError, UnknownGroupError,
                             UnknownParameterError, UnknownPresetError)

PRESETS = specs.TEMPLATES / "presets"


def preset_names():
    return names_in(PRESETS)


def load_preset(name):
    """(spec, values) of a preset: the template's defaults, then the preset's values."""
    data = read_named(PRESETS, name, "preset")
    spec = specs.load(data["preset"]["template"])
    values = {p.key: p.default for p in spec.parameters}
    for key, value in data.get("values", {}).items():
        if key not in spec.parameter:
            raise UnknownParameterError(f"preset {name!r} sets unknown parameter {key!r}")
        values[key] = value
    return spec, values, data["preset"]


def apply_group(spec, values, preset, number):
    """Values with class group ``number`` of the preset's group table applied."""
    table_name = preset.get("groups")
    if table_name is None:
        raise UnknownPresetError(f"--group: preset {preset['name']!r} has no table of groups")
    with open(specs.TEMPLATES / "groups" / f"{table_name}.toml", "rb") as handle:
        groups = {g["number"]: g for g in tomllib.load(handle)["group"]}
    if number not in groups:
        raise UnknownGroupError(f"--group {number}: no such group in preset {preset['name']!r}; "
                                f"groups are {min(groups)}–{max(groups)}")
    values = dict(values)
    for key, value in groups[number].items():
        if key != "number":
            if key not in spec.parameter:
                raise UnknownParameterError(f"group {number} sets unknown parameter {key!r}")
            values[key] = value
    return values


def parse_number(key, text):
    """A finite float from ``text``, or ParameterValueError naming ``key``."""
    try:
        value = float(text)
    except (TypeError, ValueError):
        raise ParameterValueError(f"parameter {key}: {text!r} is not a number") from None
    if not math.isfinite(value):
        raise ParameterValueError(f"parameter {key}: {text!r} is not a finite number")
    return value


def apply_overrides(spec, values, assignments):
    """Values with each ``KEY=VALUE`` of ``assignments`` applied."""
    values = dict(values)
    for assignment in assignments:
        key, sep, text = assignment.partition("=")
        key = key.strip()
        if not sep:
            raise ParameterValueError(f"--set {assignment!r}: expected KEY=VALUE")
        if key not in spec.parameter:
            close = [k for k in spec.parameter if key in k or k in key]
            hint = f" (did you mean {', '.join(close)}?)" if close else ""
            raise UnknownParameterError(f"--set: unknown parameter {key!r}{hint}; "
                                        f"parameters are: {', '.join(spec.parameter)}")
        values[key] = parse_number(key, text.strip())
    return values


def breaks_bounds(parameter, value):
    """True when ``value`` is outside the parameter's own bounds."""
    if parameter.kind == "flag":
        return value not in (0, 1)
    lo, hi = parameter.min, parameter.max
    return ((lo is not None and (value <= lo if parameter.min_open else value < lo))
            or (hi is not None and (value >= hi if parameter.max_open else value > hi)))


def _describe(spec, keys, values):
    def unit(key):
        u = spec.parameter[key].unit
        return "" if u == "-" else f" {u}"
    return ", ".join(f"{key} = {values[key]:g}{unit(key)}" for key in keys)


def validate(spec, values, trace_points=0):
    """Raise the first error a user would need to fix; return the values as floats."""
    for parameter in spec.parameters:
        value = parse_number(parameter.key, values[parameter.key])
        if breaks_bounds(parameter, value):
            raise ParameterValueError(
                f"parameter {parameter.key} = {value:g}: must be {parameter.bounds_text()}")
        values[parameter.key] = value
    namespace = dict(values, trace_points=trace_points)
    functions = {"__builtins__": {}, "abs": abs, "min": min, "max": max,
                 **{name: getattr(math, name) for name in
                    ("sqrt", "tan", "sin", "cos", "asin", "acos", "atan", "pi", "radians",
                     "degrees")}}
    for rule in spec.rules:
        try:
            broken = eval(rule.python, functions, namespace)  # noqa: S307 (our own data)
        except (ValueError, ZeroDivisionError):
            broken = True                        # a math domain error is a broken rule too
        if broken:
            raise GeometryError(f"{_describe(spec, rule.names, values)}: {rule.en}")
    return values
