"""One walk on our simulator, measured: the real agent plays a walk motion (``PlayMotion`` with
``repeat=True``) from a standstill, optionally leaning or pushed, then is asked to stop (the walk leaves
through its ``finalize`` stop phases); ground truth gives the figures. Shared by the gait tuner and the walk
benchmark.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

from agent.motion import MotionController, MotionLibrary
from agent.motion.dynamic import DynamicParams
from agent.skills.base import PlayMotion
from motion_studio.scenarios import Scenario, Truth
from agent.protocol.constants import CYCLE_S

#: Where walk runs put the ball: by the touch line, off every walk's path (left at the centre spot, it lay
#: under a robot started there and on the forward runs' line) [m].
BALL_AWAY_M = (0.0, 9.8)


@dataclass(frozen=True)
class Push:
    """A push: at ``time_s`` after the walk request, add ``velocity_m_s`` (robot frame: forward, left) to
    the torso."""

    time_s: float
    forward_m_s: float = 0.0
    left_m_s: float = 0.0


def apply_due_pushes(scenario: Scenario, pending: list[Push], time_s: float) -> None:
    """Give the robot every push of ``pending`` (sorted by time) that is due at ``time_s`` [s] and drop it
    from the list; the push's robot-frame velocity is turned into the world frame by the current heading."""
    while pending and time_s >= pending[0].time_s:
        push = pending.pop(0)
        heading = math.radians(scenario.truth().heading_deg)
        c, s = math.cos(heading), math.sin(heading)
        scenario.push((c * push.forward_m_s - s * push.left_m_s, s * push.forward_m_s + c * push.left_m_s, 0.0))


@dataclass
class WalkRun:
    """A measured walk. Distances in the start frame of the robot (forward = start heading, left)."""

    motion: str
    lean: float
    truths: list[Truth] = field(repr=False)
    walk_cycles: int
    """Cycles with the walk requested (the rest is the stop)."""
    fall_cycle: int | None
    """Index into ``truths`` of the first fallen cycle (REFERENCE §8.1 criterion), None if none."""
    start_heading_deg: float

    def _frame(self, truth: Truth) -> tuple[float, float]:
        x0, y0, _ = self.truths[0].torso_m
        dx, dy = truth.torso_m[0] - x0, truth.torso_m[1] - y0
        c, s = math.cos(math.radians(self.start_heading_deg)), math.sin(math.radians(self.start_heading_deg))
        return c * dx + s * dy, -s * dx + c * dy

    @property
    def fell(self) -> bool:
        """Fell while walking."""
        return self.fall_cycle is not None and self.fall_cycle < self.walk_cycles

    @property
    def fell_stopping(self) -> bool:
        """Fell after the stop request."""
        return self.fall_cycle is not None and self.fall_cycle >= self.walk_cycles

    @property
    def walk_end(self) -> Truth:
        """The last walking cycle (or the fall)."""
        end = self.walk_cycles - 1 if self.fall_cycle is None else min(self.fall_cycle, self.walk_cycles - 1)
        return self.truths[max(0, end)]

    @property
    def walk_time_s(self) -> float:
        return self.walk_cycles * CYCLE_S

    def displacement_m(self, truth: Truth | None = None) -> tuple[float, float]:
        """(forward, left) of ``truth`` (default: the end of the walk) from the start [m]."""
        return self._frame(truth or self.walk_end)

    def steady_velocity_m_s(self, skip_s: float = 3.0) -> tuple[float, float]:
        """(forward, left) mean velocity after the first ``skip_s`` of walking (start ramp excluded) [m/s];
        over the walk up to a fall, (0, 0) if too short."""
        start = min(int(skip_s / CYCLE_S), len(self.truths) - 1)
        end_truth = self.walk_end
        end = self.truths.index(end_truth)
        if end - start < 25:
            return 0.0, 0.0
        a, b = self._frame(self.truths[start]), self._frame(end_truth)
        elapsed = (end - start) * CYCLE_S
        return (b[0] - a[0]) / elapsed, (b[1] - a[1]) / elapsed

    @property
    def heading_change_deg(self) -> float:
        """Heading at the end of the walk minus the start heading [deg], wrapped to (-180, 180]."""
        change = self.walk_end.heading_deg - self.start_heading_deg
        return (change + 180.0) % 360.0 - 180.0

    @property
    def curvature_deg_m(self) -> float:
        """Heading change per metre walked (+ = curving left) [deg/m]."""
        path = self.path_length_m(self.walk_cycles)
        return self.heading_change_deg / path if path > 0.05 else 0.0

    def path_length_m(self, cycles: int) -> float:
        """Length of the torso's ground path over the first ``cycles``, sampled every 10 cycles [m]."""
        points = [t.torso_m[:2] for t in self.truths[:cycles:10]]
        return sum(math.dist(a, b) for a, b in zip(points, points[1:]))

    @property
    def feet_off_fraction(self) -> float:
        """Fraction of walking cycles with both feet off the ground (run challenge bonus)."""
        cycles = self.truths[:self.walk_cycles]
        return sum(t.feet_off_ground for t in cycles) / max(1, len(cycles))

    @property
    def settled(self) -> bool:
        """Stopped standing: no fall, and the torso moved < 2 cm over the last 0.5 s."""
        if self.fall_cycle is not None or len(self.truths) <= self.walk_cycles + 25:
            return False
        return math.dist(self.truths[-25].torso_m[:2], self.truths[-1].torso_m[:2]) < 0.02


def make_controller(library: MotionLibrary, dynamic: DynamicParams | None = None,
                    robot_type: int = 0) -> MotionController:
    """A motion controller over ``library`` for ``robot_type`` (its joints, ranges and speeds) with the shipped
    dynamic elements unless given."""
    from agent.motion import load_dynamic_params

    return MotionController(library, dynamic or load_dynamic_params(), robot_type)


def run_walk(library: MotionLibrary, motion: str, duration_s: float, *, position_m: tuple[float, float] = (-13.5, 0.0),
             heading_deg: float = 0.0, lean: float = 0.0, pushes: Sequence[Push] = (), stop_s: float = 2.0,
             x_limit_m: float | None = 14.5, dynamic: DynamicParams | None = None, seed: int = 0,
             ball_m: tuple[float, float] | None = BALL_AWAY_M, robot_type: int = 0) -> WalkRun:
    """Play ``motion`` for ``duration_s`` (or until a fall or the torso passes ``x_limit_m``), then request no
    motion for ``stop_s`` (the walk finalizes into its stop phases).

    Raises:
        KeyError: ``motion`` is not in the library.
    """
    library.get(motion)
    controller = make_controller(library, dynamic, robot_type)
    request = {"lean": lean} if lean else {}
    scenario = Scenario(PlayMotion(motion, repeat=True, **request), position_m=position_m, heading_deg=heading_deg,
                        controller=controller, recover_falls=False, seed=seed, ball_m=ball_m, robot_type=robot_type)
    truths: list[Truth] = []
    fall_cycle = None
    pending = sorted(pushes, key=lambda p: p.time_s)
    cycles = int(round(duration_s / CYCLE_S))
    walk_cycles = cycles
    for index in range(cycles):
        apply_due_pushes(scenario, pending, index * CYCLE_S)
        truth = scenario.run(1)[0]
        truths.append(truth)
        if truth.fallen:
            fall_cycle = index
            walk_cycles = index + 1
            break
        if x_limit_m is not None and truth.torso_m[0] >= x_limit_m:
            walk_cycles = index + 1
            break
    if fall_cycle is None:
        scenario.set_skill(None)
        for offset, truth in enumerate(scenario.run(int(round(stop_s / CYCLE_S)))):
            truths.append(truth)
            if truth.fallen:
                fall_cycle = walk_cycles + offset
                break
    return WalkRun(motion, lean, truths, walk_cycles, fall_cycle, heading_deg)


__all__ = ["BALL_AWAY_M", "Push", "WalkRun", "make_controller", "run_walk"]
