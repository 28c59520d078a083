"""The seed agent's localization filter, REFERENCE §7.5 Algorithm 1: a FIFO of the last estimates, mean out.

On a new estimate e:
1. empty queue -> push e;
2. e farther than ``agree_m`` (2 m, 2012 code) from the current mean -> drop e and pop the oldest entry, so a
   persistent true jump (a beam, a referee move) empties the queue and the belief restarts there;
3. else -> if full pop the oldest, then push e.
The belief is the mean (circular mean for the heading, as the 2012 code does).

Quirks, kept as options so the seed's numbers can be reproduced:
* ``pop_without_push_when_full`` (2012 code): a full queue pops and does not push, so the belief then only
  changes every other agreeing estimate. Off by default (the thesis text).
* The agreement test looks at position only; a heading jump (a turn) is always accepted and averaged in,
  so a turning robot's heading lags by up to half the queue length in frames. Not fixed: it is the seed.
* Nothing ages out: a robot that sees no landmarks keeps its old mean.
"""

from __future__ import annotations

import math
from collections import deque

from agent.world.frames import Pose2D, circular_mean_rad, wrap_angle_rad

MAX_SIZE = 10
AGREE_M = 2.0
#: "Well localized" = at least this many entries (2012 code; chooses the team message type, §7.9).
WELL_LOCALIZED_SIZE = 5


class FifoFilter:
    """Algorithm 1 over (x, y, heading) estimates; also usable for the ball with ``heading`` ignored.

    Args:
        max_size: queue length (10).
        agree_m: agreement gate on the position [m] (2).
        pop_without_push_when_full: reproduce the 2012 code's full-queue quirk.
    """

    def __init__(self, max_size: int = MAX_SIZE, agree_m: float = AGREE_M,
                 pop_without_push_when_full: bool = False) -> None:
        self.max_size = max_size
        self.agree_m = agree_m
        self.pop_without_push_when_full = pop_without_push_when_full
        self.queue: deque[Pose2D] = deque()
        self._mean: Pose2D | None = None

    def reset(self) -> None:
        """Forget every estimate."""
        self.queue.clear()
        self._mean = None

    def add(self, estimate: Pose2D) -> Pose2D | None:
        """Feed one estimate; returns the new belief (None once a disagreement emptied the queue)."""
        queue, mean = self.queue, self._mean
        if not queue or mean is None:
            queue.append(estimate)
        elif math.hypot(estimate.x_m - mean.x_m, estimate.y_m - mean.y_m) > self.agree_m:
            queue.popleft()
        elif len(queue) >= self.max_size:
            queue.popleft()
            if not self.pop_without_push_when_full:
                queue.append(estimate)
        else:
            queue.append(estimate)
        self._mean = self._compute_mean()
        return self._mean

    def _compute_mean(self) -> Pose2D | None:
        n = len(self.queue)
        if n == 0:
            return None
        heading = circular_mean_rad([p.heading_rad for p in self.queue])
        return Pose2D(sum(p.x_m for p in self.queue) / n, sum(p.y_m for p in self.queue) / n,
                      wrap_angle_rad(heading))

    @property
    def mean(self) -> Pose2D | None:
        """The belief, or None before the first estimate."""
        return self._mean

    @property
    def well_localized(self) -> bool:
        """At least :data:`WELL_LOCALIZED_SIZE` agreeing estimates in the queue."""
        return len(self.queue) >= WELL_LOCALIZED_SIZE
