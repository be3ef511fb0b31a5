"""Sheet units (templates/units.toml): dimension, factor to SI, number format.

The same table serves the evaluator (values in and out of SI), the formula compiler
(``{key|unit}`` conversions) and the grader (unit slips only within one dimension).
"""
import math
from functools import lru_cache

from crankbook.support import resources


def _table():
    return resources.read_toml("units.toml")["unit"]


def answer_convertible(typed, wanted):
    """Whether an answer typed in ``typed`` can be read in ``wanted``: one dimension,
    or one that ``[answer_dimensions]`` takes as it (N·m for a J item)."""
    if dimension(typed) == dimension(wanted):
        return True
    also = resources.read_toml("units.toml").get("answer_dimensions", {})
    return dimension(typed) in also.get(dimension(wanted), ())


def same_unit(typed, wanted):
    """Whether ``typed`` is ``wanted`` under another name (N·m for J): the answer
    is in the asked unit, not a slip."""
    return typed == wanted or (answer_convertible(typed, wanted) and
                               math.isclose(si_factor(typed), si_factor(wanted),
                                            rel_tol=1e-12))


def normalised(text):
    """A unit as typed, made comparable: NFKC (full-width letters), lower case, no
    spaces, ·/./* as ·, ^2 and a trailing 2 as ²."""
    import re
    import unicodedata
    text = unicodedata.normalize("NFKC", str(text)).strip().lower().replace(" ", "")
    text = re.sub(r"[.*⋅•]", "·", text).replace("^2", "²").replace("^-1", "⁻¹")
    text = re.sub(r"(?<=[a-z])2\b", "²", text)
    return text


@lru_cache(maxsize=512)
def typed_unit(text):
    """The unit a person means by ``text`` after a number ("mm", "m/s^2", "N.m",
    "毫米"), or None."""
    wanted = normalised(text)
    if not wanted:
        return None
    for unit, spellings in resources.read_toml("units.toml").get("typed", {}).items():
        if wanted in (normalised(s) for s in spellings) or wanted == normalised(unit):
            return unit
    return None


def known(unit):
    return unit in _table()


def _entry(unit):
    try:
        return _table()[unit]
    except KeyError:
        raise KeyError(f"unit {unit!r} is not defined in units.toml") from None


def si_factor(unit):
    """Factor that turns a value in ``unit`` into SI."""
    return _entry(unit)["si"]


def dimension(unit):
    return _entry(unit)["dimension"]


def number_format(unit):
    """Excel number format for cells in ``unit``."""
    return _entry(unit)["format"]


def units_of(dimension_name):
    """Every unit of one dimension."""
    return [u for u, e in _table().items() if e["dimension"] == dimension_name]


def slip_units_of(dimension_name):
    """The units of one dimension the grader takes a slip into (``slip = false``
    leaves one out: µm beside mm)."""
    return [u for u in units_of(dimension_name) if _table()[u].get("slip", True)]


def convertible(source, target):
    return dimension(source) == dimension(target)


def _power_of_ten(ratio):
    exponent = round(math.log10(ratio))
    return exponent if exponent and math.isclose(ratio, 10.0 ** exponent, rel_tol=1e-12) else None


def excel_conversion(reference, source, target):
    """Excel text of ``reference`` (in ``source``) expressed in ``target``."""
    if source == target:
        return reference
    if dimension(source) == "angle" and {source, target} == {"deg", "rad"}:
        return f"{'RADIANS' if target == 'rad' else 'DEGREES'}({reference})"
    ratio = si_factor(source) / si_factor(target)
    if math.isclose(ratio, 1.0, rel_tol=1e-15):
        return reference
    exponent = _power_of_ten(ratio)
    if exponent is not None and exponent > 0:
        return f"({reference}*{10 ** exponent})"
    if exponent is not None:
        return f"({reference}/{10 ** -exponent})"
    if {source, target} == {"rpm", "rad/s"}:
        return f"({reference}*PI()/30)" if target == "rad/s" else f"({reference}*30/PI())"
    return f"({reference}*{ratio!r})"
