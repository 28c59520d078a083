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

:meth:`RealWalkBench.script` plays a transition trial of ``motion_studio.walk_trials`` (a ``Script`` of walk, stop,
turn and stand requests) the same way after the same reset, without its pushes (the trainer cannot push a
robot), and reports it as ``walk_trials.run_script`` reports ours (``walk_trials.trial_result``, shared).

The figures come from the monitor's truth through :func:`walk_run`, which cuts the run as ``run_walk`` does
(the first fallen cycle, the torso past ``x_limit_m``), so ``tune_gait.trial_score`` scores both servers alike.
The real server never runs in tests: :func:`walk_run` is the part they check, on a recorded real walk.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace
from pathlib import Path

from agent.motion import MotionLibrary
from agent.skills.base import PlayMotion
from motion_studio.realserver.rollout_kick import RealKickBench, RealKickConfig, parse_truth, sample_truth
from motion_studio.scenarios import Truth
from motion_studio.walk_rollout import BALL_AWAY_M, WalkRun
from motion_studio.walk_trials import Script, ScriptedRequests, TrialResult, trial_result
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
        return self._retrying(library, position_m, heading_deg, lambda: self._walk(
            library, motion, duration_s, heading_deg, lean, stop_s, x_limit_m))

    def script(self, library: MotionLibrary, script: Script, *, position_m: tuple[float, float] = (-5.0, 0.0),
               heading_deg: float = 0.0, settle_s: float = 1.5) -> TrialResult:
        """One transition trial (``walk_trials.Script``, its pushes left out) from ``position_m``, then nothing
        requested for ``settle_s``, as ``walk_trials.run_script`` plays it on ours.

        Raises:
            RuntimeError: the server stalled twice.
        """
        return self._retrying(library, position_m, heading_deg,
                              lambda: self._script(library, script, heading_deg, settle_s))

    def _retrying(self, library: MotionLibrary, position_m: tuple[float, float], heading_deg: float,
                  rollout: Callable[[], object]):
        """``rollout()`` from ``position_m`` (the ball parked at BALL_AWAY_M), once more on a fresh server if the
        server stalls."""
        ball = (BALL_AWAY_M[0] - position_m[0], BALL_AWAY_M[1] - position_m[1])
        self.config = replace(self.config, spot_m=position_m, aim_deg=heading_deg, park_ball_m=ball)
        for attempt in range(2):
            if self.session is None:
                self._open(library)
            try:
                return rollout()
            except (OSError, RuntimeError, ValueError) as error:
                if attempt:
                    raise RuntimeError(f"the real server stalled twice in one rollout ({error})") from error
                self.close()
                self.restarts += 1
        raise AssertionError("unreachable")

    def _truths(self, since: int, start_s: float) -> list[Truth | None]:
        """The truth per cycle from the state the message after ``start_s`` reports up to now (the frames used
        are dropped)."""
        session = self.session
        self._wait_frame(since, session.game_time_s)
        samples = parse_truth(session.monitor.frames[since:], self.workdir)
        del session.monitor.frames[:]
        first = round(start_s / CYCLE_S) + 1
        last = round(session.game_time_s / CYCLE_S)
        return [sample_truth(samples[k]) if k in samples else None for k in range(first, last + 1)]

    def _script(self, library: MotionLibrary, script: Script, heading_deg: float, settle_s: float) -> TrialResult:
        session, behavior = self.session, self.behavior
        self._reset(library, heading_deg)
        since = len(session.monitor.frames)
        session.command("(reqfullstate)")
        skill = ScriptedRequests(script)
        behavior.set_skill(skill)
        body = session.agent.world.body
        limit = round((script.duration_s + settle_s + 8.0) / CYCLE_S)  # as run_script: turns take their time
        settle_cycles = round(settle_s / CYCLE_S)
        phases: list[tuple[int, str | None, str | None]] = []
        start_s, done_at, fallen = None, None, 0
        for index in range(limit):
            session.step()
            start_s = session.game_time_s if start_s is None else start_s
            phases.append((skill.index, behavior.motion.motion_name, behavior.motion.phase_name))
            fallen = fallen + 1 if body.fallen else 0
            if fallen >= FALLEN_CYCLES:
                break
            if skill.done and done_at is None:
                done_at = index
            if done_at is not None and index - done_at >= settle_cycles:
                break
        # phases[i] played in the cycle whose state truths[i] reports
        return trial_result(script.label, self._truths(since, start_s), phases)

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
        # the first walking cycle's truth: the state the message after the first walk command reports
        return walk_run(self._truths(since, start_s), motion, lean, walk_cycles, heading_deg, x_limit_m)


__all__ = ["FALLEN_CYCLES", "RealWalkBench", "walk_run"]
