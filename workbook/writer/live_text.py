"""Words that hold a result: an item's name such as "Main bearing {checked_journal}"
(the main bearing the orbit analyses, chosen live in the workbook).

Wherever the writer prints such a name — an items sheet's row, a column's header, a
chart's legend entry — it writes a text formula, ``="Main bearing
"&IF(ISNUMBER(ref),TEXT(ref,"0"),"?")&" (engine frame)"``, cached with numpy's value,
so the name follows the inputs in every engine as the numbers do.  The template
language allows it for a discrete scalar (a whole number; crankbook.spec.check); a
header's rows in both languages are such formulas alike.  "?" stands where the
result is blank (the inputs break a rule).
"""
import math

import numpy as np

from crankbook.spec import placeholders

UNKNOWN = "?"


def _parts(text, layout):
    """[(literal text, None) or (None, held key)] of ``text``; None when it holds no
    result."""
    if "{" not in text or not layout.live_keys:
        return None
    try:
        nodes = placeholders.parse(text)
    except placeholders.TemplateSyntaxError:    # a label's own braces: plain words
        return None
    if not any(isinstance(n, placeholders.Ref) and n.key in layout.live_keys for n in nodes):
        return None
    return [(None, n.key) if isinstance(n, placeholders.Ref) else (n, None) for n in nodes]


def is_live(text, layout):
    return _parts(text, layout) is not None


def _whole_number(value):
    value = float(np.ravel(value)[0])
    return str(int(round(value))) if math.isfinite(value) else UNKNOWN


def cached(text, layout):
    """The text as the engines compute it for the built inputs."""
    parts = _parts(text, layout)
    if parts is None:
        return text
    return "".join(literal if key is None else _whole_number(layout.live_values[key])
                   for literal, key in parts)


def expression(text, layout):
    """The Excel expression (no leading "=") of ``text``: a quoted constant, or the
    concatenation of its pieces with each held result."""
    parts = _parts(text, layout)
    if parts is None:
        return quoted(text)
    pieces = []
    for literal, key in parts:
        if key is not None:
            ref = layout.locator.whole_range(key)
            pieces.append(f'IF(ISNUMBER({ref}),TEXT({ref},"0"),"{UNKNOWN}")')
        elif literal:
            pieces.append(quoted(literal))
    return "&".join(pieces)


EXCEL_TEXT_CONSTANT = 255         # characters: Excel refuses a longer string in a formula


def quoted(text):
    """``text`` as a formula's string constant: pieces of at most 255 characters
    joined by & (a longer label would make Excel drop the formula), quotes doubled."""
    pieces = [text[i:i + EXCEL_TEXT_CONSTANT]
              for i in range(0, len(text), EXCEL_TEXT_CONSTANT)] or [""]
    return "&".join('"' + piece.replace('"', '""') + '"' for piece in pieces)


def write_text(ws, row, col, text, style, layout):
    """Write ``text`` at (row, col): a formula when it holds a result, else the text."""
    if is_live(text, layout):
        ws.write_formula(row, col, "=" + expression(text, layout), style, cached(text, layout))
    else:
        ws.write(row, col, text, style)
