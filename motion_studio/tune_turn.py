"""Tune the turn-gain curve (``[turn_gain]`` of ``motions/params/dynamic_elements.toml``) on our simulator.

Default (``--optimizer casadi``): the curve problem of ``motion_studio.turn_problem`` (requested turn of one
motion -> gain at a few points, monotone and bounded; loss: squared error of the turn made against the turn
requested, plus time) solved by the CasADi/IPOPT trust region of the tuning room on rollouts;
``--optimizer cmaes`` solves the same problem with CMA-ES, ``--compare`` runs both on one budget. The tuned
curve is then checked as the turn skill uses it: ``TurnBy`` by dead reckoning for requests of 3-60 deg
(prediction error = |measured - predicted|).

``--optimizer fit`` keeps the first method: the turn per motion of ``turn_left`` and ``turn_right`` played
back to back at a grid of gains (``skill_bench.turn.gain_sweep``, truth heading), and a least-squares line
turn = a + b * gain, which is the curve's line model (``agent.motion.dynamic.TurnGain``): ``predicted_base_deg``
= the line at ``min_gain``, ``predicted_slope_deg`` = its rise from ``min_gain`` to 1, and the request -> gain
map is its inverse.

Only the ``[turn_gain]`` section is rewritten with ``--write`` (the other sections and their comments stay).

Run::

    motion-studio tune turn --evaluations 40
    motion-studio tune turn --optimizer fit --write
"""

from __future__ import annotations

import argparse
import json
from dataclasses import fields
from pathlib import Path

import numpy as np

from agent.motion.dynamic import DEFAULT_PARAMS_PATH, TurnGain, load_dynamic_params
from motion_studio.skill_bench.turn import gain_sweep
from motion_studio.tuning import make_backend
from motion_studio.tuning.dynamic_file import write_dynamic_section
from motion_studio.tuning.params_file import Provenance, replace_sections, toml_value
from motion_studio.tuning.run_folder import default_run_dir
from motion_studio.tuning.session import OPTIMIZERS, add_curve_run_options, one_line_errors, run_optimizer
from motion_studio.turn_problem import (CHECK_DEG, CHECK_QUICK_DEG, QUICK_POINTS_DEG, REQUEST_POINTS_DEG,
                                        prediction_error, turn_curve, turn_problem)

#: Gains measured by default.
FIT_GAINS = (0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)
#: Smallest gain of the fitted curve: the turn motions scale from a step in place, so small gains still step
#: properly and turn a little (the seed agent's 0.3 would make ~12 deg the smallest turn).
MIN_GAIN = 0.05
MOTIONS = 6


def fit_turn_gain(rows: list[dict[str, float | bool]], min_gain: float = MIN_GAIN,
                  provenance: str = "") -> tuple[TurnGain, float]:
    """The curve fitted to sweep rows (gain, left_deg, right_deg); returns it and the fit's RMS residual [deg].

    Raises:
        ValueError: fewer than two gains, a fall in the sweep, or a line that does not rise with the gain.
    """
    if len(rows) < 2:
        raise ValueError(f"need at least two gains to fit a line, got {len(rows)}")
    fallen = [row["gain"] for row in rows if row.get("left_fell") or row.get("right_fell")]
    if fallen:
        raise ValueError(f"the robot fell at gains {fallen}; a curve fitted through falls would mislead")
    gains = np.array([float(row["gain"]) for row in rows for _ in (0, 1)])
    turns = np.array([float(row[side]) for row in rows for side in ("left_deg", "right_deg")])
    slope, intercept = np.polyfit(gains, turns, 1)
    if slope <= 0.0:
        raise ValueError(f"the turn does not grow with the gain (slope {slope:.3g} deg per unit gain)")
    residual = float(np.sqrt(np.mean((intercept + slope * gains - turns) ** 2)))
    base = float(intercept + slope * min_gain)
    rise = float(slope * (1.0 - min_gain))
    curve = TurnGain(min_gain=min_gain, offset_deg=round(base, 3), span_deg=round(rise, 3),
                     predicted_base_deg=round(base, 3), predicted_slope_deg=round(rise, 3), provenance=provenance)
    return curve, residual


def section_text(curve: TurnGain) -> str:
    """The ``[turn_gain]`` section, with the formulas as comments."""
    values = {f.name: getattr(curve, f.name) for f in fields(curve)}
    lines = ["[turn_gain]", f"provenance = {toml_value(values.pop('provenance'))}",
             "# gain = min_gain + (1 - min_gain) * min(span_deg, max(0, |turn_deg| - offset_deg)) / span_deg"]
    lines += [f"{key} = {toml_value(values[key])}" for key in ("min_gain", "offset_deg", "span_deg")]
    lines.append("# Predicted turn of one turn motion at a gain: "
                 "base_deg + slope_deg * (gain - min_gain) / (1 - min_gain).")
    lines += [f"{key} = {toml_value(values[key])}" for key in ("predicted_base_deg", "predicted_slope_deg")]
    if curve.request_points_deg:
        lines.append("# Tuned curve (replaces the line above): gain at each requested turn of one motion, linear "
                     "between, inverted for the prediction.")
        lines += [f"{key} = {toml_value(list(values[key]))}" for key in ("request_points_deg", "curve_gains")]
    return "\n".join(lines) + "\n"


def replace_section(text: str, name: str, section: str) -> str:
    """``text`` with TOML section ``[name]`` replaced by ``section`` (appended if missing)."""
    return replace_sections(text, {name: section})


def write_curve(curve: TurnGain, path: Path = DEFAULT_PARAMS_PATH) -> None:
    """Rewrite the ``[turn_gain]`` section of ``path`` (the tuning room's writer) and check that the file
    still loads to ``curve``.

    Raises:
        TuningError: the rewritten file does not load back to the curve (the file is left unchanged).
    """
    write_dynamic_section("turn_gain", curve, section_text(curve), path)


def fit_main(args: argparse.Namespace) -> TurnGain:
    """``--optimizer fit``: sweep the gains and fit the line."""
    rows = gain_sweep(FIT_GAINS, args.motions, args.seed)
    for row in rows:
        print(f"gain {row['gain']:.2f}: left {row['left_deg']:6.2f} deg, right {row['right_deg']:6.2f} deg")
    table = ", ".join(f"{row['gain']:g}: {(float(row['left_deg']) + float(row['right_deg'])) / 2:.2f}"
                      for row in rows)
    provenance = Provenance.now().text(
        f"fitted on our simulator: turn per motion [deg] of turn_left/turn_right (mean of both, {args.motions} "
        f"motions each, truth heading) at gain {table}; least-squares line; min_gain {args.min_gain}")
    curve, residual = fit_turn_gain(rows, args.min_gain, provenance)
    print(f"fit: {curve.predicted_base_deg} deg at gain {curve.min_gain}, +{curve.predicted_slope_deg} deg to gain 1,"
          f" RMS residual {residual:.2f} deg")
    return curve


@one_line_errors("motion-studio tune turn")
def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="motion-studio tune turn", description=__doc__.splitlines()[0],
                                     formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument("--optimizer", choices=(*OPTIMIZERS, "fit"), default="casadi",
                        help="casadi: trust region with IPOPT; cmaes: CMA-ES; fit: gain sweep and a least-squares line")
    parser.add_argument("--evaluations", type=int, default=40, help="candidates at most (casadi, cmaes)")
    parser.add_argument("--quick", action="store_true",
                        help=f"points {QUICK_POINTS_DEG} on the left side only, check {CHECK_QUICK_DEG} deg")
    parser.add_argument("--from-seed-curve", action="store_true",
                        help="start from the seed agent's curve (REFERENCE 7.3) instead of the shipped one")
    add_curve_run_options(parser, "turn_gain")
    parser.add_argument("--min-gain", type=float, default=MIN_GAIN, help="smallest gain of the curve (fit)")
    parser.add_argument("--motions", type=int, default=MOTIONS, help="motions per gain and side (fit)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the simulator (and of CMA-ES)")
    parser.add_argument("--write", action="store_true", help="rewrite [turn_gain] of the parameter file")
    parser.add_argument("--params", type=Path, default=DEFAULT_PARAMS_PATH, help="dynamic elements file")
    args = parser.parse_args(argv)
    if args.optimizer == "fit":
        curve = fit_main(args)
    else:
        dynamic = load_dynamic_params(args.params)
        start = TurnGain() if args.from_seed_curve else dynamic.turn_gain
        points = QUICK_POINTS_DEG if args.quick else REQUEST_POINTS_DEG
        problem = turn_problem(start, points, ("left",) if args.quick else ("left", "right"), args.seed)
        backend = make_backend("inprocess", args.workers, args.ray_address)
        try:
            if args.compare:
                from motion_studio.tuning.compare import compare

                comparison = compare(problem, args.run_dir or default_run_dir("turn_gain_compare"), args.evaluations,
                                     seed=args.seed, backend=backend)
                print(json.dumps(comparison.table()))
                result = comparison.casadi
            else:
                result = run_optimizer(problem, args.optimizer, args.run_dir or default_run_dir(
                    "turn_gain", args.optimizer), args.evaluations, seed=args.seed, backend=backend, bar=True)
        finally:
            backend.close()
        figures = result.best["result"]
        check = prediction_error(turn_curve(result.best["values"], points), dynamic,
                                 CHECK_QUICK_DEG if args.quick else CHECK_DEG, args.seed)
        curve = turn_curve(result.best["values"], points, Provenance.now().text(
            f"{args.optimizer} on our simulator ({result.rollouts} rollouts): turn per motion at the points "
            f"within {figures.get('max_error_deg', float('nan')):.2f} deg; TurnBy 3-60 deg by dead reckoning: "
            f"|measured - predicted| mean {check['prediction_error_mean_deg']} deg, max "
            f"{check['prediction_error_max_deg']} deg"))
        print(f"curve: gains {list(curve.curve_gains)} at {list(curve.request_points_deg)} deg")
        print(f"TurnBy check: {json.dumps(check)}")
    if args.write:
        write_curve(curve, args.params)
        print(f"wrote [turn_gain] of {args.params}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())


__all__ = ["FIT_GAINS", "MIN_GAIN", "fit_turn_gain", "replace_section", "section_text", "write_curve"]
