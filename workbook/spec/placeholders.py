"""The placeholders of a formula template, parsed once into a small tree.

A template is Excel formula text with placeholders in braces (docs/templates.md):

    {key}               a parameter, constant, quantity (its meaning depends on where
                        the formula is: see crankbook.spec.formulas)
    {key:head}          a part of a series: head, tail, prev, last, all, items
    {key:rows}          the number of rows of a grid as laid out, a number
    {key:at(EXPR)}      a periodic series at the grid angle EXPR
    {key:item(EXPR)}    item EXPR (1-based) of a per-item quantity
    {key|unit}          converted into ``unit`` (any part may be converted too)
    {item} {index}      the formula's own item number; the summation index
    {item:axis}         that axis's part of the formula's own item of a product axis
    {row_index}         0-based row of the formula within its grid
    {sum:axis(EXPR)}    EXPR summed over the items of ``axis``

EXPR is itself a template.  The parser is the only place that knows this syntax.
"""
import re
from dataclasses import dataclass

NAME = re.compile(r"[a-z_][a-z_0-9]*")
PARTS = ("head", "tail", "prev", "last", "all", "items", "rows")
CALL_PARTS = ("at", "item")
SPECIAL = ("item", "index", "row_index")


class TemplateSyntaxError(ValueError):
    """A template that does not follow the placeholder syntax."""


@dataclass(frozen=True)
class Ref:
    key: str
    part: str | None = None          # one of PARTS or CALL_PARTS
    argument: tuple | None = None    # parsed EXPR of at()/item()
    unit: str | None = None


@dataclass(frozen=True)
class Special:
    name: str                        # item, index, row_index
    axis: str | None = None          # {item:throw}: that axis's part of a product item


@dataclass(frozen=True)
class Sum:
    axis: str
    body: tuple                      # parsed EXPR


def parse(text):
    """The template as a tuple of str (literal text) and Ref/Special/Sum nodes."""
    nodes, position = _parse(text or "", 0, closing=None)
    return nodes


def _parse(text, i, closing):
    nodes, literal = [], []
    depth = 0
    while i < len(text):
        char = text[i]
        if char == '"':                       # an Excel string: braces inside are text
            end = text.find('"', i + 1)
            while end != -1 and text[end + 1:end + 2] == '"':
                end = text.find('"', end + 2)
            if end == -1:
                raise TemplateSyntaxError(f"unterminated string in {text!r}")
            literal.append(text[i:end + 1])
            i = end + 1
            continue
        if closing and char == "(":
            depth += 1
        elif closing and char == ")":
            if depth == 0:
                break
            depth -= 1
        if char == "{":
            if literal:
                nodes.append("".join(literal))
                literal = []
            node, i = _placeholder(text, i + 1)
            nodes.append(node)
            continue
        if char == "}":
            raise TemplateSyntaxError(f"unmatched '}}' at {i} in {text!r}")
        literal.append(char)
        i += 1
    if closing and i >= len(text):
        raise TemplateSyntaxError(f"missing ')' in {text!r}")
    if literal:
        nodes.append("".join(literal))
    return tuple(nodes), i


def _name(text, i):
    match = NAME.match(text, i)
    if not match:
        raise TemplateSyntaxError(f"expected a name at {i} in {text!r}")
    return match.group(0), match.end()


def _placeholder(text, i):
    """Parse after '{'; return (node, index after '}')."""
    if text.startswith("{", i):              # an Excel array constant {"a","b"}: literal
        raise TemplateSyntaxError(f"nested '{{' at {i} in {text!r}")
    if text.startswith("sum:", i):
        axis, i = _name(text, i + 4)
        if not text.startswith("(", i):
            raise TemplateSyntaxError(f"{{sum:{axis}…}} needs (EXPR) in {text!r}")
        body, i = _parse(text, i + 1, closing=")")
        return Sum(axis, body), _close(text, i + 1)
    key, i = _name(text, i)
    if key in SPECIAL and text.startswith("}", i):
        return Special(key), i + 1
    if key == "item" and text.startswith(":", i):
        axis, i = _name(text, i + 1)
        return Special(key, axis), _close(text, i)
    part = argument = unit = None
    if text.startswith(":", i):
        part, i = _name(text, i + 1)
        if part in CALL_PARTS:
            if not text.startswith("(", i):
                raise TemplateSyntaxError(f"{{{key}:{part}…}} needs (EXPR) in {text!r}")
            argument, i = _parse(text, i + 1, closing=")")
            i += 1
        elif part not in PARTS:
            raise TemplateSyntaxError(f"unknown part {part!r} of {{{key}}} in {text!r}; "
                                      f"parts are {', '.join(PARTS + CALL_PARTS)}")
    if text.startswith("|", i):
        end = text.find("}", i)
        if end == -1:
            raise TemplateSyntaxError(f"unterminated placeholder in {text!r}")
        unit, i = text[i + 1:end].strip(), end
    return Ref(key, part, argument, unit), _close(text, i)


def _close(text, i):
    if not text.startswith("}", i):
        raise TemplateSyntaxError(f"expected '}}' at {i} in {text!r}")
    return i + 1


def walk(nodes):
    """Every Ref, Special and Sum node, nested ones included."""
    for node in nodes:
        if isinstance(node, str):
            continue
        yield node
        if isinstance(node, Ref) and node.argument:
            yield from walk(node.argument)
        if isinstance(node, Sum):
            yield from walk(node.body)


def references(text):
    """Keys referred to by a template (nested ones included)."""
    return [n.key for n in walk(parse(text)) if isinstance(n, Ref)]


def unparse(nodes):
    """Template text of a parsed template (inverse of :func:`parse`)."""
    out = []
    for node in nodes:
        if isinstance(node, str):
            out.append(node)
        elif isinstance(node, Special):
            out.append("{" + node.name + (":" + node.axis if node.axis else "") + "}")
        elif isinstance(node, Sum):
            out.append("{sum:" + node.axis + "(" + unparse(node.body) + ")}")
        else:
            text = node.key
            if node.part:
                text += ":" + node.part
                if node.argument is not None:
                    text += "(" + unparse(node.argument) + ")"
            if node.unit:
                text += "|" + node.unit
            out.append("{" + text + "}")
    return "".join(out)


def rename(text, function):
    """The template with every reference key k replaced by function(k)."""
    if text is None:
        return None

    def walk_nodes(nodes):
        out = []
        for node in nodes:
            if isinstance(node, Ref):
                argument = walk_nodes(node.argument) if node.argument is not None else None
                out.append(Ref(function(node.key), node.part, argument, node.unit))
            elif isinstance(node, Sum):
                out.append(Sum(node.axis, walk_nodes(node.body)))
            else:
                out.append(node)
        return tuple(out)
    return unparse(walk_nodes(parse(text)))
