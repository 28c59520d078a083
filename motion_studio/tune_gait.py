"""Tune a walk's gait parameters on our simulator with CMA-ES, checkpointing every generation.

Each candidate: GaitParams -> IK keyframes (``motions.authoring.gait``) -> the real agent plays the walk on
our simulator (``motion_studio.walk_rollout``) in a few trials (a plain run, a sideways push, a forward
push), each followed by a stop. The loss rewards speed along the walk's direction and punishes falls
(REFERENCE §8.1: a fall costs 2 m), falls while stopping, sideways drift and heading change.

Run::

    python -m motion_studio.tune_gait walk_forward --generations 30 --workers 2 --write

``--backend real`` judges the candidates on the real rcssserver3d 0.7.3 instead
(``motion_studio.realserver.gait_backend``: the process re-runs itself inside the real-server scripts' private
namespace, one server, one walk at a time, the robot put back by trainer commands; the trials without pushes,
scored by the same :func:`trial_score` from the monitor's truth); ``--backend both`` takes the mean of that loss
and ours (our trials, pushes and ``--robust`` transitions included)::

    python -m motion_studio.tune_gait walk_forward --backend both --lean --robust 6 --generations 12

The run folder (``out/tuning/gait_<motion>_<step cycles>``, ``_real`` or ``_both`` for those backends: checkpoint, trace of every evaluation, plots;
``motion_studio.tuning``) is checkpointed after each generation; running the same command again resumes from
it. ``--write`` puts the best parameters into
``motions/params/gait.toml`` (section = motion name, with a provenance line and the measured speeds) and
regenerates the motion file.
"""

from __future__ import annotations

import argparse
import datetime
import json
import math
import tomllib
from collections.abc import Callable, Sequence
from dataclasses import dataclass, fields, replace
from functools import partial
from pathlib import Path

import numpy as np

from agent.motion import MotionLibrary
from kinematics.errors import IKError
from motion_studio.tuning import InProcess, Parameter, Problem, make_backend
from motion_studio.tuning.session import legacy_data, one_line_errors, run_cmaes
from motion_studio.tuning.params_file import Provenance, write_file
from motion_studio.tuning.run_folder import default_run_dir
from motion_studio.realserver.gait_backend import BACKENDS as REAL_BACKENDS
from motion_studio.walk_rollout import Push, WalkRun, run_walk
from motions.authoring.gait import MEASURED_KEYS, GaitParams, build_walk, write_gait_files
from motions.authoring.gait_params import (GAIT_PARAMS_PATH, dumps_gait_params, load_gait_params, provenance,
                                           read_common, read_header)

#: Direction of each walk in the robot frame (forward, left).
DIRECTIONS: dict[str, tuple[float, float]] = {"walk_forward": (1.0, 0.0), "walk_fast": (1.0, 0.0),
                                              "walk_backward": (-1.0, 0.0), "walk_left": (0.0, 1.0),
                                              "walk_right": (0.0, -1.0)}


#: Search spaces: gait shape (every walk) and posture (the forward walk's, which the stance shares).
SHAPE = (Parameter("step_height_m", 0.01, 0.05), Parameter("sway_m", 0.0, 0.04),
         Parameter("sway_phase", -0.3, 0.3), Parameter("swing_linear", 0.0, 1.0),
         Parameter("double_support_cycles", 0, 2, step=1), Parameter("toe_out_deg", 0.0, 6.0),
         Parameter("ramp_steps", 1, 4, step=1))
POSTURE = (Parameter("torso_height_m", 0.30, 0.365), Parameter("torso_pitch_deg", 0.0, 25.0),
           Parameter("torso_forward_m", -0.03, 0.04), Parameter("foot_spacing_m", 0.09, 0.14))
#: The posture is the shared stance's ([common]; every walk starts from and stops in ``stand``), so it is
#: searched only with ``--posture`` (and then moved to [common] with ``--write --common``).
SPACES: dict[str, tuple[Parameter, ...]] = {
    "walk_forward": (Parameter("step_length_m", 0.04, 0.13),) + SHAPE + (Parameter("arm_swing_deg", 0, 30),),
    "walk_fast": (Parameter("step_length_m", 0.08, 0.15),) + SHAPE + (Parameter("arm_swing_deg", 0, 30),),
    "walk_backward": (Parameter("step_length_m", -0.09, -0.02),) + SHAPE + (Parameter("torso_pitch_deg", 0.0, 25.0),),
    "walk_left": (Parameter("side_step_m", -0.08, -0.01), Parameter("step_length_m", -0.01, 0.01)) + SHAPE,
    "walk_right": (Parameter("side_step_m", 0.01, 0.08), Parameter("step_length_m", -0.01, 0.01)) + SHAPE,
}


@dataclass(frozen=True)
class Trial:
    """One rollout of a candidate: walk ``duration_s`` with ``pushes``."""

    duration_s: float
    pushes: tuple[Push, ...] = ()
    lean: float = 0.0
    """Walk-lean request of the trial (+ = curve left): the walk must stay up and curve that way."""


def default_trials(motion: str, quick: bool = False, lean: bool = False) -> tuple[Trial, ...]:
    """A plain run (20 s for the forward walk: the run challenge), a sideways push, a forward push, and with
    ``lean`` full leans both ways (the walk must stay steerable)."""
    forward = DIRECTIONS[motion][0] > 0
    long_s = 20.0 if forward else 12.0
    if quick:
        return (Trial(6.0),)
    trials = (Trial(long_s), Trial(10.0, (Push(4.0, left_m_s=0.25),)),
              Trial(10.0, (Push(4.0, forward_m_s=0.2 if forward else -0.2), Push(7.0, left_m_s=-0.25))))
    if lean and forward:
        trials += (Trial(10.0, lean=1.0), Trial(10.0, lean=-1.0))
    return trials


#: Loss of a candidate whose keyframes are out of reach or whose evaluation failed (a walk that falls at once
#: has a loss of about 0.7, so this ranks below any walk).
FAIL_LOSS = 10.0
#: Curvature [deg/m] a full lean must reach to earn its whole bonus.
LEAN_CURVATURE_DEG_M = 20.0


def trial_place(trial: Trial, direction: tuple[float, float]) -> dict[str, object]:
    """Where a trial starts and where its walk is cut (``run_walk``'s ``position_m`` and ``x_limit_m``), the
    same on both servers: forward walks from the own goal's end (lean trials from x = -8 m) up to x = 14.5 m,
    the others from the centre."""
    if direction[0] <= 0:
        return {"position_m": (0.0, 0.0), "x_limit_m": None}
    return {"position_m": (-8.0, 0.0) if trial.lean else (-13.5, 0.0), "x_limit_m": 14.5}


def trial_score(run: WalkRun, direction: tuple[float, float]) -> dict[str, float]:
    """Figures and the score of one trial (higher is better); a lean trial earns a bonus for curving its
    way (capped) instead of paying for the heading change, and its speed is along its path: credited with the
    way along the start heading, a walk that ignored the lean scored as well as one that curved at the cap (the
    real-server runs of 2026-11-26 found such unsteerable walks best)."""
    forward, left = run.displacement_m()
    along = forward * direction[0] + left * direction[1]
    across = abs(-forward * direction[1] + left * direction[0])
    time_s = run.walk_time_s if not run.fell else max(run.walk_time_s, 10.0)
    score = (run.path_length_m(run.walk_cycles) if run.lean else along) / time_s
    if run.fell:
        score -= 2.0 / time_s + 0.5
    if run.fell_stopping:
        score -= 0.3
    if run.lean:
        curving = math.copysign(1.0, run.lean) * run.curvature_deg_m
        score += 0.02 * max(-LEAN_CURVATURE_DEG_M, min(LEAN_CURVATURE_DEG_M, curving))
    else:
        score -= 0.3 * across / max(time_s, 1.0) + 0.002 * abs(run.heading_change_deg)
    figures = {"score": score, "along_m": along, "across_m": across, "time_s": run.walk_time_s, "fell": float(run.fell),
               "fell_stopping": float(run.fell_stopping), "heading_deg": run.heading_change_deg}
    if run.lean:
        figures["curvature_deg_m"] = run.curvature_deg_m
    return figures


@dataclass(frozen=True)
class Robust:
    """Transition trials added to a candidate's loss (``motion_studio.walk_trials``): ``count`` scripts drawn
    from ``seed`` (the same for every candidate of a generation), a fraction ``noisy`` of them played with
    Gaussian noise of ``noise_deg`` on the walk's leg targets; each fall costs ``fall_cost``."""

    seed: int = 0
    count: int = 8
    noisy: float = 0.5
    noise_deg: float = 0.4
    fall_cost: float = 1.5


def candidate_library(motion: str, params: GaitParams) -> MotionLibrary:
    """The shipped motions (stand, turns) with the candidate walk in place of ``motion``, its stance the
    shipped ``stand``'s (as ``motions.authoring.gait.write_gait_files`` writes it).

    Raises:
        IKError: a keyframe of the candidate out of reach.
    """
    from agent.motion import default_library

    library = default_library(0)
    library.add(build_walk(motion, params, stance=load_gait_params()["stand"]))
    return library


def robust_figures(motion: str, library: MotionLibrary, robust: Robust) -> dict[str, float]:
    """Falls of the candidate in ``robust.count`` transition scripts (some with keyframe noise)."""
    import random

    from motion_studio.walk_trials import perturbed, run_script, transition_script

    rng = random.Random(robust.seed)
    clean = library.get(motion)
    falls = noisy_falls = 0
    for index in range(robust.count):
        script = transition_script(rng, library, motion)
        noisy = index < round(robust.noisy * robust.count)
        library.add(perturbed(clean, rng, robust.noise_deg) if noisy else clean)
        fell = run_script(library, script, seed=robust.seed * 100 + index).fell
        falls += fell
        noisy_falls += fell and noisy
    library.add(clean)
    return {"falls": falls, "noisy_falls": noisy_falls, "count": robust.count}


def evaluate(motion: str, params: GaitParams, trials: Sequence[Trial], robust: Robust | None = None) -> dict[str, object]:
    """Loss (lower is better) and per-trial figures of one candidate; an IK failure is a large loss. Lean
    trials play with the shipped ``[walk_lean]`` curve; ``robust`` adds transition trials."""
    try:
        library = candidate_library(motion, params)
    except IKError as error:
        return {"loss": FAIL_LOSS, "error": str(error)[:200], "trials": []}
    direction = DIRECTIONS[motion]
    results = []
    for trial in trials:
        run = run_walk(library, motion, trial.duration_s, pushes=trial.pushes, lean=trial.lean,
                       **trial_place(trial, direction))
        results.append(trial_score(run, direction))
    loss = -float(np.mean([r["score"] for r in results]))
    out: dict[str, object] = {"trials": [{k: round(v, 4) for k, v in r.items()} for r in results]}
    if robust is not None:
        figures = robust_figures(motion, library, robust)
        loss += robust.fall_cost * figures["falls"] / max(1, figures["count"])
        out["robust"] = figures
    out["loss"] = loss
    return out


def _evaluate_values(motion: str, base: dict, trials: tuple[Trial, ...], robust: Robust | None,
                     values: dict[str, float]) -> dict[str, object]:
    """:func:`evaluate` of the base with ``values`` put in, from plain data (runs in worker processes)."""
    return evaluate(motion, replace(_params(base), **values), trials, robust)


def _params(values: dict) -> GaitParams:
    from motions.authoring.gait_params import _gait_values

    return GaitParams(**_gait_values(values, "candidate"))


def _as_dict(params: GaitParams) -> dict:
    out = {}
    for f in fields(params):
        value = getattr(params, f.name)
        out[f.name] = {g.name: getattr(value, g.name) for g in fields(value)} if f.name == "arm" else value
    return out


def tune(motion: str, base: GaitParams, dimensions: Sequence[Parameter], trials: Sequence[Trial], generations: int,
         checkpoint: Path, workers: int = 1, sigma0: float = 0.15, popsize: int | None = None, seed: int = 0,
         progress: Callable[[str], None] | None = print, robust: Robust | None = None, bar: bool = False,
         judge: Callable[[GaitParams], dict] | None = None) -> dict:
    """Run (or resume) CMA-ES from ``base`` in the run folder ``checkpoint``; returns ``best`` (lowest loss,
    whole parameters), every ``evaluations`` entry, ``motion`` and ``base``. With ``robust``, every candidate
    plays the same ``robust.count`` transition scripts (the robust seed); :func:`validate` re-ranks the
    leading candidates on one larger set. With ``judge`` (``realserver.gait_backend.RealJudge``: the real
    server, and ours with ``--backend both``) the candidates are judged by it one after the other in this
    process instead."""
    rollouts = len(trials) + (robust.count if robust else 0)
    if judge is not None:
        def evaluate_fn(values: dict[str, float]) -> dict[str, object]:
            return judge(replace(base, **values))
        rollouts += len(getattr(judge, "trials", ()))
    else:
        evaluate_fn = partial(_evaluate_values, motion, _as_dict(base), tuple(trials), robust)
    problem = Problem(f"gait:{motion}", tuple(dimensions), evaluate_fn,
                      start={d.name: getattr(base, d.name) for d in dimensions}, fail_loss=FAIL_LOSS,
                      rollouts_per_candidate=rollouts)
    backend = InProcess() if judge is not None else make_backend("inprocess", workers)
    try:
        result = run_cmaes(problem, checkpoint, generations, sigma0, popsize, seed, backend, progress, bar)
    finally:
        backend.close()
    data = legacy_data(result, lambda values: _as_dict(replace(base, **values)))
    return {"motion": motion, "dimensions": [d.name for d in dimensions], "base": _as_dict(base), **data}


def validate(data: dict, trials: Sequence[Trial], robust: Robust, top: int = 4,
             progress: Callable[[str], None] = print) -> dict:
    """Re-rank the ``top`` lowest-loss distinct candidates of a checkpoint (and its base) on one set of
    ``robust.count`` transition scripts; returns the winner as a ``best`` entry (``validated`` = figures)."""
    motion = data["motion"]
    seen, entries = set(), []
    pool = [{"params": data["base"], "loss": float("inf")}] + sorted(data["evaluations"],
                                                                    key=lambda e: e["result"]["loss"])
    for entry in pool:
        key = json.dumps(entry["params"], sort_keys=True)
        if key not in seen:
            seen.add(key)
            entries.append(entry)
        if len(entries) > top:
            break
    ranked = []
    for entry in entries:
        result = evaluate(motion, _params(entry["params"]), trials, robust)
        progress(f"validate loss {result['loss']:.4f} {result['trials']} {result.get('robust')}")
        ranked.append({"loss": result["loss"], "params": entry["params"], "result": result})
    return min(ranked, key=lambda e: e["loss"])


def write_best(motion: str, best: dict, command: str, params_path: Path = GAIT_PARAMS_PATH,
               common_keys: Sequence[str] = (), note: str = "") -> list[Path]:
    """Put the best parameters into the parameter file (and ``common_keys`` into [common]), with the
    measured steady speeds of a confirming run (and ``note``, e.g. the real server's figures) in its
    provenance, then regenerate the motion files."""
    table = load_gait_params(params_path)
    common = read_common(params_path)
    best_params = _params(best["params"])
    if common_keys:
        # The posture moves to [common]: every motion (the stance first) takes it, so walks start from and
        # stop in the same stance; a walk that needs its own posture is tuned again afterwards.
        moved = {k: getattr(best_params, k) for k in common_keys}
        common = replace(common, **moved)
        table = {name: replace(params, **moved) for name, params in table.items()}
    table[motion] = best_params
    figures = measure(motion, best_params)
    provenances = {name: provenance(params_path, name) for name in ["common", *table]}
    date = datetime.date.today().isoformat()
    provenances[motion] = Provenance.now(command).text(
        f"loss {best['loss']:.4f}; steady forward {figures['forward_m_s']:.3f} m/s, left {figures['left_m_s']:.3f} m/s "
        f"over {figures['time_s']:.0f} s, fell {figures['fell']}" + (f"; {note}" if note else ""))
    if common_keys:
        provenances["common"] = f"posture keys {', '.join(common_keys)} from the tuned {motion} ({date})"
    # Measured figures: the new ones for ``motion``, the file's own for every other section.
    raw = tomllib.loads(params_path.read_text(encoding="utf-8"))
    measured = {name: {key: float(raw[name][key]) for key in MEASURED_KEYS if key in raw.get(name, {})}
                for name in table}
    measured[motion] = {"measured_forward_m_s": figures["forward_m_s"], "measured_left_m_s": figures["left_m_s"],
                        "measured_stop_m": figures["stop_m"]}
    text = dumps_gait_params(common, table, provenances, read_header(params_path), measured)
    write_file(params_path, text, load_gait_params)
    names = tuple(table) if common_keys else (motion,)
    return write_gait_files(params_path, names=names)


def measure(motion: str, params: GaitParams, duration_s: float = 20.0, robot_type: int = 0,
            library: MotionLibrary | None = None) -> dict[str, float]:
    """Steady velocity of a plain run (for the motion file's measured constants); ``library`` holds the
    motion already (default: built from ``params`` for type 0)."""
    if library is None:
        library = candidate_library(motion, params)
    forward = DIRECTIONS[motion][0] > 0
    run = run_walk(library, motion, duration_s, position_m=(-13.5, 0.0) if forward else (0.0, 0.0),
                   x_limit_m=14.5 if forward else None, robot_type=robot_type)
    v_forward, v_left = run.steady_velocity_m_s()
    end = run.truths[run.walk_cycles - 1].torso_m[:2]
    stop_m = math.dist(end, run.truths[-1].torso_m[:2]) if not run.fell else 0.0
    return {"forward_m_s": v_forward, "left_m_s": v_left, "time_s": run.walk_time_s, "fell": run.fell,
            "stop_m": stop_m}


def measure_type(robot_type: int, names: Sequence[str] | None = None) -> Path:
    """Regenerate the walks of ``robot_type`` (``motions/files/type<N>``), measure them and write their figures
    into its override file (``motions/params/gait_type<N>.toml``, other keys kept), then regenerate them with
    the figures as constants."""
    from agent.motion import default_library
    from motions.authoring.toml_text import toml_value
    from motions.authoring.gait_types import WALK_NAMES, type_params_path, write_type_gait_files

    path = type_params_path(robot_type)
    raw = tomllib.loads(path.read_text(encoding="utf-8")) if path.is_file() else {}
    write_type_gait_files(robot_type)  # the files measured are those of the current overrides
    library = default_library(robot_type)
    date = datetime.date.today().isoformat()
    for name in names or WALK_NAMES:
        figures = measure(name, GaitParams(), robot_type=robot_type, library=library)
        section = {k: v for k, v in raw.get(name, {}).items() if k not in ("measured_forward_m_s", "measured_left_m_s",
                                                                        "measured_stop_m", "measured")}
        section["measured"] = (f"python -m motion_studio.tune_gait --measure-type {robot_type} on {date}: steady "
                               f"forward {figures['forward_m_s']:.3f} m/s, left {figures['left_m_s']:.3f} m/s over "
                               f"{figures['time_s']:.0f} s, fell {figures['fell']}")
        section.update(measured_forward_m_s=round(figures["forward_m_s"], 4),
                       measured_left_m_s=round(figures["left_m_s"], 4), measured_stop_m=round(figures["stop_m"], 4))
        raw[name] = section
    lines = [f"# Walk overrides and measured figures of robot type {robot_type} (motions.authoring.gait_types).",
             "# Units in the key names; a section's gait keys override the type-0 parameters of gait.toml.",
             f"# Measured keys written by python -m motion_studio.tune_gait --measure-type {robot_type}."]
    for name, section in raw.items():
        lines += ["", f"[{name}]"] + [f"{key} = {toml_value(value)}" for key, value in section.items()]
    write_file(path, "\n".join(lines) + "\n", lambda written: tomllib.loads(written.read_text(encoding="utf-8")))
    write_type_gait_files(robot_type)
    return path


def bounded(space: Sequence[Parameter], bounds: Sequence[str]) -> tuple[Parameter, ...]:
    """``space`` with the bounds of ``NAME=LOW:HIGH`` items replaced (a search kept to part of the space, e.g.
    only steps long enough for a faster walk).

    Raises:
        TuningError: a malformed item or a name not in the space (the message lists the names).
    """
    from motion_studio.tuning.errors import TuningError

    out = {parameter.name: parameter for parameter in space}
    for item in bounds:
        name, _, low_high = item.partition("=")
        low, _, high = low_high.partition(":")
        if name not in out:
            raise TuningError(f"--bound {item!r}: unknown parameter {name!r}; known: {', '.join(out)}")
        try:
            low_value, high_value = float(low), float(high)
        except ValueError:
            raise TuningError(f"--bound {item!r}: expected NAME=LOW:HIGH with numbers") from None
        out[name] = replace(out[name], low=low_value, high=high_value)  # a TuningError if low > high
    return tuple(out.values())


def _tune_real(args: argparse.Namespace, base: GaitParams, space: Sequence[Parameter], trials: Sequence[Trial],
               robust: Robust | None, checkpoint: Path, argv: list[str] | None) -> dict:
    """:func:`tune` judged on the real server (``--backend real``) or on both (``both``): the process re-runs
    itself inside the real-server scripts' private namespace first, then keeps one real server for the run."""
    import sys

    from motion_studio.realserver.gait_backend import RealJudge, real_trials
    from motion_studio.realserver.rollout_kick import ensure_private_network
    from motion_studio.realserver.rollout_walk import RealWalkBench

    ensure_private_network("motion_studio.tune_gait", list(argv) if argv is not None else sys.argv[1:])
    with RealWalkBench(args.real_workdir) as bench:
        judge = RealJudge(bench, args.motion, real_trials(args.motion, args.lean, args.quick),
                          tuple(trials) if args.backend == "both" else None,
                          robust if args.backend == "both" else None)
        # ours plays (and counts as rollouts) only with "both"
        return tune(args.motion, base, space, judge.ours_trials or (), args.generations, checkpoint, 1, args.sigma,
                    args.popsize, args.seed, robust=judge.robust, bar=True, judge=judge)


@one_line_errors("motion-studio tune gait")
def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="motion-studio tune gait", description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument("motion", choices=sorted(SPACES), nargs="?", help="walk to tune")
    parser.add_argument("--measure-type", type=int, default=None, metavar="N",
                        help="measure robot type N's shipped walks into gait_type<N>.toml and regenerate them")
    parser.add_argument("--generations", type=int, default=30, help="CMA-ES generations")
    parser.add_argument("--workers", type=int, default=1, help="local processes for the rollouts")
    parser.add_argument("--popsize", type=int, default=None, help="candidates per generation (default 4 + 3 ln n)")
    parser.add_argument("--sigma", type=float, default=0.15, help="initial step in box units (0-1)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the CMA-ES sampler")
    parser.add_argument("--step-cycles", type=int, default=None, help="fix step_cycles (cycles of 20 ms per step)")
    parser.add_argument("--checkpoint", type=Path, default=None,
                        help="run folder (checkpoint, trace, plots); default out/tuning/gait_<motion>_<step cycles>")
    parser.add_argument("--quick", action="store_true", help="one short trial per candidate (smoke test)")
    parser.add_argument("--lean", action="store_true", help="add full-lean trials (the walk must stay steerable)")
    parser.add_argument("--robust", type=int, default=0, metavar="N",
                        help="add N random transition trials per candidate (motion_studio.walk_trials)")
    parser.add_argument("--noise-deg", type=float, default=0.4, help="keyframe noise of half the robust trials")
    parser.add_argument("--posture", action="store_true", help="also search the posture (the shared stance)")
    parser.add_argument("--bound", action="append", default=[], metavar="NAME=LOW:HIGH",
                        help="narrow a searched parameter's bounds (e.g. step_length_m=0.072:0.09: only faster "
                             "gaits); repeatable")
    parser.add_argument("--validate", type=int, default=0, metavar="N",
                        help="before --write: re-rank the leading candidates on N transition trials")
    parser.add_argument("--base-json", type=Path, default=None, help="start from these parameters (JSON object)")
    parser.add_argument("--start-params", type=Path, default=None,
                        help="start from the motion's section of this gait parameter file (e.g. "
                             "motions/params/gait_fast.toml; its [common] posture included)")
    parser.add_argument("--backend", choices=("mujoco", *REAL_BACKENDS), default="mujoco",
                        help="where the candidates are judged: our simulator (default), the real rcssserver3d 0.7.3 "
                             "(motion_studio.realserver.rollout_walk, one walk at a time, the unpushed trials), or "
                             "both (the mean of the real and our loss)")
    parser.add_argument("--real-workdir", type=Path, default=Path("out/tune_gait_real"),
                        help="the real server's log and monitor frames (--backend real|both)")
    parser.add_argument("--write", action="store_true", help="write the best into gait.toml and regenerate")
    parser.add_argument("--common", action="store_true", help="with --write: the posture keys also go to [common]")
    args = parser.parse_args(argv)
    if args.measure_type is not None:
        print(measure_type(args.measure_type, [args.motion] if args.motion else None))
        return 0
    if args.motion is None:
        parser.error("a motion is needed unless --measure-type is given")
    base = load_gait_params(args.start_params or GAIT_PARAMS_PATH)[args.motion]
    if args.base_json:
        base = _params(json.loads(args.base_json.read_text()))
    if args.step_cycles:
        base = replace(base, step_cycles=args.step_cycles)
    suffix = ("_robust" if args.robust else "") + ("" if args.backend == "mujoco" else f"_{args.backend}")
    checkpoint = args.checkpoint or default_run_dir(f"gait_{args.motion}_{base.step_cycles}{suffix}")
    robust = Robust(count=args.robust, noise_deg=args.noise_deg) if args.robust else None
    space = bounded(SPACES[args.motion] + (POSTURE if args.posture else ()), args.bound)
    trials = default_trials(args.motion, args.quick, args.lean)
    if args.backend == "mujoco":
        data = tune(args.motion, base, space, trials, args.generations, checkpoint, args.workers, args.sigma,
                    args.popsize, args.seed, robust=robust, bar=True)
    else:
        data = _tune_real(args, base, space, trials, robust, checkpoint, argv)
    print(f"best loss {data['best']['loss']:.4f}: {data['best']['params']}")
    if args.validate:
        data["best"] = validate(data, trials, Robust(seed=10_000, count=args.validate, noise_deg=args.noise_deg))
        print(f"validated best loss {data['best']['loss']:.4f}: {data['best']['params']}")
    if args.write:
        command = (f"motion-studio tune gait {args.motion} --step-cycles {base.step_cycles} "
                   f"--generations {args.generations} --seed {args.seed}" + (" --lean" if args.lean else "")
                   + (f" --robust {args.robust} --noise-deg {args.noise_deg}" if args.robust else "")
                   + (f" --validate {args.validate}" if args.validate else "") + (" --posture" if args.posture else "")
                   + (f" --backend {args.backend}" if args.backend != "mujoco" else "")
                   + (f" --start-params {args.start_params}" if args.start_params else "")
                   + "".join(f" --bound {item}" for item in args.bound))
        keys = [d.name for d in POSTURE] if args.common else []
        from motion_studio.realserver.gait_backend import real_note

        for path in write_best(args.motion, data["best"], command, common_keys=keys,
                               note=real_note(data["best"]["result"])):
            print(path)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
