"""Turn benchmark on our simulator: turn rate left and right, turn per motion against the gain, and the error
of the turn-gain prediction over requested turns, with the real agent (``motion_studio.scenarios.Scenario``).

Trials (each on a fresh simulator, the robot first stepping once in place into the walk stance):

* **rate**: ``turn_left`` / ``turn_right`` played back to back at gain 1 for several motions; rate = truth
  heading change / time, drift = torso displacement per motion.
* **gain sweep**: turn per motion at gains 0.3..1.0 (the data the ``[turn_gain]`` curve is fitted to,
  ``motion_studio.tune_turn``).
* **prediction**: ``agent.skills.turn.TurnBy(angle)`` by dead reckoning only (no localization), for
  requested angles 3..60 deg both ways; predicted = the curve's turn for the motions it played, measured =
  truth heading change. A request beyond one motion's range plays several motions.

No league challenge scores turning (REFERENCE §8), so ``score`` is the mean turn rate [deg/s]. Targets: issue 6
(turn >= 30 deg/s, aim 60 deg/s, no falls); the prediction error target (mean |error| <= 2 deg) is ours.
"""

from __future__ import annotations

import math
import pathlib
from collections.abc import Callable
from dataclasses import dataclass

from functools import lru_cache

from agent.motion import MotionController, MotionLibrary, default_library, load_dynamic_params
from agent.motion.dynamic import DynamicParams
from agent.skills.base import PlayMotion, Skill
from agent.skills.turn import TURN_MOTIONS, TurnBy
from motion_studio.scenarios import Scenario, Truth

#: Requested turns of the prediction trials [deg] (each played left and right).
REQUESTED_DEG = (3.0, 6.0, 10.0, 15.0, 20.0, 25.0, 30.0, 40.0, 50.0, 60.0)
REQUESTED_QUICK_DEG = (3.0, 10.0, 20.0, 30.0, 45.0, 60.0, 8.0, 52.0)
#: Gains of the sweep.
GAINS = (0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)
GAINS_QUICK = (0.3, 0.65, 1.0)
#: Motions per rate / sweep trial.
RATE_MOTIONS, RATE_MOTIONS_QUICK = 10, 4
SWEEP_MOTIONS, SWEEP_MOTIONS_QUICK = 6, 3
#: Cycles of settling after the first step in place, and after a TurnBy before measuring.
SETTLE_CYCLES = 10
#: A trial longer than this is cut (a stuck skill) [s].
TRIAL_LIMIT_S = 20.0
TARGETS = {"turn_rate_deg_s": 30.0, "turn_rate_aim_deg_s": 60.0, "falls": 0,
           "prediction_error_mean_abs_deg": 2.0}


@dataclass
class TurnRun:
    """What one trial measured (truth)."""

    turn_deg: float
    """Heading change, + = left [deg]."""
    duration_s: float
    drift_m: float
    """Torso ground displacement from start to end [m]."""
    fell: bool
    motions: int


def _unwrapped_turn_deg(history: list[Truth]) -> float:
    total = 0.0
    for a, b in zip(history, history[1:]):
        total += (b.heading_deg - a.heading_deg + 180.0) % 360.0 - 180.0
    return total


@lru_cache(maxsize=8)
def _library(robot_type: int, motions_dir: pathlib.Path | None) -> MotionLibrary:
    """The motion library of a robot type, read once per type and folder (controllers only read it)."""
    return default_library(robot_type, motions_dir)


def new_scenario(seed: int = 0, dynamic: DynamicParams | None = None, motions_dir: pathlib.Path | None = None,
                 side: str = "left", robot_type: int = 0) -> tuple[Scenario, MotionController]:
    """A robot of ``robot_type`` at (-5, 0) facing +x that has stepped once in place into the walk stance (turn
    gain base), playing that type's motions, without fall recovery (a fall ends a trial)."""
    controller = MotionController(_library(robot_type, motions_dir), dynamic or load_dynamic_params(), robot_type)
    base = controller.library.gain_bases[TURN_MOTIONS[side]]
    scenario = Scenario(PlayMotion(base), controller=controller, recover_falls=False, seed=seed,
                        robot_type=robot_type)
    scenario.run(int(3.0 / 0.02), stop=lambda truth: controller.completed[base] > 0)
    scenario.set_skill(None)
    scenario.run(SETTLE_CYCLES)
    return scenario, controller


def _run_skill(scenario: Scenario, skill: Skill, done: Callable[[], bool], settle_cycles: int = 0) -> TurnRun:
    start = scenario.history[-1]
    first = len(scenario.history) - 1
    scenario.set_skill(skill)
    fell = False
    while not done() and scenario.engine.time_s - start.time_s < TRIAL_LIMIT_S:
        truth = scenario.run(1)[0]
        if truth.fallen:
            fell = True
            break
    end_time = scenario.history[-1].time_s
    if not fell and settle_cycles:
        scenario.set_skill(None)
        fell = any(t.fallen for t in scenario.run(settle_cycles))
    history = scenario.history[first:]
    end = history[-1]
    drift = math.hypot(end.torso_m[0] - start.torso_m[0], end.torso_m[1] - start.torso_m[1])
    return TurnRun(_unwrapped_turn_deg(history), end_time - start.time_s, drift, fell, 0)


def run_motions(side: str, gain: float, motions: int, seed: int = 0, dynamic: DynamicParams | None = None,
                motions_dir: pathlib.Path | None = None, robot_type: int = 0) -> TurnRun:
    """Play the turn motion of ``side`` back to back ``motions`` times at ``gain``; truth of the whole run."""
    scenario, controller = new_scenario(seed, dynamic, motions_dir, side, robot_type)
    name = TURN_MOTIONS[side]
    before = controller.completed[name]
    run = _run_skill(scenario, PlayMotion(name, repeat=True, gain=gain),
                     lambda: controller.completed[name] - before >= motions)
    run.motions = controller.completed[name] - before
    return run


def run_turn_by(angle_deg: float, seed: int = 0, dynamic: DynamicParams | None = None,
                motions_dir: pathlib.Path | None = None, robot_type: int = 0) -> tuple[TurnRun, float]:
    """TurnBy(angle) by dead reckoning; returns the truth of the run (after settling) and the predicted turn."""
    scenario, controller = new_scenario(seed, dynamic, motions_dir, "left" if angle_deg > 0 else "right",
                                        robot_type)
    skill = TurnBy(angle_deg, tolerance_deg=0.5, use_localization=False)
    run = _run_skill(scenario, skill, lambda: skill.done, settle_cycles=SETTLE_CYCLES)
    run.motions = skill.motions_played
    return run, skill.predicted_deg


def gain_sweep(gains: tuple[float, ...], motions: int, seed: int = 0, dynamic: DynamicParams | None = None,
               motions_dir: pathlib.Path | None = None, progress: Callable[[], None] | None = None,
               robot_type: int = 0) -> list[dict[str, float | bool]]:
    """Turn per motion [deg] at each gain, left and right (right reported as a positive turn)."""
    rows = []
    for gain in gains:
        row: dict[str, float | bool] = {"gain": gain}
        for side, sign in (("left", 1.0), ("right", -1.0)):
            run = run_motions(side, gain, motions, seed, dynamic, motions_dir, robot_type)
            row[f"{side}_deg"] = round(sign * run.turn_deg / max(run.motions, 1), 2)
            row[f"{side}_fell"] = run.fell
            if progress:
                progress()
        rows.append(row)
    return rows


def run(quick: bool = False, seed: int = 0, progress: Callable[[int, int], None] | None = None,
        robot_type: int = 0) -> dict:
    """The turn figures of a robot of ``robot_type`` (0-4) with its shipped motions (see the module
    docstring); JSON-ready, with ``robot_type``."""
    dynamic = load_dynamic_params()
    curve = dynamic.turn_gain
    requested = REQUESTED_QUICK_DEG if quick else REQUESTED_DEG
    gains = GAINS_QUICK if quick else GAINS
    rate_motions = RATE_MOTIONS_QUICK if quick else RATE_MOTIONS
    total = 2 + 2 * len(gains) + 2 * len(requested)
    done = 0

    def tick() -> None:
        nonlocal done
        done += 1
        if progress:
            progress(done, total)

    falls = 0
    rates: dict[str, dict[str, float]] = {}
    for side, sign in (("left", 1.0), ("right", -1.0)):
        trial = run_motions(side, 1.0, rate_motions, seed, dynamic, robot_type=robot_type)
        falls += trial.fell
        rates[side] = {"rate_deg_s": round(sign * trial.turn_deg / trial.duration_s, 1),
                       "turn_per_motion_deg": round(sign * trial.turn_deg / max(trial.motions, 1), 2),
                       "drift_per_motion_m": round(trial.drift_m / max(trial.motions, 1), 4),
                       "motions": trial.motions, "fell": trial.fell}
        tick()
    sweep = gain_sweep(gains, SWEEP_MOTIONS_QUICK if quick else SWEEP_MOTIONS, seed, dynamic, progress=tick,
                       robot_type=robot_type)
    falls += sum(bool(row["left_fell"]) + bool(row["right_fell"]) for row in sweep)
    trials = []
    for angle in requested:
        for sign in (1.0, -1.0):
            trial, predicted = run_turn_by(sign * angle, seed, dynamic, robot_type=robot_type)
            falls += trial.fell
            trials.append({"requested_deg": sign * angle, "predicted_deg": round(predicted, 2),
                           "measured_deg": round(trial.turn_deg, 2), "motions": trial.motions,
                           "drift_m": round(trial.drift_m, 4), "fell": trial.fell})
            tick()
    errors = [t["measured_deg"] - t["predicted_deg"] for t in trials]
    request_errors = [t["measured_deg"] - t["requested_deg"] for t in trials]
    mean_rate = (rates["left"]["rate_deg_s"] + rates["right"]["rate_deg_s"]) / 2.0
    prediction = {"mean_abs_deg": round(sum(map(abs, errors)) / len(errors), 2),
                  "max_abs_deg": round(max(map(abs, errors)), 2),
                  "mean_deg": round(sum(errors) / len(errors), 2),
                  "request_mean_abs_deg": round(sum(map(abs, request_errors)) / len(request_errors), 2),
                  "request_max_abs_deg": round(max(map(abs, request_errors)), 2)}
    slowest = min(rates["left"]["rate_deg_s"], rates["right"]["rate_deg_s"])
    return {
        "robot_type": robot_type,
        "score": round(mean_rate, 1),
        "score_note": "no league turn challenge: score = mean turn rate [deg/s]",
        "rate_left_deg_s": rates["left"]["rate_deg_s"], "rate_right_deg_s": rates["right"]["rate_deg_s"],
        "rates": rates, "falls": falls, "prediction_error": prediction, "prediction_trials": trials,
        "gain_sweep": sweep,
        "turn_gain_curve": {"min_gain": curve.min_gain, "offset_deg": curve.offset_deg, "span_deg": curve.span_deg,
                            "predicted_base_deg": curve.predicted_base_deg,
                            "predicted_slope_deg": curve.predicted_slope_deg},
        "targets": TARGETS,
        "passed": {"turn_rate": slowest >= TARGETS["turn_rate_deg_s"],
                   "turn_rate_aim": slowest >= TARGETS["turn_rate_aim_deg_s"],
                   "no_falls": falls == TARGETS["falls"],
                   "prediction_error": prediction["mean_abs_deg"] <= TARGETS["prediction_error_mean_abs_deg"]},
        "quick": quick, "seed": seed,
    }


def plot(result: dict, out_dir: pathlib.Path) -> list[pathlib.Path]:
    """turn_type<N>.png (N = the result's robot type): measured vs predicted turn over the requests, turn per
    motion vs gain, and the rates."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir.mkdir(parents=True, exist_ok=True)
    fig, (ax_pred, ax_gain, ax_rate) = plt.subplots(1, 3, figsize=(15, 4.5))
    trials = result["prediction_trials"]
    requested = [abs(t["requested_deg"]) for t in trials]
    ax_pred.plot([0, max(requested)], [0, max(requested)], color="0.7", lw=1, label="requested")
    for sign, marker, side in ((1.0, "o", "left"), (-1.0, "s", "right")):
        chosen = [t for t in trials if t["requested_deg"] * sign > 0]
        ax_pred.scatter([abs(t["requested_deg"]) for t in chosen], [abs(t["predicted_deg"]) for t in chosen],
                        marker=marker, facecolors="none", edgecolors="C0", label=f"predicted ({side})")
        ax_pred.scatter([abs(t["requested_deg"]) for t in chosen], [abs(t["measured_deg"]) for t in chosen],
                        marker=marker, color="C1", s=14, label=f"measured ({side})")
    error = result["prediction_error"]
    ax_pred.set(xlabel="requested turn [deg]", ylabel="turn [deg]",
                title=f"TurnBy, dead reckoning: |measured - predicted| mean {error['mean_abs_deg']} deg, "
                      f"max {error['max_abs_deg']} deg")
    ax_pred.title.set_fontsize(9)
    ax_pred.legend(fontsize=7)
    sweep = result["gain_sweep"]
    gains = [row["gain"] for row in sweep]
    ax_gain.plot(gains, [row["left_deg"] for row in sweep], "o-", label="measured left")
    ax_gain.plot(gains, [row["right_deg"] for row in sweep], "s--", label="measured right")
    curve = result["turn_gain_curve"]
    span = 1.0 - curve["min_gain"]
    line = [curve["predicted_base_deg"] + curve["predicted_slope_deg"] * (g - curve["min_gain"]) / span for g in gains]
    ax_gain.plot(gains, line, color="k", lw=1, label="[turn_gain] prediction")
    ax_gain.set(xlabel="gain", ylabel="turn per motion [deg]", title="turn per motion vs gain")
    ax_gain.legend(fontsize=8)
    sides = ["left", "right"]
    values = [result["rates"][s]["rate_deg_s"] for s in sides]
    ax_rate.bar(sides, values, color=["C0", "C1"])
    for level, label in ((result["targets"]["turn_rate_deg_s"], "target"),
                         (result["targets"]["turn_rate_aim_deg_s"], "aim")):
        ax_rate.axhline(level, color="0.4", ls=":", lw=1)
        ax_rate.text(1.45, level, label, va="bottom", ha="right", fontsize=8)
    ax_rate.set(ylabel="turn rate at gain 1 [deg/s]",
                title=f"type {result.get('robot_type', 0)} turn rate (falls: {result['falls']})")
    fig.tight_layout()
    path = out_dir / f"turn_type{result.get('robot_type', 0)}.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return [path]


__all__ = ["GAINS", "REQUESTED_DEG", "TARGETS", "TurnRun", "gain_sweep", "new_scenario", "plot", "run",
           "run_motions", "run_turn_by"]
