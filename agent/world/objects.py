"""Objects the world model tracks: the ball, teammates, opponents and landmarks, each with its last sighting.

Every position exists twice: egocentric (forward, left of the torso's ground point, at the last sighting)
and in the team frame (through the self pose at that time, or as a teammate reported it). ``seen_s`` is
the server time of the sighting or report; ``age_s(now)`` tells how old it is.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class Tracked:
    """One object at its last sighting."""

    forward_m: float | None
    """Ego x at the sighting [m] (None for reports heard from teammates)."""
    left_m: float | None
    """Ego y at the sighting [m]."""
    x_m: float | None
    """Team-frame x [m] (None when the self pose was unknown at the sighting)."""
    y_m: float | None
    """Team-frame y [m]."""
    seen_s: float
    """Server time of the sighting or report [s]."""
    source: str = "vision"
    """``vision``, ``say`` (a teammate's message) or ``referee`` (where a rule put the ball, not seen yet)."""

    def age_s(self, now_s: float) -> float:
        """Seconds since the sighting."""
        return now_s - self.seen_s

    @property
    def position(self) -> tuple[float, float] | None:
        """Team-frame (x, y), or None."""
        return None if self.x_m is None else (self.x_m, self.y_m)  # type: ignore[return-value]

    @property
    def distance_m(self) -> float | None:
        """Ground distance at the sighting [m], None for reports."""
        return None if self.forward_m is None else math.hypot(self.forward_m, self.left_m)  # type: ignore[arg-type]

    @property
    def bearing_rad(self) -> float | None:
        """Ego direction at the sighting [rad], 0 = forward, positive left; None for reports."""
        return None if self.forward_m is None else math.atan2(self.left_m, self.forward_m)  # type: ignore[arg-type]


@dataclass(frozen=True, slots=True)
class TeammateReport:
    """What a teammate said about itself in its last message (REFERENCE §7.9 message types)."""

    unum: int
    """The speaker."""
    kind: str
    """Message type letter (``c``, ``l``, ``b``, ``x``, ``i``...)."""
    heard_s: float
    """Server time when heard [s]."""
    game_time_s: float
    """Game time the speaker said it at [s] (from the hear perceptor)."""
    position: tuple[float, float] | None = None
    """The speaker's team-frame position [m] (c, l)."""
    ball: tuple[float, float] | None = None
    """The ball's team-frame position as the speaker sees it [m] (c)."""
    ball_polar: tuple[float, float] | None = None
    """(distance [m], direction [rad]) of the ball from the speaker (b)."""
    active: bool = True
    """False after an ``x`` message (fallen or lost)."""
