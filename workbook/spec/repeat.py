"""Entries written once and laid out several times: ``repeat`` in a template.

An entry of any ``[[…]]`` list (a column, a scalar, a sheet …) that holds

    repeat = { step = [1, 2, 3], previous = [0, 1, 2] }

stands for as many entries as the lists are long (all of one length), the i-th with
every ``${step}`` and ``${previous}`` in its text — key, labels, formula, part, args,
nested tables — replaced by the lists' i-th values.  A formula may build a key from
them: ``{peak_angle_${previous}|rad}`` is ``{peak_angle_0|rad}`` in the first copy.
The copies take the entry's place in its list, in order, so a workbook built from a
repeated entry is the workbook its written-out copies build, byte for byte.

``together = n`` beside ``repeat`` repeats the entry and the n − 1 entries after it as
one block: all n for the first values, then all n for the second, and so on (four
look-ups per Raimondi–Boyd table, table after table).
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
        out, position = [], 0
        while position < len(data):
            item = data[position]
            if isinstance(item, dict) and "repeat" in item:
                block = _block(data, position, file)
                out += [expanded(copy, file) for copy in _copies(block, file)]
                position += len(block)
            else:
                out.append(expanded(item, file))
                position += 1
        return out
    if isinstance(data, str) and "${" in data:
        name = _USE.search(data).group(1)
        raise SpecError(file, "repeat", f"${{{name}}} is used outside a repeated entry")
    return data


def _block(entries, position, file):
    """The repeated entry and the entries ``together`` takes with it."""
    head = entries[position]
    key = str(head.get("key", "repeat"))
    size = head.get("together", 1)
    if not isinstance(size, int) or isinstance(size, bool) or size < 1:
        raise SpecError(file, key, "together must be a whole number of entries, 1 or more")
    block = entries[position:position + size]
    if len(block) < size:
        raise SpecError(file, key, f"together = {size}, but only {len(block)} entries "
                                   f"follow from here")
    for other in block[1:]:
        if not isinstance(other, dict) or "repeat" in other or "together" in other:
            raise SpecError(file, key, "an entry the repeat takes together has no repeat "
                                       "or together of its own")
    return block


def _copies(block, file):
    entry = block[0]
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
    bodies = [{k: v for k, v in entry.items() if k not in ("repeat", "together")}] + block[1:]
    return [_filled(body, {name: _text(values[i]) for name, values in table.items()},
                    file, key)
            for i in range(lengths.pop()) for body in bodies]


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
