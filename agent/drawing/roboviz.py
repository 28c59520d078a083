"""RoboViz's UDP draw protocol (REFERENCE §5.5), one function per packet: pure, bytes out.

A packet is ``[command byte][sub byte]`` + payload. Numbers are 6 ASCII characters (``"%6f"`` cut to 6, as
RoboViz reads them: ``1.5000``, ``-2.000``, ``15.300``), colours 3 (RGB) or 4 (RGBA) bytes, names and texts
NUL-terminated. Coordinates are SimSpark field coordinates [m]. Shapes go into a named set and show once
that set's buffer is swapped (`swap_buffers`), so a frame is drawn whole or not at all.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

#: Command and sub-command bytes (RoboViz rv.comm.drawing.commands).
OPTION, SHAPE, ANNOTATION, CONTROL = 0, 1, 2, 3
SWAP_BUFFERS = 0
CIRCLE, LINE, POINT, SPHERE, POLYGON = 0, 1, 2, 3, 4
STANDARD_ANNOTATION, AGENT_ANNOTATION, AGENT_ANNOTATION_CLEAR = 0, 1, 2

Colour = tuple[int, int, int]
ColourAlpha = tuple[int, int, int, int]


def number(value: float) -> bytes:
    """A float in RoboViz's 6-character spelling.

    Raises:
        ValueError: not finite, or too large to keep its integer part in 6 characters (|value| >= 99999.5).
    """
    if not math.isfinite(value) or abs(value) >= 99999.5:
        raise ValueError(f"a RoboViz number must be finite and below 99999.5 in magnitude, got {value!r}")
    return f"{value:6f}"[:6].encode("ascii")


def _numbers(values: Sequence[float]) -> bytes:
    return b"".join(number(v) for v in values)


def _colour(colour: Sequence[int]) -> bytes:
    if not all(0 <= c <= 255 for c in colour):
        raise ValueError(f"colour components must be 0-255, got {tuple(colour)}")
    return bytes(colour)


def _text(text: str) -> bytes:
    data = text.encode("utf-8")
    if b"\0" in data:
        raise ValueError(f"a RoboViz name or text cannot hold NUL, got {text!r}")
    return data + b"\0"


def swap_buffers(set_name: str) -> bytes:
    """Show what was drawn into every set whose name starts with ``set_name`` since its last swap."""
    return bytes((OPTION, SWAP_BUFFERS)) + _text(set_name)


def circle(center_xy_m: tuple[float, float], radius_m: float, thickness_px: float, colour: Colour,
           set_name: str) -> bytes:
    """A circle on the ground (z 0)."""
    return bytes((SHAPE, CIRCLE)) + _numbers((*center_xy_m, radius_m, thickness_px)) + _colour(colour) + _text(set_name)


def line(start_m: tuple[float, float, float], end_m: tuple[float, float, float], thickness_px: float,
         colour: Colour, set_name: str) -> bytes:
    """A line segment between two field points."""
    return bytes((SHAPE, LINE)) + _numbers((*start_m, *end_m, thickness_px)) + _colour(colour) + _text(set_name)


def point(position_m: tuple[float, float, float], size_px: float, colour: Colour, set_name: str) -> bytes:
    """A point of ``size_px`` pixels."""
    return bytes((SHAPE, POINT)) + _numbers((*position_m, size_px)) + _colour(colour) + _text(set_name)


def sphere(center_m: tuple[float, float, float], radius_m: float, colour: Colour, set_name: str) -> bytes:
    """A solid sphere."""
    return bytes((SHAPE, SPHERE)) + _numbers((*center_m, radius_m)) + _colour(colour) + _text(set_name)


def polygon(vertices_m: Sequence[tuple[float, float, float]], colour: ColourAlpha, set_name: str) -> bytes:
    """A filled convex polygon (3-255 vertices), RGBA colour."""
    if not 3 <= len(vertices_m) <= 255:
        raise ValueError(f"a polygon needs 3-255 vertices, got {len(vertices_m)}")
    return (bytes((SHAPE, POLYGON, len(vertices_m))) + _colour(colour)
            + b"".join(_numbers(v) for v in vertices_m) + _text(set_name))


def annotation(text: str, position_m: tuple[float, float, float], colour: Colour, set_name: str) -> bytes:
    """Text at a field point."""
    return bytes((ANNOTATION, STANDARD_ANNOTATION)) + _numbers(position_m) + _colour(colour) + _text(text) + _text(set_name)


def _agent_byte(side: str, unum: int) -> int:
    """RoboViz's team-and-agent byte: team (left 0, right 1) x 128 + unum - 1."""
    if side not in ("left", "right") or not 1 <= unum <= 11:
        raise ValueError(f"need side left/right and unum 1-11, got {side!r}, {unum!r}")
    return (0 if side == "left" else 128) + unum - 1


def agent_annotation(side: str, unum: int, text: str, colour: Colour) -> bytes:
    """Text that RoboViz keeps above this robot (replaces the robot's previous one; no buffer swap)."""
    return bytes((ANNOTATION, AGENT_ANNOTATION, _agent_byte(side, unum))) + _colour(colour) + _text(text)


def agent_annotation_clear(side: str, unum: int) -> bytes:
    """Remove the text above this robot."""
    return bytes((ANNOTATION, AGENT_ANNOTATION_CLEAR, _agent_byte(side, unum)))
