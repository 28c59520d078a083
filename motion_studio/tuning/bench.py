"""The tuning benchmark: the symbolic Nao against Pinocchio, and the CasADi trust region against CMA-ES on the
lean and turn curve problems with one rollout budget each (figures, never pass/fail).

Why both optimizers on each problem from the same start and budget: "rollouts to target" (the rollouts each
needed to reach CMA-ES's final objective) is only meaningful on the same problem; the tuned curves are then
judged as the agent uses them (the lean curve's curvature error, TurnBy's prediction error).
"""

from __future__ import annotations

import shutil
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import casadi

from motion_studio.tuning.backends import make_backend
from motion_studio.tuning.compare import compare
from motion_studio.tuning.run_folder import RUNS_DIR, draw_plots

#: Budgets [candidates per optimizer] and problem sizes.
QUICK = {"turn_evaluations": 12, "lean_evaluations": 8, "symbolic_samples": 3, "strike_generations": 1}
FULL = {"turn_evaluations": 40, "lean_evaluations": 40, "symbolic_samples": 10, "strike_generations": 3}


def run(quick: bool = False, out: Path | None = None, workers: int = 2,
        progress: Callable[[str], None] | None = None) -> dict[str, Any]:
    """The figures (JSON-ready); run folders under ``out`` (default ``out/tuning/bench[_quick]``, made anew)."""
    from agent.motion import load_dynamic_params
    from agent.motion.dynamic import TurnGain
    from kinematics.spec import ROBOT_TYPES
    from kinematics.symbolic import pinocchio_max_diff_m
    from motion_studio import lean_problem, turn_problem

    started = time.monotonic()
    say = progress or (lambda text: None)
    sizes = QUICK if quick else FULL
    out = out or RUNS_DIR / ("bench_quick" if quick else "bench")
    shutil.rmtree(out, ignore_errors=True)
    figures: dict[str, Any] = {"quick": quick}
    figures["symbolic_vs_pinocchio_max_diff_m"] = max(
        pinocchio_max_diff_m(t, sizes["symbolic_samples"]) for t in ROBOT_TYPES)
    figures["curve_solver"] = f"ipopt (casadi {casadi.__version__} nlpsol)"
    from motion_studio.strike_keyframe import optimise_strike

    strike = optimise_strike(0)
    figures["strike_toe_speed_m_s"] = round(strike.toe_speed_m_s, 3)  # kinematic bound at 6.14 rad/s
    from motion_studio.standup_keypose import section_keyposes
    from motion_studio.strike_refine import refine_strike

    authored, widest = section_keyposes("standup_front")
    figures["standup_keypose_margin_m"] = {"authored": round(authored.margin_m, 4), "ipopt": round(widest.margin_m, 4)}
    say("strike keyframe refined by rollouts")
    refined = refine_strike("kick", sizes["strike_generations"], run_dir=out / "strike_refine", strike=strike)
    figures["strike_refine_loss"] = {"seeded": round(refined.start_loss, 4), "refined": round(refined.best_loss, 4),
                                     "rollouts": refined.rollouts}
    dynamic = load_dynamic_params()
    backend = make_backend("processes", workers) if workers > 1 else make_backend()
    try:
        # Turn gain from the seed agent's curve (REFERENCE 7.3): the shipped one is already tuned.
        points = turn_problem.QUICK_POINTS_DEG if quick else turn_problem.REQUEST_POINTS_DEG
        turn = turn_problem.turn_problem(TurnGain(), points, ("left",) if quick else ("left", "right"))
        say("turn gain: trust region and CMA-ES")
        turns = compare(turn, out / "turn", sizes["turn_evaluations"], min_radius=0.005, backend=backend)
        commands = lean_problem.QUICK_COMMANDS if quick else lean_problem.COMMANDS
        lean = lean_problem.lean_problem(dynamic, commands, lean_problem.QUICK_WALK_S if quick else lean_problem.WALK_S)
        say("walk lean: trust region and CMA-ES")
        leans = compare(lean, out / "lean", sizes["lean_evaluations"], min_radius=0.02, backend=backend)
    finally:
        backend.close()
    for problem, comparison in ((turn, turns), (lean, leans)):
        for result in (comparison.casadi, comparison.cmaes):
            draw_plots(result, problem)
    say("TurnBy with the tuned turn-gain curve")
    curve = turn_problem.turn_curve(turns.casadi.best["values"], points)
    check = turn_problem.prediction_error(curve, dynamic,
                                          turn_problem.CHECK_QUICK_DEG if quick else turn_problem.CHECK_DEG)
    lean_best = leans.casadi.best["result"]
    speeds = [v for k, v in lean_best.items() if k.startswith("speed_ratio_")]
    figures.update({
        "lean_curvature_error_deg_m": round(lean_best.get("curvature_error_max_deg_m", float("nan")), 3),
        "lean_target_deg_m_at_full_lean": lean_problem.TARGET_DEG_M,
        "lean_min_speed_ratio": round(min(speeds, default=float("nan")), 3),
        "lean_falls": lean_best.get("falls"),
        "turn_prediction_error_deg": check["prediction_error_mean_deg"],
        "turn_prediction_error_max_deg": check["prediction_error_max_deg"],
        "turn_request_error_deg": check["request_error_mean_deg"],
        "turn_time_per_turn_s": check["time_per_turn_s"],
        "casadi_rollouts_to_target": {"lean": leans.casadi_rollouts_to_target,
                                      "turn": turns.casadi_rollouts_to_target},
        "cmaes_rollouts_to_target": {"lean": leans.cmaes_rollouts_to_target, "turn": turns.cmaes_rollouts_to_target},
        "comparison": {"lean": leans.table(), "turn": turns.table()},
        "tuned": {"lean": leans.casadi.best["values"], "turn": turns.casadi.best["values"]},
        "run_folders": str(out),
    })
    figures["wall_s"] = round(time.monotonic() - started, 1)
    return figures


__all__ = ["FULL", "QUICK", "run"]
