"""Walk benchmark on our simulator, with the real agent playing the shipped walks
(``motion_studio.walk_rollout`` over ``motion_studio.scenarios.Scenario``).

Trials:

* **run challenge** (magmaChallenge v3.2, REFERENCE §8.1): beam to (-13.5, 0); timing starts when the torso
  crosses x = -13 or 4 s after the beam, whichever is first; 20 s; score = speed (Δx / 20 s) + fraction of
  cycles with both feet off the ground; a fall ends the run and costs 2 m (never below 0).
* **20 m**: ``walk_forward`` from (-13.5, 0) until the torso has gone 20 m along x: time, speed, falls; then
  the stop through the walk's ``finalize`` (settled = standing still 2 s later; stopping distance).
* **20 m fast**: the same with ``walk_fast`` (the fast forward walk, issue 14: >= 0.8 m/s aimed) where the
  library has it.
* **backward / sideways**: each walk for 12 s from the centre: steady speed, drift, falls, stop.
* **lean**: ``walk_forward`` at full lean left and right (the ``[walk_lean]`` curve): curvature [deg/m].
* **walk to**: ``agent.skills.walk.WalkTo`` to points 2-3 m away (localization, not truth): time, final
  error, falls.

Targets (issue 6): forward >= 0.45 m/s with 0 falls over 20 m (floor), >= 0.70 m/s (aim).
"""

from __future__ import annotations

import math
import pathlib
from collections.abc import Callable

from agent.motion import MotionLibrary, default_library
from agent.skills.walk import FAST, WalkTo
from motion_studio.scenarios import Scenario, Truth
from motion_studio.walk_rollout import BALL_AWAY_M, CYCLE_S, WalkRun, run_walk

TARGETS = {"speed_floor_m_s": 0.45, "speed_aim_m_s": 0.70, "falls_20m": 0, "walk_to_error_m": 0.3}
#: REFERENCE §8.1 run challenge.
RUN_START_M = (-13.5, 0.0)
RUN_LINE_X_M = -13.0
RUN_WAIT_S = 4.0
RUN_TIME_S = 20.0
RUN_END_X_M = 14.5
FALL_PENALTY_M = 2.0
#: Side walks and lean trials.
SIDE_WALKS = ("walk_backward", "walk_left", "walk_right")
SIDE_TIME_S, SIDE_TIME_QUICK_S = 12.0, 5.0
LEAN_TIME_S, LEAN_TIME_QUICK_S = 10.0, 5.0
#: WalkTo trials: (start x, y, heading deg) -> target (x, y).
WALK_TO = (((-5.0, 0.0, 0.0), (-2.5, 0.5)), ((-5.0, 0.0, 0.0), (-4.0, 2.0)), ((-5.0, 0.0, 90.0), (-3.0, -1.0)))
WALK_TO_LIMIT_S = 30.0
#: Trace sampling for the plots [cycles].
TRACE_EVERY = 5


def run_challenge(run: WalkRun) -> dict:
    """Run-challenge figures of a forward run started at RUN_START_M (REFERENCE §8.1)."""
    truths = run.truths[:run.walk_cycles]
    start = next((i for i, t in enumerate(truths) if t.torso_m[0] >= RUN_LINE_X_M or i * CYCLE_S >= RUN_WAIT_S),
                 len(truths) - 1)
    end = min(len(truths) - 1, start + int(RUN_TIME_S / CYCLE_S))
    end = next((i for i in range(start, end + 1) if truths[i].torso_m[0] >= RUN_END_X_M), end)
    fell = run.fall_cycle is not None and run.fall_cycle <= start + int(RUN_TIME_S / CYCLE_S)
    if fell:
        end = min(end, run.fall_cycle or end)
    distance = truths[end].torso_m[0] - truths[start].torso_m[0]
    if fell:
        distance = max(0.0, distance - FALL_PENALTY_M)
    timed = truths[start:end + 1]
    off = sum(t.feet_off_ground for t in timed) / max(1, len(timed))
    speed = distance / RUN_TIME_S
    return {"score": round(speed + off, 3), "speed_m_s": round(speed, 3), "feet_off_fraction": round(off, 4),
            "distance_m": round(distance, 3), "fell": fell}


def twenty_metres(run: WalkRun) -> dict:
    """Time and speed over the first 20 m along x, stop figures."""
    x0 = run.truths[0].torso_m[0]
    reached = next((i for i, t in enumerate(run.truths[:run.walk_cycles]) if t.torso_m[0] - x0 >= 20.0), None)
    end = run.truths[run.walk_cycles - 1]
    stop_m = (math.dist(run.truths[-1].torso_m[:2], end.torso_m[:2]) if not run.fell else None)
    time_s = None if reached is None else (reached + 1) * CYCLE_S
    return {"time_s": None if time_s is None else round(time_s, 2),
            "speed_m_s": None if time_s is None else round(20.0 / time_s, 3),
            "steady_speed_m_s": round(run.steady_velocity_m_s()[0], 3),
            "falls": int(run.fell), "heading_change_deg": round(run.heading_change_deg, 1),
            "lateral_drift_m": round(run.displacement_m()[1], 3),
            "stop_settled": run.settled, "stop_fell": run.fell_stopping,
            "stop_distance_m": None if stop_m is None else round(stop_m, 3)}


def side_walk(run: WalkRun) -> dict:
    forward, left = run.steady_velocity_m_s()
    return {"forward_m_s": round(forward, 3), "left_m_s": round(left, 3), "falls": int(run.fell),
            "heading_change_deg": round(run.heading_change_deg, 1), "stop_settled": run.settled}


def lean_trial(run: WalkRun) -> dict:
    return {"curvature_deg_m": round(run.curvature_deg_m, 2), "heading_change_deg": round(run.heading_change_deg, 1),
            "path_m": round(run.path_length_m(run.walk_cycles), 2), "falls": int(run.fell)}


def walk_to_trial(start: tuple[float, float, float], target: tuple[float, float], seed: int,
                  library: MotionLibrary | None = None, robot_type: int = 0) -> dict:
    """WalkTo from ``start`` (x, y, heading deg) to ``target`` (field frame = the left team's frame) by a robot
    of ``robot_type`` (with ``library``, else the shipped motions of that type)."""
    skill = WalkTo(*target)
    controller = None
    if library is not None:
        from motion_studio.walk_rollout import make_controller
        controller = make_controller(library, robot_type=robot_type)
    scenario = Scenario(skill, position_m=start[:2], heading_deg=start[2], robot_type=robot_type, seed=seed,
                        controller=controller, recover_falls=False, ball_m=BALL_AWAY_M)
    truths: list[Truth] = scenario.run(int(WALK_TO_LIMIT_S / CYCLE_S), stop=lambda t: skill.done or t.fallen)
    end = truths[-1]
    return {"start": list(start), "target": list(target), "done": skill.done, "reached": skill.reached,
            "time_s": round(len(truths) * CYCLE_S, 2), "error_m": round(math.dist(end.torso_m[:2], target), 3),
            "fell": end.fallen, "corrections": skill.corrections}


def _trace(run: WalkRun) -> dict:
    points = run.truths[::TRACE_EVERY]
    return {"time_s": [round(t.time_s - run.truths[0].time_s, 2) for t in points],
            "x_m": [round(t.torso_m[0], 3) for t in points], "y_m": [round(t.torso_m[1], 3) for t in points],
            "z_m": [round(t.torso_m[2], 3) for t in points], "walk_end_s": round(run.walk_time_s, 2)}


def run(quick: bool = False, seed: int = 0, progress: Callable[[int, int], None] | None = None,
        library: MotionLibrary | None = None, robot_type: int = 0) -> dict:
    """All walk trials of a robot of ``robot_type`` (0-4) playing ``library`` (default: that type's shipped
    motions); JSON-ready figures with ``robot_type``, ``score`` (the run challenge's), ``targets`` and
    ``passed``."""
    library = library or default_library(robot_type)
    walk_to = WALK_TO[:1] if quick else WALK_TO
    fast = FAST in library
    total = 2 + int(fast) + len(SIDE_WALKS) + 2 + len(walk_to)
    done = 0

    def tick() -> None:
        nonlocal done
        done += 1
        if progress is not None:
            progress(done, total)

    forward_s = 8.0 if quick else 45.0
    challenge = run_walk(library, "walk_forward", RUN_WAIT_S + RUN_TIME_S if not quick else 8.0, position_m=RUN_START_M,
                         x_limit_m=RUN_END_X_M, seed=seed, robot_type=robot_type)
    tick()
    long_run = challenge if quick else run_walk(library, "walk_forward", forward_s, position_m=RUN_START_M,
                                                x_limit_m=RUN_START_M[0] + 20.5, seed=seed,
                                                robot_type=robot_type)
    tick()
    fast_run = None
    if fast:
        fast_run = run_walk(library, FAST, 8.0 if quick else forward_s, position_m=RUN_START_M,
                            x_limit_m=RUN_START_M[0] + 20.5, seed=seed, robot_type=robot_type)
        tick()
    sides = {}
    for name in SIDE_WALKS:
        sides[name] = side_walk(run_walk(library, name, SIDE_TIME_QUICK_S if quick else SIDE_TIME_S,
                                         position_m=(0.0, 0.0), x_limit_m=None, seed=seed,
                                         robot_type=robot_type))
        tick()
    leans = {}
    for label, lean in (("left", 1.0), ("right", -1.0)):
        leans[label] = lean_trial(run_walk(library, "walk_forward", LEAN_TIME_QUICK_S if quick else LEAN_TIME_S,
                                           position_m=(-8.0, 0.0), lean=lean, x_limit_m=None, seed=seed,
                                           robot_type=robot_type))
        tick()
    walk_to_results = []
    for start, target in walk_to:
        walk_to_results.append(walk_to_trial(start, target, seed, library, robot_type))
        tick()
    challenge_figures = run_challenge(challenge)
    twenty = twenty_metres(long_run)
    speed = twenty["speed_m_s"] or 0.0
    fast_twenty = twenty_metres(fast_run) if fast_run is not None else None
    falls = (twenty["falls"] + (fast_twenty["falls"] if fast_twenty else 0) + sum(s["falls"] for s in sides.values())
             + sum(l["falls"] for l in leans.values()))
    passed = {
        "speed_floor": (not quick) and speed >= TARGETS["speed_floor_m_s"] and twenty["falls"] == 0,
        "speed_aim": (not quick) and speed >= TARGETS["speed_aim_m_s"] and twenty["falls"] == 0,
        "no_falls": falls == 0 and not any(r["fell"] for r in walk_to_results),
        "stop_settled": bool(twenty["stop_settled"]),
        "walk_to": all(r["error_m"] <= TARGETS["walk_to_error_m"] for r in walk_to_results),
    }
    return {
        "robot_type": robot_type,
        "score": challenge_figures["score"],
        "quick": quick, "seed": seed,
        "run_challenge": challenge_figures,
        "forward_20m": twenty,
        "fast_20m": fast_twenty,
        "side_walks": sides,
        "lean_full": leans,
        "lean_curvature_deg_m": round((leans["left"]["curvature_deg_m"] - leans["right"]["curvature_deg_m"]) / 2, 2),
        "walk_to": walk_to_results,
        "falls": falls,
        "targets": TARGETS,
        "passed": passed,
        "traces": {"run_challenge": _trace(challenge)},
    }


def plot(result: dict, out_dir: pathlib.Path) -> list[pathlib.Path]:
    """``walk_type<N>.png`` (N = the result's robot type): the run challenge's x over time, speed (1 s window)
    and torso height."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    trace = result["traces"]["run_challenge"]
    t, x, z = trace["time_s"], trace["x_m"], trace["z_m"]
    window = max(1, int(round(1.0 / (TRACE_EVERY * CYCLE_S))))
    speed_t = t[window:]
    speed = [(x[i] - x[i - window]) / (t[i] - t[i - window]) for i in range(window, len(t))]
    fig, axes = plt.subplots(3, 1, figsize=(8, 8), sharex=True)
    axes[0].plot(t, x)
    axes[0].set_ylabel("torso x [m]")
    challenge = result["run_challenge"]
    axes[0].set_title(f"type {result.get('robot_type', 0)} run challenge: score {challenge['score']}, "
                      f"speed {challenge['speed_m_s']} m/s, "
                      f"20 m: {result['forward_20m']['speed_m_s']} m/s"
                      + (f", fast {result['fast_20m']['speed_m_s']} m/s" if result.get("fast_20m") else "")
                      + f", falls {result['falls']}")
    axes[1].plot(speed_t, speed)
    axes[1].axhline(TARGETS["speed_floor_m_s"], color="tab:red", linestyle="--", label="floor 0.45 m/s")
    axes[1].axhline(TARGETS["speed_aim_m_s"], color="tab:green", linestyle="--", label="aim 0.70 m/s")
    axes[1].set_ylabel("speed (1 s) [m/s]")
    axes[1].legend(loc="lower right")
    axes[2].plot(t, z)
    axes[2].axhline(0.25, color="tab:red", linestyle="--", label="fall (0.25 m)")
    axes[2].set_ylabel("torso height [m]")
    axes[2].set_xlabel("time since the walk request [s]")
    axes[2].legend(loc="lower right")
    for axis in axes:
        axis.axvline(trace["walk_end_s"], color="grey", linestyle=":")
        axis.grid(alpha=0.3)
    fig.tight_layout()
    path = out_dir / f"walk_type{result.get('robot_type', 0)}.png"
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return [path]


__all__ = ["TARGETS", "plot", "run", "run_challenge"]
