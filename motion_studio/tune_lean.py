"""Tune the walk-lean curve (``[walk_lean]`` of ``motions/params/dynamic_elements.toml``) on our simulator.

The shipped ``walk_forward`` plays at full lean left and right (and half lean left) from a standstill;
the loss rewards the weaker side's curvature [deg/m] (up to a cap: a lean steers, it does not turn in
place), a half lean that curves about half as much, and keeping the speed, and punishes falls hard. Searched:
the offsets of the swing leg's hip yaw-pitch (le1), hip pitch (le3) and ankle pitch (le5) at a full lean.

Run::

    python -m motion_studio.tune_lean --generations 15 --write

Checkpoints to ``/tmp/nao3d-tune/walk_lean.json`` after every generation and resumes from it.
"""

from __future__ import annotations

import argparse
import datetime
import json
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from agent.motion import default_library, load_dynamic_params
from agent.motion.dynamic import DEFAULT_PARAMS_PATH, DynamicParams, save_dynamic_params
from motion_studio.cmaes import CMAES
from motion_studio.walk_rollout import run_walk

#: Searched offsets [deg] and bounds.
BOUNDS = {"le1": (-5.0, 0.0), "le3": (-2.0, 2.0), "le5": (-2.0, 2.0)}
#: Curvature beyond this earns nothing more [deg/m].
CURVATURE_CAP_DEG_M = 40.0
TRIAL_S = 10.0
CHECKPOINT = Path("/tmp/nao3d-tune/walk_lean.json")


def file_header(path: Path = DEFAULT_PARAMS_PATH) -> str:
    """The leading comment block of the parameter file (kept when the section is rewritten)."""
    lines = []
    for line in path.read_text(encoding="utf-8").splitlines():
        if not line.startswith("#"):
            break
        lines.append(line[1:].removeprefix(" "))
    return "\n".join(lines)


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
    left = figures["left_curvature_deg_m"] - figures["straight_curvature_deg_m"]
    right = figures["straight_curvature_deg_m"] - figures["right_curvature_deg_m"]
    half = figures["half_curvature_deg_m"] - figures["straight_curvature_deg_m"]
    weaker = min(left, right, CURVATURE_CAP_DEG_M)
    falls = sum(figures[f"{k}_fell"] for k in ("left", "half", "straight", "right"))
    speed = min(figures["left_speed_m_s"], figures["right_speed_m_s"])
    return -(weaker - 0.3 * abs(half - left / 2) + 10.0 * speed) + 100.0 * falls


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m motion_studio.tune_lean", description=__doc__.split("\n\n")[0])
    parser.add_argument("--generations", type=int, default=15)
    parser.add_argument("--popsize", type=int, default=8)
    parser.add_argument("--checkpoint", type=Path, default=CHECKPOINT)
    parser.add_argument("--write", action="store_true", help="write the best offsets into dynamic_elements.toml")
    parser.add_argument("--scan", default=None,
                        help='evaluate these offset sets instead of CMA-ES, e.g. "le1=-2;le1=-3,le3=1"')
    args = parser.parse_args(argv)
    base = load_dynamic_params()
    names = list(BOUNDS)
    if args.scan:
        data = {"best": {"loss": float("inf")}, "evaluations": []}
        for spec in args.scan.split(";"):
            offsets = {n: 0.0 for n in names}
            offsets.update({k.strip(): float(v) for k, v in (item.split("=") for item in spec.split(","))})
            figures = lean_figures(with_offsets(base, offsets))
            value = loss(figures)
            data["evaluations"].append({"offsets": offsets, "loss": value, "figures": figures})
            print(f"{offsets} loss {value:.2f} {figures}", flush=True)
            if value < data["best"]["loss"]:
                data["best"] = {"loss": value, "offsets": offsets, "figures": figures}
        args.generations = 0
        method = f'--scan "{args.scan}"'
    else:
        method = f"--generations {args.generations}"
    low = np.array([BOUNDS[n][0] for n in names])
    span = np.array([BOUNDS[n][1] - BOUNDS[n][0] for n in names])
    if args.scan:
        strategy = CMAES.create(np.full(len(names), 0.5))
    elif args.checkpoint.is_file():
        data = json.loads(args.checkpoint.read_text())
        strategy = CMAES.from_state(data["cmaes"])
    else:
        start = np.array([base.walk_lean.joint_offsets_deg.get(n, 0.0) for n in names])
        strategy = CMAES.create(np.clip((start - low) / span, 0, 1), 0.25, args.popsize)
        figures = lean_figures(base)
        data = {"best": {"loss": loss(figures), "offsets": dict(zip(names, start.tolist())), "figures": figures},
                "evaluations": []}
        print(f"base {data['best']}", flush=True)
    args.checkpoint.parent.mkdir(parents=True, exist_ok=True)
    while strategy.generation < args.generations:
        started = time.monotonic()
        losses = []
        for x in strategy.ask():
            offsets = dict(zip(names, (low + x * span).round(2).tolist()))
            figures = lean_figures(with_offsets(base, offsets))
            value = loss(figures)
            losses.append(value)
            data["evaluations"].append({"offsets": offsets, "loss": value, "figures": figures})
            if value < data["best"]["loss"]:
                data["best"] = {"loss": value, "offsets": offsets, "figures": figures}
        strategy.tell(losses)
        data["cmaes"] = strategy.state()
        args.checkpoint.write_text(json.dumps(data))
        print(f"gen {strategy.generation} {time.monotonic() - started:.0f}s min {min(losses):.2f} best {data['best']}",
              flush=True)
    best = data["best"]
    print(f"best {best}")
    if args.write:
        figures = best["figures"]
        lean = replace(with_offsets(base, best["offsets"]).walk_lean, provenance=(
            f"python -m motion_studio.tune_lean {method} on {datetime.date.today()}: "
            f"full lean curvature left {figures['left_curvature_deg_m']} deg/m, right "
            f"{figures['right_curvature_deg_m']} deg/m, half left {figures['half_curvature_deg_m']} deg/m, "
            f"straight {figures['straight_curvature_deg_m']} deg/m, falls "
            f"{int(sum(figures[k + '_fell'] for k in ('left', 'half', 'straight', 'right')))} in four 10 s runs of "
            f"walk_forward; "
            f"offsets act on the swing leg (motions.authoring.gait lean names)"))
        # Re-read now: other tuners rewrite their own sections of the same file.
        current = load_dynamic_params()
        save_dynamic_params(replace(current, walk_lean=lean), DEFAULT_PARAMS_PATH, file_header())
        print(DEFAULT_PARAMS_PATH)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
