"""Number text in motion files: strict parsing and shortest exact formatting.

Readers must not accept what the playing agents would misread (Python's ``float`` takes ``nan``, ``inf`` and
``1_0``), and writers must give back numbers that read as the same float, written the way people write
them (``46``, ``-7.5``, never ``46.0`` or ``1e-05``), so re-saving a file does not rewrite every value.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from decimal import Decimal

_DECIMAL = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")
_INTEGER = re.compile(r"[+-]?\d+")


def parse_decimal(text: str) -> float | None:
    """A finite float from plain decimal text (optional exponent), None if the text is not such a number.

    Surrounding whitespace is allowed (Java's ``Float.parseFloat`` trims it); ``nan``, ``inf``, hex and
    digit separators are not.
    """
    stripped = text.strip()
    if not _DECIMAL.fullmatch(stripped):
        return None
    value = float(stripped)
    return value if math.isfinite(value) else None


def parse_integer(text: str) -> int | None:
    """An integer from decimal digit text with optional sign and surrounding whitespace, None otherwise."""
    stripped = text.strip()
    return int(stripped) if _INTEGER.fullmatch(stripped) else None


def _positional(text: str) -> str:
    """Decimal text without exponent, trailing zeros or a trailing point (``4.60e+01`` -> ``46``)."""
    fixed = format(Decimal(text), "f")
    if "." in fixed:
        fixed = fixed.rstrip("0").rstrip(".")
    if fixed in ("-0", ""):
        fixed = "0"
    return fixed


def shortest_decimal(value: float, reads_back: Callable[[float], bool] | None = None) -> str:
    """The shortest positional decimal text whose float satisfies ``reads_back`` (default: equals ``value``).

    Args:
        value: the number to write; finite.
        reads_back: test applied to ``float(candidate)``; lets a caller ask for text that converts back
            exactly through a unit change (degrees in the file, radians inside).

    Returns:
        Text such as ``"46"``, ``"-7.5"``, ``"0.00001"``. If no candidate up to 17 significant digits passes
        (a unit change can make a float unreachable), the 17-digit text of ``value``: then the read-back
        differs from the original by about one unit in the last place.
    """
    if not math.isfinite(value):
        raise ValueError(f"cannot write a non-finite number: {value!r}")
    test = reads_back if reads_back is not None else (lambda x: x == value)
    for digits in range(1, 18):
        candidate = _positional(f"{value:.{digits}g}")
        if test(float(candidate)):
            return candidate
    return _positional(f"{value:.17g}")


def degrees_text_for_rad(angle_rad: float) -> str:
    """Shortest degree text that reads back (via ``math.radians``) as exactly ``angle_rad`` where possible."""
    return shortest_decimal(math.degrees(angle_rad), lambda deg: math.radians(deg) == angle_rad)


def is_whole(value: float, tolerance: float = 1e-6) -> bool:
    """Whether ``value`` is an integer up to ``tolerance`` (durations in ms after float arithmetic)."""
    return abs(value - round(value)) <= tolerance
