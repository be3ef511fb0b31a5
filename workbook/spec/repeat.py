"""Entries written once and laid out several times: ``repeat`` in a template.

An entry of any ``[[…]]`` list (a column, a scalar, a sheet …) that holds

    repeat = { step = [1, 2, 3], previous = [0, 1, 2] }

stands for as many entries as the lists are long (all of one length), the i-th with
every ``${step}`` and ``${previous}`` in its text — key, labels, formula, part, args,
nested tables — replaced by the lists' i-th values.  A formula may build a key from
them: ``{peak_angle_${previous}|rad}`` is ``{peak_angle_0|rad}`` in the first copy.
The copies take the entry's place in its list, in order, so a workbook built from a
repeated entry is the workbook its written-out copies build, byte for byte.
"""
import re

from crankbook.errors import SpecError

_NAME = re.compile(r"[a-z][a-z0-9_]*\Z")
_USE = re.compile(r"\$\{([^}]*)\}")


def expanded(data, file):
    """``data`` (parsed TOML) with every repeated entry written out."""
    if isinstance(data, dict):
        return {key: expanded(value, file) for key, value in data.items()}
    if isinstance(data, list):
        out = []
        for item in data:
            if isinstance(item, dict) and "repeat" in item:
                out += [expanded(copy, file) for copy in _copies(item, file)]
            else:
                out.append(expanded(item, file))
        return out
    if isinstance(data, str) and "${" in data:
        name = _USE.search(data).group(1)
        raise SpecError(file, "repeat", f"${{{name}}} is used outside a repeated entry")
    return data


def _copies(entry, file):
    key = str(entry.get("key", "repeat"))
    table = entry["repeat"]
    if not isinstance(table, dict) or not table:
        raise SpecError(file, key, "repeat must be a table of lists, e.g. "
                                   "repeat = { step = [1, 2, 3] }")
    lengths = set()
    for name, values in table.items():
        if not _NAME.match(name):
            raise SpecError(file, key, f"repeat: {name!r} is not a plain lower-case name")
        if not isinstance(values, list) or not values or \
                not all(isinstance(v, (int, float, str)) and not isinstance(v, bool)
                        for v in values):
            raise SpecError(file, key, f"repeat: {name} must be a list of numbers or words")
        lengths.add(len(values))
    if len(lengths) != 1:
        raise SpecError(file, key, "repeat: the lists must be of one length")
    body = {k: v for k, v in entry.items() if k != "repeat"}
    return [_filled(body, {name: _text(values[i]) for name, values in table.items()},
                    file, key)
            for i in range(lengths.pop())]


def _text(value):
    return f"{value:g}" if isinstance(value, float) else str(value)


def _filled(value, names, file, key):
    if isinstance(value, dict):
        return {k: _filled(v, names, file, key) for k, v in value.items()}
    if isinstance(value, list):
        return [_filled(v, names, file, key) for v in value]
    if isinstance(value, str):
        def one(match):
            if match.group(1) not in names:
                raise SpecError(file, key, f"${{{match.group(1)}}} is not one of the "
                                           f"repeat's names ({', '.join(names)})")
            return names[match.group(1)]
        return _USE.sub(one, value)
    return value
