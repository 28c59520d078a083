"""Number spelling on the wire: the server's float formats, the agent's float format, strict number parsing.

Three formats exist and each has one function here so no caller improvises:

* agent-facing server output (sense messages): C++ ``std::fixed`` with precision 2, i.e. printf ``"%.2f"``
  of the perceptor's value (REFERENCE §1). Python's ``f"{x:.2f}"`` rounds the exact binary value half-to-even
  like glibc, so ``-0.001`` gives ``-0.00`` and ``0.125`` gives ``0.12`` exactly as the server prints them.
* monitor output: C++ default ostream formatting (precision 6, ``%g``): ``30``, ``0.042``, ``-8.74228e-08``,
  ``-0``.
* agent output (effectors): plain decimals, never exponents, at most 4 decimals (see
  :func:`format_agent_float` for why).

Parsing is strict (a token must be a decimal number, optionally with an exponent, or a NaN/Inf spelling):
``float()`` alone would accept ``"1_0"``, ``" 1"`` and ``"infinity"`` silently.
"""

from __future__ import annotations

import math
import re
import struct
from functools import cache

from agent.protocol.errors import ProtocolError

#: A decimal with optional sign, fraction and exponent, or a NaN/Inf spelling as C's strtod accepts it.
_FLOAT_TOKEN = re.compile(r"[+-]?(?:(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?|(?i:nan|inf|infinity))\Z")
_INT_TOKEN = re.compile(r"[+-]?\d+\Z")

#: Decimals of :func:`format_agent_float`: 1e-4 rad/s over a 20 ms cycle moves a joint 2e-6 rad, far below
#: the simulator's own noise, while keeping a 22-joint command short.
AGENT_FLOAT_DECIMALS = 4


def _c_non_finite(value: float) -> str:
    """How glibc prints a non-finite double: ``nan``/``-nan``/``inf``/``-inf`` (Python drops NaN's sign)."""
    if math.isnan(value):
        return "-nan" if math.copysign(1.0, value) < 0 else "nan"
    return "inf" if value > 0 else "-inf"


def format_fixed2(value: float) -> str:
    """A perceptor float as the server prints it in sense messages (printf ``"%.2f"``).

    Args:
        value: the value (SimSpark stores perceptor values as float32; pass :func:`round_float32` of a
            physics double to reproduce the server's rounding at exact half-cent boundaries).

    Returns:
        e.g. ``"-0.00"``, ``"104.36"``; non-finite values as glibc prints them (``"nan"``, ``"-inf"``).
    """
    if value - value == 0.0:  # finite; cheaper than math.isfinite on this hot path
        return f"{value:.2f}"
    return _c_non_finite(value)


#: The sense-message float spelling as a printf format (what the templates of sense_format write).
FIXED2 = "%.2f"
#: Hundredths `fixed2_table` spells: values below 400.00 in magnitude (angles, distances, accelerations and
#: most forces; anything else is formatted as usual).
FIXED2_TABLE_HUNDREDTHS = 40_000


@cache
def fixed2_table() -> tuple[bytes, ...]:
    """``FIXED2`` of every hundredth below `FIXED2_TABLE_HUNDREDTHS`, for writers that format many values at once.

    Entry ``m`` is the spelling of ``m / 100`` and entry ``FIXED2_TABLE_HUNDREDTHS + m`` that of ``-m / 100``
    (so index ``FIXED2_TABLE_HUNDREDTHS`` is ``-0.00``). A value whose correctly rounded hundredths are ``m``
    has exactly the spelling of entry ``m`` (or the negative one): printf rounds the exact binary value to the
    nearest hundredth, and the double nearest ``m / 100`` rounds back to ``m / 100``. Looking spellings up
    here costs a fifth of formatting them; sim.fixed2 finds the entries with numpy (built on first use).
    """
    count = FIXED2_TABLE_HUNDREDTHS
    spell = FIXED2.encode("ascii")
    return tuple([spell % (m / 100) for m in range(count)] + [spell % -(m / 100) for m in range(count)])


def format_g6(value: float | int) -> str:
    """A monitor number as C++ ``ostream << value`` prints it (default precision 6, ``%g``).

    Args:
        value: a float (printed ``%g``: ``0.042``, ``-8.74228e-08``, ``-0``) or an int (printed as is).
    """
    if isinstance(value, int):
        return str(value)
    if value - value == 0.0:
        return f"{value:g}"
    return _c_non_finite(value)


def format_agent_float(value: float) -> str:
    """An effector value as this project sends it: plain decimal, at most 4 decimals, trailing zeros cut.

    Why this shape: the server parses effector values as plain decimals and whether it accepts exponent
    notation is unverified (REFERENCE §1), so ``repr()`` (``1e-05``) is out; 4 decimals are far below any
    physical effect (see :data:`AGENT_FLOAT_DECIMALS`); trimming keeps ``(beam -2.5 0 0)`` as agents write
    it. ``-0`` is written ``0``.

    Raises:
        ProtocolError: NaN or Inf (the server would reject them; offset 0, snippet the value's repr).
    """
    if value - value != 0.0:
        raise ProtocolError(f"effector value must be finite, got {value!r}", 0, repr(value).encode())
    text = f"{value:.{AGENT_FLOAT_DECIMALS}f}".rstrip("0").rstrip(".")
    return "0" if text == "-0" else text


def round_float32(value: float) -> float:
    """``value`` rounded to the nearest float32, as SimSpark stores perceptor values before printing."""
    return struct.unpack("<f", struct.pack("<f", value))[0]


def parse_float(token: str, offset: int, data: bytes | str | None = None) -> float:
    """A float token, strictly; NaN and Inf parse (callers flag them with ``math.isfinite``).

    Args:
        token: the atom, e.g. ``"-0.00"``, ``"1e-3"``, ``"nan"``.
        offset: byte offset of the token in its message (for the error).
        data: the whole message, to cut the error snippet from; the token itself is used when omitted.

    Raises:
        ProtocolError: the token is not a number.
    """
    if _FLOAT_TOKEN.match(token) is None:
        raise _bad_token("float", token, offset, data)
    return float(token)


def parse_finite_float(token: str, offset: int, data: bytes | str | None = None) -> float:
    """Like :func:`parse_float`, but NaN and Inf are errors too (perceptor values are always finite)."""
    value = parse_float(token, offset, data)
    if value - value != 0.0:
        raise _bad_token("finite float", token, offset, data)
    return value


def parse_int(token: str, offset: int, data: bytes | str | None = None) -> int:
    """An integer token (``"3"``, ``"-1"``), strictly.

    Raises:
        ProtocolError: the token is not an integer.
    """
    if _INT_TOKEN.match(token) is None:
        raise _bad_token("integer", token, offset, data)
    return int(token)


def _bad_token(kind: str, token: str, offset: int, data: bytes | str | None) -> ProtocolError:
    if data is None:
        return ProtocolError(f"expected a {kind}, got {token!r}", offset, token.encode("latin-1", "replace"))
    return ProtocolError.at(f"expected a {kind}, got {token!r}", data, offset)
