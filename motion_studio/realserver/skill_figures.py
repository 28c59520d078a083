"""The figures of one skill case run (``motion-studio real skills``): falls, turning, displacement, speed,
ball, standing up; and the side-by-side table of the real and our run."""

from __future__ import annotations

import math

from motion_studio.realserver.cases import CYCLE_S, STAND_CYCLES, Case
from motion_studio.skill_bench.dribble import KEEP_M, measure
from motion_studio.realserver.measures import fallen, first_fall, pose_of, stood_index, wrap_deg
from motion_studio.realserver.skill_runs import Run


def figures(run: Run, case: Case) -> dict[str, float | str]:
    """The measured figures of a run (NaN where the truth is missing)."""
    truths = [t for t in run.truths if t is not None]
    if not truths:
        return {"truth cycles": 0}
    first = truths[0]
    out: dict[str, float | str] = {"truth cycles": len(truths), "self-collision pairs": run.self_collisions}
    if run.where == "real":
        out["sense msgs rejected (real)"] = run.bad_messages
    if run.where == "sim":
        out["self-collision fouls"] = run.fouls
        out["blow-ups (ours)"] = run.blow_ups
    fall = first_fall(run.truths)
    out["first fall [s]"] = math.nan if fall is None else fall * CYCLE_S
    heading, turned = first.heading_deg, 0.0
    for t in truths[1:]:
        turned += wrap_deg(t.heading_deg - heading)
        heading = t.heading_deg
    out["turn total [deg]"] = turned
    end_index = (case.walk_cycles or case.cycles) - 1
    end = next((run.truths[i] for i in range(min(end_index, len(run.truths) - 1), -1, -1)
                if run.truths[i] is not None), truths[-1])
    c, s = math.cos(math.radians(first.heading_deg)), math.sin(math.radians(first.heading_deg))
    dx, dy = end.torso_m[0] - first.torso_m[0], end.torso_m[1] - first.torso_m[1]
    out["forward [m]"], out["left [m]"] = c * dx + s * dy, -s * dx + c * dy
    out["heading change [deg]"] = wrap_deg(end.heading_deg - first.heading_deg)
    upright = [t for t in truths if not fallen(t)]
    out["torso z mean [m]"] = sum(t.torso_m[2] for t in upright) / max(1, len(upright))
    out["up_z min"] = min(t.up_z for t in truths)
    if case.walk_cycles:
        seconds = case.walk_cycles * CYCLE_S
        out["speed [m/s]"] = math.hypot(dx, dy) / seconds
        start = run.truths[min(150, len(run.truths) - 1)]
        if start is not None and fall is None:
            out["speed after 3 s [m/s]"] = math.dist(start.torso_m[:2], end.torso_m[:2]) / (seconds - 3.0)
    out.update(orbit_figures(run, case))
    turns = [i for i, name in run.completions if name.startswith("turn_")]
    if turns:
        headings = []
        for i in [0, *turns]:
            t = next((run.truths[j] for j in range(i, -1, -1) if run.truths[j] is not None), None)
            headings.append(t.heading_deg if t is not None else math.nan)
        per = [wrap_deg(b - a) for a, b in zip(headings, headings[1:])]
        out["turn motions"] = len(turns)
        out["turn per motion [deg]"] = sum(per) / len(per)
        out["turn per motion min/max"] = f"{min(per):.1f}/{max(per):.1f}"
        out["turn motion [s]"] = turns[0] * CYCLE_S if len(turns) == 1 else (turns[-1] - turns[0]) * CYCLE_S / (
            len(turns) - 1)
        out["turn rate [deg/s]"] = sum(per) / (turns[-1] * CYCLE_S)
        out["drift [m]"] = math.dist(first.torso_m[:2], end.torso_m[:2])
    if (case.ball_m is not None or case.kick) and not math.isnan(first.ball_m[0]):
        out["ball moved [m]"] = math.dist(first.ball_m[:2], truths[-1].ball_m[:2])
        if case.kick or case.motion == "kick":   # a kick motion, or KickToward's line-up (aimed along the start heading)
            dx, dy = truths[-1].ball_m[0] - first.ball_m[0], truths[-1].ball_m[1] - first.ball_m[1]
            out["ball direction [deg]"] = wrap_deg(math.degrees(math.atan2(dy, dx)) - first.heading_deg)
    out.update(dribble_figures(run, case))
    if case.fall:
        # stood up: the torso centre above 0.30 m for 1 s after the fall (measures.stood_index; an upright
        # tilt alone is no stand: a robot sitting upright keeps its torso below 0.30 m)
        stood = stood_index(run.truths, fall + 1) if fall is not None else None
        out["stood up after [s]"] = math.nan if stood is None else (stood - fall) * CYCLE_S
        out["upright at end"] = "yes" if truths[-1].up_z > 0.9 and truths[-1].torso_m[2] > 0.3 else "no"
    return out


def orbit_figures(run: Run, case: Case) -> dict[str, float]:
    """An orbit case's circle (``circle_fit`` of the torso's path while it walks): its centre ahead of and left of
    the start pose, and its radius [m]; empty for any other case or a run that fell (shared by ``motion-studio real
    skills`` and ``motion-studio transfer``)."""
    if case.motion is None or not case.motion.startswith("orbit_") or first_fall(run.truths) is not None:
        return {}
    walked = [t for t in run.truths[:case.walk_cycles] if t is not None]
    circle = circle_fit([t.torso_m[:2] for t in walked])   # None for fewer than three poses
    if circle is None:
        return {}
    (cx, cy), radius = circle
    ahead, left = pose_of(walked[0]).to_ego(cx, cy)
    return {"orbit centre ahead [m]": ahead, "orbit centre left [m]": left, "orbit radius [m]": radius}


def circle_fit(points: list[tuple[float, float]]) -> tuple[tuple[float, float], float] | None:
    """Centre and radius [m] of the circle nearest to ``points`` (algebraic least squares: x² + y² = 2ax + 2by + c);
    None for fewer than three points or points on a line. Why: an orbit walks round a point ahead of its start, and
    where that point lies says whether the ball it circles stays ahead of the feet."""
    import numpy as np

    if len(points) < 3:
        return None
    xy = np.asarray(points, dtype=float)
    matrix = np.column_stack([2.0 * xy[:, 0], 2.0 * xy[:, 1], np.ones(len(xy))])
    (a, b, c), _, rank, _ = np.linalg.lstsq(matrix, (xy ** 2).sum(axis=1), rcond=None)
    if rank < 3:
        return None
    return (float(a), float(b)), float(math.sqrt(max(0.0, c + a * a + b * b)))


def dribble_figures(run: Run, case: Case) -> dict[str, float | str]:
    """The dribble benchmark's figures of a dribble case's run (``skill_bench.dribble.measure`` after the stand);
    empty for any other case (shared by ``motion-studio real skills`` and ``motion-studio transfer``)."""
    if case.dribble is None or case.ball_m is None:
        return {}
    direction_deg, way_m = case.dribble
    dribble = measure(run.truths[STAND_CYCLES:], case.ball_m, direction_deg, way_m,
                      run.modes[STAND_CYCLES:] if run.modes else None)
    out: dict[str, float | str] = {
        "dribble ball way [m]": way_m,
        "dribble time [s]": math.nan if dribble["time_s"] is None else dribble["time_s"],
        "dribble speed [m/s]": math.nan if dribble["speed_m_s"] is None else dribble["speed_m_s"],
        f"ball within {KEEP_M} m [share]": dribble["keep_share"]}
    for label, key in (("p95", "distance_p95_m"), ("max", "distance_max_m")):
        out[f"ball from torso {label} [m]"] = math.nan if dribble[key] is None else dribble[key]
    out["dribble fell"] = "yes" if dribble["fell"] else "no"
    for group, seconds in dribble.get("time_by_mode_s", {}).items():
        out[f"dribble {group} [s]"] = seconds
    return out


def table(case: Case, real: dict, sim: dict) -> str:
    """The figures of both runs side by side, with ours - real."""
    title = f"{case.name} (robot type {case.robot_type})" if case.robot_type else case.name
    rows = [title, f"  {'figure':28s} {'real 0.7.3':>14s} {'ours':>14s} {'ours - real':>12s}"]
    for key in dict.fromkeys([*real, *sim]):
        a, b = real.get(key, ""), sim.get(key, "")
        diff = b - a if isinstance(a, (int, float)) and isinstance(b, (int, float)) else ""
        rows.append(f"  {key:28s} {_cell(a):>14s} {_cell(b):>14s} {_cell(diff):>12s}")
    return "\n".join(rows)


def _cell(value: object) -> str:
    if isinstance(value, float):
        return "-" if math.isnan(value) else f"{value:.3f}"
    return str(value)
