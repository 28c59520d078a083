"""The strike keyframe (``motion_studio.strike_keyframe``, IPOPT on the symbolic Nao) refined by MuJoCo
rollouts: its contact geometry seeds a few of the kick's parameters, and a short CMA-ES run through the
tuning room (``motion_studio.tune_kick.kick_problem``) refines them on our simulator.

Why two stages: the keyframe NLP knows the kinematics exactly (how the toe can move fastest at the contact
under the 6.14 rad/s limit, with the CoM over the support sole) but nothing of contact, ball or balance
dynamics; rollouts know those but are expensive and noisy in 35 dimensions. So the NLP chooses the start
and the rollouts move only the parameters its answer sets:

* ``ball_ahead_m`` / ``ball_side_m``: the ball's centre where the keyframe's toe meets it (one ball radius
  ahead of the toe, beside the support sole as far as the toe is);
* ``strike_hip_offset_deg``: the kicking leg's hip yaw-pitch at the contact (the NLP drives it near its
  limit: the toe gains speed as the leg swings in and forward about the 45 deg axis).

The keyframe kicks with the left foot, the kick generator with the right; hip yaw-pitch has the same sign on
both sides, the side offset is mirrored. The run starts with the seeded kick itself (the tuning room
evaluates the start first), so the refined kick is never worse than the start on the same rollouts. Nothing
is written into ``motions/params`` (the shipped kick was tuned on the real server).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

from sim.field import BALL_RADIUS_M
from motion_studio.kick_rollout import Placement
from motion_studio.strike_keyframe import Strike, optimise_strike
from motion_studio.tune_kick import (OURS_CHECK_PLACEMENTS, SPACE, Backend, Objective, kick_problem, mujoco_rollout)
from motion_studio.tuning import InProcess, subset
from motion_studio.tuning.run_folder import default_run_dir
from motion_studio.tuning.session import run_cmaes
from motions.authoring.kick import KickParams, kick_params, stance_params

#: The kick parameters the strike keyframe sets, refined by rollouts.
REFINED = ("ball_ahead_m", "ball_side_m", "strike_hip_offset_deg")


@dataclass(frozen=True)
class Refinement:
    """The seeded start and the refined best: values of REFINED, their losses on the same placements
    (lower is better; ``motion_studio.tune_kick.evaluate``), rollouts spent and the run folder."""

    start: dict[str, float]
    start_loss: float
    best: dict[str, float]
    best_loss: float
    rollouts: int
    run_dir: Path


def seeded_values(strike: Strike) -> dict[str, float]:
    """REFINED's values from the keyframe (see the module docstring), clipped into the kick tuner's bounds."""
    toe_side_m, toe_ahead_m, _ = strike.toe_position_m
    raw = {"ball_ahead_m": toe_ahead_m + BALL_RADIUS_M, "ball_side_m": -toe_side_m,
           "strike_hip_offset_deg": strike.angles_deg["llj1"]}
    bounds = {p.name: (p.low, p.high) for p in subset(SPACE, REFINED)}
    return {name: round(min(max(value, bounds[name][0]), bounds[name][1]), 4) for name, value in raw.items()}


def refine_strike(section: str = "kick", generations: int = 3, placements: Sequence[Placement] = OURS_CHECK_PLACEMENTS,
                  popsize: int | None = 4, sigma0: float = 0.1, seed: int = 0, run_dir: Path | None = None,
                  strike: Strike | None = None, progress: Callable[[str], None] | None = None) -> Refinement:
    """Seed ``section``'s kick with the IPOPT strike and refine REFINED by CMA-ES on our simulator from
    ``placements`` (in this process; the run folder resumes like every tuning run).

    Raises:
        ValueError: an unknown kick section, generations < 1 or no placements.
    """
    if generations < 1:
        raise ValueError(f"generations: {generations} (need at least 1)")
    if not placements:
        raise ValueError("placements: none given")
    strike = strike or optimise_strike(0)
    start = seeded_values(strike)
    base: KickParams = replace(kick_params(section), **start)
    problem = kick_problem(f"{section}_strike", base, stance_params(), subset(SPACE, REFINED), Objective(),
                           [Backend("mujoco", mujoco_rollout, tuple(placements))])
    run_dir = run_dir or default_run_dir(f"kick_{section}_strike_refine")
    result = run_cmaes(problem, run_dir, generations, sigma0, popsize, seed, InProcess(), progress, plots=False)
    first = next(r for r in result.records if r["kind"] == "evaluation" and r["iteration"] == -1)
    return Refinement(start, float(first["loss"]), dict(result.best["values"]), float(result.best["loss"]),
                      result.rollouts, run_dir)


__all__ = ["REFINED", "Refinement", "refine_strike", "seeded_values"]
