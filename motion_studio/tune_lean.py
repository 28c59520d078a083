"""Tune the walk-lean curve (``[walk_lean]`` of ``motions/params/dynamic_elements.toml``) on our simulator.

Default (``--optimizer casadi``): the curve problem of ``motion_studio.lean_problem`` (full-lean offsets of the
swing leg's hip yaw-pitch and hip pitch, and the command curve: curvature linear in the request over [-1, 1],
no fall, at most 10 % speed loss) solved by the CasADi/IPOPT trust region of the tuning room on rollouts;
``--optimizer cmaes`` solves the same problem with CMA-ES, ``--compare`` runs both on one budget.

``--scan`` keeps the first method: evaluate given offset sets (full lean left/right, half lean left,
straight) and keep the one with the best of the old score (weaker side's curvature, speed, falls).

Run::

    motion-studio tune lean --evaluations 60 --workers 2
    motion-studio tune lean --scan "le1=-2.5;le1=-3" --write
"""

from __future__ import annotations

import argparse
import json
from dataclasses import replace
from pathlib import Path

from agent.motion import default_library, load_dynamic_params
from agent.motion.dynamic import DEFAULT_PARAMS_PATH, DynamicParams, WalkLean
from motion_studio.lean_problem import (COMMANDS, QUICK_COMMANDS, QUICK_WALK_S, TARGET_DEG_M, WALK_S, lean_curve,
                                        lean_problem)
from motion_studio.tuning import make_backend
from motion_studio.tuning.dynamic_file import write_dynamic_section
from motion_studio.tuning.params_file import Provenance, section_text
from motion_studio.tuning.run_folder import default_run_dir
from motion_studio.tuning.session import OPTIMIZERS, add_curve_run_options, one_line_errors, run_optimizer
from motion_studio.walk_rollout import run_walk

#: Curvature beyond this earns nothing more in the scan's score [deg/m].
CURVATURE_CAP_DEG_M = 40.0
TRIAL_S = 10.0


def with_offsets(dynamic: DynamicParams, offsets: dict[str, float]) -> DynamicParams:
    lean = replace(dynamic.walk_lean, joint_offsets_deg={k: round(float(v), 2) for k, v in offsets.items()})
    return replace(dynamic, walk_lean=lean)


def lean_figures(dynamic: DynamicParams, duration_s: float = TRIAL_S) -> dict[str, float]:
    """Curvature [deg/m], steady speed [m/s] and falls of full-left, half-left, straight and full-right runs."""
    library = default_library(0)
    out: dict[str, float] = {}
    for label, lean in (("left", 1.0), ("half", 0.5), ("straight", 0.0), ("right", -1.0)):
        run = run_walk(library, "walk_forward", duration_s, position_m=(-8.0, 0.0), lean=lean, x_limit_m=None,
                       dynamic=dynamic)
        out[f"{label}_curvature_deg_m"] = round(run.curvature_deg_m, 2)
        out[f"{label}_speed_m_s"] = round(run.steady_velocity_m_s()[0], 3)
        out[f"{label}_fell"] = float(run.fell or run.fell_stopping)
    return out


def loss(figures: dict[str, float]) -> float:
    """The scan's score (lower is better): the weaker side's curvature, half lean half as much, speed, falls."""
    left = figures["left_curvature_deg_m"] - figures["straight_curvature_deg_m"]
    right = figures["straight_curvature_deg_m"] - figures["right_curvature_deg_m"]
    half = figures["half_curvature_deg_m"] - figures["straight_curvature_deg_m"]
    weaker = min(left, right, CURVATURE_CAP_DEG_M)
    falls = sum(figures[f"{k}_fell"] for k in ("left", "half", "straight", "right"))
    speed = min(figures["left_speed_m_s"], figures["right_speed_m_s"])
    return -(weaker - 0.3 * abs(half - left / 2) + 10.0 * speed) + 100.0 * falls


def scan(base: DynamicParams, spec: str) -> tuple[WalkLean, str]:
    """``--scan``: the best of the given offset sets by :func:`loss`, and its note for the provenance."""
    best: dict = {"loss": float("inf")}
    for item in spec.split(";"):
        offsets = {"le1": 0.0, "le3": 0.0, "le5": 0.0}
        offsets.update({k.strip(): float(v) for k, v in (pair.split("=") for pair in item.split(","))})
        figures = lean_figures(with_offsets(base, offsets))
        value = loss(figures)
        print(f"{offsets} loss {value:.2f} {figures}", flush=True)
        if value < best["loss"]:
            best = {"loss": value, "offsets": offsets, "figures": figures}
    figures = best["figures"]
    note = (f"scan: full lean curvature left {figures['left_curvature_deg_m']} deg/m, right "
            f"{figures['right_curvature_deg_m']} deg/m, half left {figures['half_curvature_deg_m']} deg/m, straight "
            f"{figures['straight_curvature_deg_m']} deg/m in 10 s runs of walk_forward")
    return with_offsets(base, best["offsets"]).walk_lean, note


def write_lean(curve: WalkLean, path: Path = DEFAULT_PARAMS_PATH) -> None:
    """Rewrite ``[walk_lean]`` of ``path`` through the tuning room's writer (it must load back to ``curve``)."""
    values = {"joint_offsets_deg": dict(curve.joint_offsets_deg), "speed_points_m_s": list(curve.speed_points_m_s),
              "speed_scale": list(curve.speed_scale), "phase_points": list(curve.phase_points),
              "phase_scale": list(curve.phase_scale), "provenance": curve.provenance}
    if curve.command_points:
        values.update(command_points=list(curve.command_points), command_scale=list(curve.command_scale))
    write_dynamic_section("walk_lean", curve, section_text("walk_lean", values), path)


@one_line_errors("motion-studio tune lean")
def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="motion-studio tune lean", description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument("--optimizer", choices=OPTIMIZERS, default="casadi",
                        help="casadi: trust region with IPOPT; cmaes: CMA-ES on the same problem")
    parser.add_argument("--evaluations", type=int, default=60, help="candidates at most")
    parser.add_argument("--quick", action="store_true",
                        help=f"requests +-{QUICK_COMMANDS} and {QUICK_WALK_S:g} s walks (instead of +-{COMMANDS}, "
                             f"{WALK_S:g} s)")
    parser.add_argument("--target-deg-m", type=float, default=TARGET_DEG_M,
                        help="curvature wanted at a full lean [deg/m] (linear in the request)")
    add_curve_run_options(parser, "walk_lean")
    parser.add_argument("--seed", type=int, default=0, help="seed of CMA-ES")
    parser.add_argument("--scan", default=None,
                        help='evaluate these offset sets instead (the first method), e.g. "le1=-2;le1=-3,le3=1"')
    parser.add_argument("--write", action="store_true", help="write the tuned curve into [walk_lean]")
    parser.add_argument("--params", type=Path, default=DEFAULT_PARAMS_PATH, help="dynamic elements file")
    args = parser.parse_args(argv)
    base = load_dynamic_params(args.params)
    if args.scan:
        curve, note = scan(base, args.scan)
    else:
        commands = QUICK_COMMANDS if args.quick else COMMANDS
        problem = lean_problem(base, commands, QUICK_WALK_S if args.quick else WALK_S, args.target_deg_m)
        backend = make_backend("inprocess", args.workers, args.ray_address)
        try:
            if args.compare:
                from motion_studio.tuning.compare import compare

                comparison = compare(problem, args.run_dir or default_run_dir("walk_lean_compare"), args.evaluations,
                                     min_radius=0.02, seed=args.seed, backend=backend)
                print(json.dumps(comparison.table()))
                result = comparison.casadi
            else:
                result = run_optimizer(problem, args.optimizer, args.run_dir or default_run_dir(
                    "walk_lean", args.optimizer), args.evaluations, min_radius=0.02, seed=args.seed,
                    backend=backend, bar=True)
        finally:
            backend.close()
        figures = result.best["result"]
        speeds = [v for k, v in figures.items() if k.startswith("speed_ratio_")]
        note = (f"{args.optimizer} on our simulator ({result.rollouts} rollouts of walk_forward): curvature within "
                f"{figures.get('curvature_error_max_deg_m', float('nan')):.2f} deg/m of {args.target_deg_m:g} x request "
                f"at +-{list(commands)}, speed ratio min {min(speeds, default=float('nan')):.3f}, falls "
                f"{figures.get('falls')}")
        curve = lean_curve(base.walk_lean, result.best["values"], commands)
        print(f"best: {json.dumps(result.best['values'])}")
        print(f"figures: {json.dumps({k: round(v, 3) if isinstance(v, float) else v for k, v in figures.items()})}")
    curve = replace(curve, provenance=Provenance.now().text(note))
    if args.write:
        write_lean(curve, args.params)
        print(f"wrote [walk_lean] of {args.params}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
