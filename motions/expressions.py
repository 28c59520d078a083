"""Arithmetic over named constants, as FIIT's XML phase files write angles and durations.

Why: FIIT's motion files declare ``<constant name="strafe_leg_crouch" value="30"/>`` and then write
``<rle3 end="strafe_leg_crouch+30"/>`` or ``<rle4 end="-2*strafe_leg_crouch"/>`` (the robocup-fiit Jim
agent's loader substitutes the constants and evaluates the arithmetic for ``end`` and ``<duration>``).
Here the text is read as tokens, so a constant named ``a`` never matches inside ``a_b`` as a textual
substitution would, and nothing is ever handed to Python's ``eval``.

Grammar: ``expr := term (('+' | '-') term)*``, ``term := factor (('*' | '/') factor)*``,
``factor := ('+' | '-') factor | NUMBER | NAME | '(' expr ')'``; NUMBER is a decimal (``30``, ``-7.5``,
``1e-3``), NAME a constant (``[A-Za-z_][A-Za-z0-9_.]*``).
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping

_TOKEN = re.compile(r"(?:(?P<number>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)|(?P<name>[A-Za-z_][A-Za-z0-9_.]*)"
                    r"|(?P<op>[-+*/()]))")


class ExpressionError(ValueError):
    """An expression that cannot be read or evaluated; the message says what and where in the text."""


def _tokens(text: str) -> list[tuple[str, str, int]]:
    """(kind, text, character offset) per token; kind is number, name or op."""
    tokens: list[tuple[str, str, int]] = []
    position = 0
    while position < len(text):
        if text[position].isspace():
            position += 1
            continue
        match = _TOKEN.match(text, position)
        if match is None:
            raise ExpressionError(f"unexpected {text[position]!r} at character {position + 1}")
        kind = match.lastgroup or "op"
        tokens.append((kind, match.group(kind), match.start(kind)))
        position = match.end()
    return tokens


class _Parser:
    def __init__(self, text: str, constants: Mapping[str, float]) -> None:
        self.constants = constants
        self.tokens = _tokens(text)
        self.index = 0

    def peek(self) -> tuple[str, str, int] | None:
        return self.tokens[self.index] if self.index < len(self.tokens) else None

    def take(self) -> tuple[str, str, int]:
        token = self.peek()
        if token is None:
            raise ExpressionError("the expression ends too early")
        self.index += 1
        return token

    def expression(self) -> float:
        value = self.term()
        while (token := self.peek()) is not None and token[1] in "+-" and token[0] == "op":
            self.take()
            value = value + self.term() if token[1] == "+" else value - self.term()
        return value

    def term(self) -> float:
        value = self.factor()
        while (token := self.peek()) is not None and token[1] in "*/" and token[0] == "op":
            self.take()
            right = self.factor()
            if token[1] == "*":
                value *= right
            elif right == 0.0:
                raise ExpressionError(f"division by zero at character {token[2] + 1}")
            else:
                value /= right
        return value

    def factor(self) -> float:
        kind, text, offset = self.take()
        if kind == "op" and text in "+-":
            value = self.factor()
            return value if text == "+" else -value
        if kind == "number":
            return float(text)
        if kind == "name":
            if text not in self.constants:
                known = ", ".join(sorted(self.constants)) or "none declared"
                raise ExpressionError(f"unknown constant {text!r} (constants: {known})")
            return float(self.constants[text])
        if text == "(":
            value = self.expression()
            closing = self.take()
            if closing[1] != ")":
                raise ExpressionError(f"expected ')' at character {closing[2] + 1}, got {closing[1]!r}")
            return value
        raise ExpressionError(f"unexpected {text!r} at character {offset + 1}")


def evaluate(text: str, constants: Mapping[str, float]) -> float:
    """The value of ``text`` with ``constants`` substituted.

    Raises:
        ExpressionError: a character that is no number, name, operator or parenthesis; an unknown constant
            (the message lists the known ones); unbalanced parentheses; a division by zero; a result that is
            not finite.
    """
    parser = _Parser(text, constants)
    if not parser.tokens:
        raise ExpressionError("empty expression")
    value = parser.expression()
    extra = parser.peek()
    if extra is not None:
        raise ExpressionError(f"unexpected {extra[1]!r} at character {extra[2] + 1}")
    if not math.isfinite(value):
        raise ExpressionError(f"the value is not finite ({value})")
    return value


__all__ = ["ExpressionError", "evaluate"]
