"""The ball's velocity and where it will come to rest, from its recent team-frame sightings.

Why: a pushed or kicked ball rolls on for metres, and a player that walks at the ball's last sighting walks
behind a moving target: it re-plans every frame and arrives where the ball was. The roll is simple enough to
predict: SimSpark's ball rolls at once (μ = ∞ with force-dependent slip) and slows by drag alone, so its speed
decays exponentially at ``ROLL_DECAY_PER_S``: measured on the real rcssserver3d 0.7.3, a ball launched at v
along the ground stops after 0.677 m per m/s, that is (5/7)·v/k with 5/7 of the launch speed left once it
rolls, so k = 1.055 /s (sim.physics_params gives the same on ours: +1.1 %). A rolling ball at speed v therefore
comes to rest v/k further on.

The velocity is the least-squares slope of the sightings within ``WINDOW_S`` (vision every 3 cycles, a few cm
of noise each: about 0.1 m/s of velocity noise over 0.5 s); a sighting that jumps farther than a ball can roll
(the referee put the ball elsewhere) starts the track afresh. Positions in the team frame [m], times in server
seconds.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field

#: Exponential speed decay of a rolling ball [1/s] (see the module docstring: 0.677 m per m/s launched).
ROLL_DECAY_PER_S = (5.0 / 7.0) / 0.677
#: Sightings used for the velocity fit [s].
WINDOW_S = 0.5
#: At least this many sightings spanning at least ``MIN_SPAN_S`` give a velocity.
MIN_SAMPLES = 4
MIN_SPAN_S = 0.2
#: Slower than this the ball counts as lying still [m/s] (the velocity noise of a lying ball stays below it).
STILL_M_S = 0.25
#: A sighting this much farther from the fitted track than a kicked ball could get in the time between (12 m/s)
#: plus this margin [m] restarts the track (the ball was placed elsewhere).
JUMP_MARGIN_M = 0.5
FASTEST_BALL_M_S = 12.0


@dataclass
class BallTrack:
    """Recent ball sightings and what they say about its motion; see the module docstring."""

    samples: deque[tuple[float, float, float]] = field(default_factory=deque)
    """(server time [s], x [m], y [m]) of the sightings within ``WINDOW_S`` of the newest."""

    def add(self, time_s: float, x_m: float, y_m: float) -> None:
        """A new sighting (team frame); older ones leave the window, an impossible jump restarts the track."""
        if self.samples:
            last_t, last_x, last_y = self.samples[-1]
            reach = FASTEST_BALL_M_S * max(0.0, time_s - last_t) + JUMP_MARGIN_M
            if time_s < last_t or math.hypot(x_m - last_x, y_m - last_y) > reach:
                self.samples.clear()
        self.samples.append((time_s, x_m, y_m))
        while self.samples and self.samples[0][0] < time_s - WINDOW_S:
            self.samples.popleft()

    def clear(self) -> None:
        self.samples.clear()

    def _fit(self) -> tuple[float, float, float, float, float] | None:
        """(t_newest, x, y at t_newest, vx, vy) of the least-squares line through the samples, or None."""
        if len(self.samples) < MIN_SAMPLES or self.samples[-1][0] - self.samples[0][0] < MIN_SPAN_S:
            return None
        n = len(self.samples)
        t_mean = sum(s[0] for s in self.samples) / n
        x_mean = sum(s[1] for s in self.samples) / n
        y_mean = sum(s[2] for s in self.samples) / n
        stt = sum((s[0] - t_mean) ** 2 for s in self.samples)
        vx = sum((s[0] - t_mean) * (s[1] - x_mean) for s in self.samples) / stt
        vy = sum((s[0] - t_mean) * (s[2] - y_mean) for s in self.samples) / stt
        # The slope is the mean velocity over the window, i.e. the velocity at its mean time; the roll has
        # slowed since by exp(-k dt) and covered (1 - exp(-k dt)) / k of that velocity.
        t_new = self.samples[-1][0]
        dt = t_new - t_mean
        share = (1.0 - math.exp(-ROLL_DECAY_PER_S * dt)) / ROLL_DECAY_PER_S
        decay = math.exp(-ROLL_DECAY_PER_S * dt)
        return t_new, x_mean + vx * share, y_mean + vy * share, vx * decay, vy * decay

    def velocity_m_s(self) -> tuple[float, float] | None:
        """The ball's velocity at its newest sighting (team frame) [m/s]; (0, 0) when it lies still; None
        without enough recent sightings."""
        fit = self._fit()
        if fit is None:
            return None
        vx, vy = fit[3], fit[4]
        return (0.0, 0.0) if math.hypot(vx, vy) < STILL_M_S else (vx, vy)

    def rest_point(self) -> tuple[float, float] | None:
        """Where the ball will lie still (team frame) [m]: the fitted position plus v / ``ROLL_DECAY_PER_S``;
        None without enough recent sightings."""
        return self.position_after(math.inf)

    def position_after(self, dt_s: float) -> tuple[float, float] | None:
        """Where the ball will be ``dt_s`` after its newest sighting (team frame) [m]; None as above."""
        fit = self._fit()
        if fit is None:
            return None
        _, x, y, vx, vy = fit
        if math.hypot(vx, vy) < STILL_M_S:
            return self.samples[-1][1], self.samples[-1][2]
        share = (1.0 - math.exp(-ROLL_DECAY_PER_S * max(0.0, dt_s))) / ROLL_DECAY_PER_S
        return x + vx * share, y + vy * share

    def crossing_y(self, line_x_m: float) -> float | None:
        """y at which the ball will cross the line x = ``line_x_m`` before it stops (a keeper's intercept on
        its goal line) [m]; None if it will not reach the line or lacks a velocity."""
        fit = self._fit()
        if fit is None:
            return None
        _, x, y, vx, vy = fit
        if math.hypot(vx, vy) < STILL_M_S or abs(vx) < 1e-6:
            return None
        travel_x = vx / ROLL_DECAY_PER_S
        needed = line_x_m - x
        if needed * vx <= 0.0 or abs(needed) > abs(travel_x):
            return None
        return y + vy * needed / vx


__all__ = ["BallTrack", "ROLL_DECAY_PER_S"]
