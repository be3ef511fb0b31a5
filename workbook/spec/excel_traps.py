"""Formula texts that mean one thing to a reader and another to a spreadsheet.

Excel, LibreOffice and Gnumeric give unary minus a higher precedence than ``^``:
``=-2^2`` is 4 and ``-(a*b)^2`` is (−a·b)², not −(a·b)².  numpy (and the calc function
beside every formula) reads it the other way, so a template that writes a unary minus
before a power is refused when it is loaded; write ``-(x^2)`` or ``0-x^2``.
"""
import re

# after these (or at the start) a minus is unary
_BEFORE_UNARY = set("(,=*/^+-<>&")
_OPERAND = re.compile(r"[0-9.]+(?:[Ee][+-]?[0-9]+)?|[A-Za-z_][A-Za-z0-9_.]*")
_CLOSE = {"(": ")", "{": "}"}


def _operand_end(text, i):
    """Where the operand starting at ``i`` ends (a group, a placeholder, a number, a
    name or a function call), or None."""
    if i >= len(text):
        return None
    if text[i] in _CLOSE:
        opening, closing, depth = text[i], _CLOSE[text[i]], 0
        for j in range(i, len(text)):
            if text[j] == opening:
                depth += 1
            elif text[j] == closing:
                depth -= 1
                if depth == 0:
                    return j + 1
        return None
    match = _OPERAND.match(text, i)
    if not match:
        return None
    end = match.end()
    return _operand_end(text, end) if end < len(text) and text[end] == "(" else end


def unary_minus_power(text):
    """The first ``-x^…`` of a formula template (a little context around it), or None."""
    for i, char in enumerate(text):
        if char != "-":
            continue
        before = text[:i].rstrip()
        if before and before[-1] not in _BEFORE_UNARY:
            continue
        end = _operand_end(text, i + 1)
        if end is not None and text[end:end + 1] == "^":
            return text[max(0, i - 12):end + 3]
    return None
