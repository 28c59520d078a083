"""Walk rollouts on the real rcssserver3d 0.7.3, measured as our simulator's (``motion_studio.walk_rollout``):
the gait tuner's real backend (``motion-studio tune gait walk_forward --backend real|both``).

Why a subclass of the kick bench: a walk needs exactly its server handling (one server in this process's
private loopback namespace, trainer commands landing in a fixed cycle, the robot played into its stance and
moved upright by the trainer between rollouts, the ball parked, the monitor's frames followed from a full
state); only the rollout differs. A rollout (:meth:`RealWalkBench.walk`):

1. reset as the kick bench's: ``stand`` where the robot is, ``(playMode PlayOn)``, ``(time 0)``, the trainer
   move upright to the trial's start facing its heading, ``settle_cycles`` of ``stand``; the ball waits at
   ``walk_rollout.BALL_AWAY_M`` (by the touch line, as on ours);
2. the walk (``PlayMotion(motion, repeat=True, lean=...)``, the shipped dynamic elements) for the trial's
   duration, cut short once the agent itself has felt fallen for ``FALLEN_CYCLES``;
3. the stop: no motion requested for ``stop_s`` (the walk leaves through its stop phases).

The figures come from the monitor's truth through :func:`walk_run`, which cuts the run as ``run_walk`` does
(the first fallen cycle, the torso past ``x_limit_m``), so ``tune_gait.trial_score`` scores both servers alike.
The real server never runs in tests: :func:`walk_run` is the part they check, on a recorded real walk.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

from agent.motion import MotionLibrary
from agent.skills.base import PlayMotion
from motion_studio.realserver.rollout_kick import RealKickBench, RealKickConfig, parse_truth, sample_truth
from motion_studio.scenarios import Truth
from motion_studio.walk_rollout import BALL_AWAY_M, WalkRun
from agent.protocol.constants import CYCLE_S

#: The agent's own fall sense (its up axis below 0.6) this many cycles in a row ends the walk early: the robot
#: lies there for good (the trial is scored as a fall from the truth either way), and the rest would cost time.
FALLEN_CYCLES = 25


def walk_run(truths: Sequence[Truth | None], motion: str, lean: float, walk_cycles: int, heading_deg: float,
             x_limit_m: float | None) -> WalkRun:
    """The ``WalkRun`` of a walk's truth per cycle from its first walking cycle (walk, then stop), cut as
    ``walk_rollout.run_walk`` cuts ours: the walk ends at the first fallen cycle (the rest of the truth is
    dropped) or once the torso passes ``x_limit_m``. A missing cycle takes the nearest known truth before it
    (the first known one at the start).

    Raises:
        ValueError: no truth at all.
    """
    first = next((truth for truth in truths if truth is not None), None)
    if first is None:
        raise ValueError("no truth in the walk")
    filled: list[Truth] = []
    for truth in truths:
        filled.append(truth if truth is not None else (filled[-1] if filled else first))
    fall = next((i for i, truth in enumerate(filled) if truth.fallen), None)
    cycles = min(walk_cycles, len(filled))
    if x_limit_m is not None:
        past = next((i for i, truth in enumerate(filled[:cycles]) if truth.torso_m[0] >= x_limit_m), None)
        if past is not None:
            cycles = past + 1
    if fall is not None and fall < cycles:
        cycles = fall + 1
    if fall is not None:
        filled = filled[:fall + 1]
    return WalkRun(motion, lean, filled, cycles, fall, heading_deg)


class RealWalkBench(RealKickBench):
    """Walk rollouts one after the other on one real server (this namespace); see the module docstring.

    Args:
        workdir: server log, monitor frames.
        scripts: the real-server scripts (default: motion_studio.realserver.paths.scripts_dir()).
        settle_cycles: stance cycles after the trainer move (the kick bench's: the robot rocks after the move).

    Raises:
        RealServerError: the scripts are missing.
    """

    def __init__(self, workdir: Path, scripts: Path | None = None, settle_cycles: int = RealKickConfig.settle_cycles):
        super().__init__(workdir, RealKickConfig(settle_cycles=settle_cycles), scripts)

    def walk(self, library: MotionLibrary, motion: str, duration_s: float, *,
             position_m: tuple[float, float] = (-13.5, 0.0), heading_deg: float = 0.0, lean: float = 0.0,
             stop_s: float = 2.0, x_limit_m: float | None = 14.5) -> WalkRun:
        """One walk of ``motion`` (``library`` must also hold ``stand``) from ``position_m`` facing ``heading_deg``,
        as ``walk_rollout.run_walk`` plays it on ours; a stalled server is restarted and the walk tried again once.

        Raises:
            KeyError: ``motion`` is not in the library.
            RuntimeError: the server stalled twice.
        """
        library.get(motion)
        ball = (BALL_AWAY_M[0] - position_m[0], BALL_AWAY_M[1] - position_m[1])
        self.config = replace(self.config, spot_m=position_m, aim_deg=heading_deg, park_ball_m=ball)
        for attempt in range(2):
            if self.session is None:
                self._open(library)
            try:
                return self._walk(library, motion, duration_s, heading_deg, lean, stop_s, x_limit_m)
            except (OSError, RuntimeError, ValueError) as error:
                if attempt:
                    raise RuntimeError(f"the real server stalled twice in one walk ({error})") from error
                self.close()
                self.restarts += 1
        raise AssertionError("unreachable")

    def _walk(self, library: MotionLibrary, motion: str, duration_s: float, heading_deg: float, lean: float,
              stop_s: float, x_limit_m: float | None) -> WalkRun:
        session, behavior = self.session, self.behavior
        self._reset(library, heading_deg)
        since = len(session.monitor.frames)
        session.command("(reqfullstate)")
        behavior.set_skill(PlayMotion(motion, repeat=True, **({"lean": lean} if lean else {})))
        body = session.agent.world.body
        walk_cycles = round(duration_s / CYCLE_S)
        start_s = None
        fallen = 0
        for _ in range(walk_cycles):
            session.step()
            start_s = session.game_time_s if start_s is None else start_s
            fallen = fallen + 1 if body.fallen else 0
            if fallen >= FALLEN_CYCLES:
                break
        if fallen < FALLEN_CYCLES:
            behavior.set_skill(None)
            self._steps(round(stop_s / CYCLE_S))
        self._wait_frame(since, session.game_time_s)
        samples = parse_truth(session.monitor.frames[since:], self.workdir)
        del session.monitor.frames[:]
        # the first walking cycle's truth: the state the message after the first walk command reports
        first = round(start_s / CYCLE_S) + 1
        last = round(session.game_time_s / CYCLE_S)
        truths = [sample_truth(samples[k]) if k in samples else None for k in range(first, last + 1)]
        return walk_run(truths, motion, lean, walk_cycles, heading_deg, x_limit_m)


__all__ = ["FALLEN_CYCLES", "RealWalkBench", "walk_run"]
