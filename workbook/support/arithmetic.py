"""Arithmetic on numbers and names from data files, without eval.

Used where a data file states a small formula (an assignment's derived variant,
``heat_released = 2.1*pi/4*bore**2*stroke/1000``): + − * / ** and parentheses,
numbers, ``pi`` and the names given.
"""
import ast
import math
import operator

OPERATORS = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul,
             ast.Div: operator.truediv, ast.Pow: operator.pow}


class ArithmeticError_(ValueError):
    """A formula that is not plain arithmetic on the given names."""


def evaluate(text, names=None):
    """The value of ``text`` with ``names`` (and pi) bound; ArithmeticError_ otherwise."""
    names = {"pi": math.pi, **(names or {})}

    def value(node):
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and \
                not isinstance(node.value, bool):
            return node.value
        if isinstance(node, ast.Name) and node.id in names:
            return names[node.id]
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            operand = value(node.operand)
            return -operand if isinstance(node.op, ast.USub) else operand
        if isinstance(node, ast.BinOp) and type(node.op) in OPERATORS:
            return OPERATORS[type(node.op)](value(node.left), value(node.right))
        raise ArithmeticError_(f"{text!r}: only numbers, + − * / ** and the names "
                               f"{', '.join(sorted(names))} are allowed")
    try:
        return value(ast.parse(text, mode="eval").body)
    except SyntaxError:
        raise ArithmeticError_(f"{text!r} is not an arithmetic formula") from None


def integer(text):
    """The value of a constant integer expression such as '2+1', or None."""
    try:
        result = evaluate(text, {})
    except (ArithmeticError_, ZeroDivisionError, OverflowError):
        return None
    return result if isinstance(result, int) else None
