"""The figures of a played match (match_play.Played), the same for both servers: the monitor stream gives play
modes, goals, the ball's path and how far it got, falls per robot (torso below 0.25 m, standing again above 0.30
m, as sim/match.py counts them), where each robot stood at kick-off against its beam spot, and referee fouls;
the watched agents give their kicks (judged by the ball's move in KICK_EFFECT_S and where the ball lay in the
kicker's torso frame), motion starts and localization error (belief against the monitor's torso at the same
game time)."""

from __future__ import annotations

import collections
import math
import re
from pathlib import Path
from typing import Any

from motion_studio.realserver.match_play import BALL_TELEPORT_M, CYCLE_S, KICK_EFFECT_S, LEFT_TEAM, Played


def _frames(path: Path):  # noqa: ANN202 - Iterator[sim.replay.ReplayFrame]
    from sim.replay import read_log

    return read_log(path)


def _heading(torso: Any) -> float:
    return math.atan2(float(torso[1, 1]), float(torso[0, 1]))


def _wrap(angle_rad: float) -> float:
    return (angle_rad + math.pi) % (2 * math.pi) - math.pi


def _percentile(values: list[float], q: float) -> float:
    if not values:
        return math.nan
    ordered = sorted(values)
    index = q * (len(ordered) - 1)
    low = math.floor(index)
    high = min(low + 1, len(ordered) - 1)
    return ordered[low] + (ordered[high] - ordered[low]) * (index - low)


def figures(played: Played) -> dict[str, Any]:
    from agent.formation import beam_spot
    from sim.match import FALLEN_TORSO_Z_M, STANDING_AGAIN_Z_M
    from sim.rules.params import PLAY_MODES

    modes: list[str] = []
    previous_mode = None
    fallen: dict[str, bool] = {}
    falls: collections.Counter[str] = collections.Counter()
    truth: dict[Any, tuple[float, float, float]] = {}
    balls: dict[int, tuple[float, float]] = {}
    ball_path, ball_far, ball_x = 0.0, 0.0, [math.inf, -math.inf]
    last_ball = None
    score = (0, 0)
    goals = 0
    frames = 0
    at_kick_off: dict[str, tuple[float, float]] = {}
    before: dict[str, tuple[float, float]] = {}
    game_time = 0.0
    first_play_on = None
    seen: set[str] = set()
    for frame in _frames(played.monitor_log):
        if frame.time_s > played.until_s + CYCLE_S / 2:
            break
        frames += 1
        mode = PLAY_MODES[frame.play_mode] if frame.play_mode is not None and frame.play_mode < len(PLAY_MODES) \
            else "unknown"
        if mode != previous_mode:
            modes.append(f"{mode}@{frame.time_s:.1f}")
            goals += mode.startswith("Goal_")
            if previous_mode == "BeforeKickOff" and not at_kick_off:
                at_kick_off = dict(before)
            if mode == "PlayOn" and first_play_on is None:
                first_play_on = frame.time_s
            previous_mode = mode
        score, game_time = frame.score, frame.time_s
        for name, robot in frame.robots.items():
            if robot.side is None:  # a robot being built (no team material yet)
                continue
            seen.add(name)
            torso = robot.bodies.get("torso")
            if torso is None:
                continue
            x, y, z = (float(v) for v in torso[:3, 3])
            if mode == "BeforeKickOff":
                before[name] = (x, y)
            if not fallen.get(name) and z < FALLEN_TORSO_Z_M:
                fallen[name] = True
                falls[name] += 1
            elif fallen.get(name) and z > STANDING_AGAIN_Z_M:
                fallen[name] = False
            if frame.time_s > 0:
                truth[_truth_key(name, frame.time_s)] = (x, y, _heading(torso))
        if frame.ball is not None and frame.time_s > 0:
            bx, by = float(frame.ball[0, 3]), float(frame.ball[1, 3])
            balls[round(frame.time_s / CYCLE_S)] = (bx, by)
            if last_ball is not None:
                step = math.dist(last_ball, (bx, by))
                if step < BALL_TELEPORT_M:
                    ball_path += step
            last_ball = (bx, by)
            ball_far = max(ball_far, math.hypot(bx, by))
            ball_x = [min(ball_x[0], bx), max(ball_x[1], bx)]
    names = sorted({*seen, *(f"{team.lower()}_{unum}" for team, unum, _ in played.lineup)})
    out: dict[str, Any] = {
        "wall [s]": round(played.wall_s, 1),
        "game time [s]": round(game_time, 2),
        "monitor frames": frames,
        "kick-off": played.kick_off,
        "first PlayOn at [s]": first_play_on if first_play_on is not None else math.nan,
        "play modes": " > ".join(modes),
        "goals": goals,
        "score": f"{score[0]}:{score[1]}",
        "ball path [m]": round(ball_path, 2),
        "ball farthest from centre [m]": round(ball_far, 2),
        "ball x min/max [m]": f"{ball_x[0]:.2f}/{ball_x[1]:.2f}" if last_ball else "-",
        "ball at end": f"({last_ball[0]:.2f}, {last_ball[1]:.2f})" if last_ball else "-",
        "falls total": sum(falls.values()),
    }
    for name in names:
        out[f"falls {name}"] = falls.get(name, 0)
    offsets = []
    for team, unum, _ in played.lineup:
        spot = beam_spot(unum)
        sign = 1.0 if team == LEFT_TEAM else -1.0
        where = at_kick_off.get(f"{team.lower()}_{unum}")
        if where is not None:
            offsets.append(math.dist(where, (sign * spot.x_m, sign * spot.y_m)))
    out["beam offset max [m]"] = round(max(offsets), 3) if offsets else math.nan
    fouls = _fouls(played.monitor_log, played.until_s)
    out["referee fouls"] = format_fouls(fouls)
    if not played.agents:  # python -m agent processes (--cli): what they said is in the notes
        return out
    kicks = {w.name: len(w.kicks) for w in played.agents}
    out["kicks (motion starts)"] = sum(kicks.values())
    for name, count in kicks.items():
        out[f"kicks {name}"] = count
    moved, reach, details = [], [], []
    for watched in played.agents:
        key_name = f"{watched.team.lower()}_{watched.unum}"
        poses = {k[1]: v for k, v in truth.items() if k[0] == key_name}
        for time_s, motion in watched.kicks:
            start, end = _near(balls, time_s), _near(balls, time_s + KICK_EFFECT_S)
            robot = _near(poses, time_s)
            text = f"{watched.name} t={time_s:.1f} {motion}"
            if start is not None and end is not None:
                moved.append(math.dist(start, end))
                text += f" ball moved {moved[-1]:.2f} m"
            if start is not None and robot is not None:
                reach.append(math.dist(start, robot[:2]))
                c, s = math.cos(robot[2]), math.sin(robot[2])
                dx, dy = start[0] - robot[0], start[1] - robot[1]
                text += f", ball at torso +({c * dx + s * dy:.3f} fwd, {-s * dx + c * dy:.3f} left) m"
            details.append(text)
    out[f"kicks moving the ball > 0.5 m in {KICK_EFFECT_S:g} s"] = sum(1 for m in moved if m > 0.5)
    out["ball moved per kick mean [m]"] = round(sum(moved) / len(moved), 2) if moved else math.nan
    out["ball moved per kick max [m]"] = round(max(moved), 2) if moved else math.nan
    out["torso-ball at kick start median [m]"] = round(_percentile(reach, 0.5), 3)
    out["kick details"] = "; ".join(details) or "-"
    starts: collections.Counter[str] = collections.Counter()
    for watched in played.agents:
        starts.update(watched.motion_starts)
    out["motion starts"] = ", ".join(f"{m} {n}" for m, n in sorted(starts.items()))
    position, heading = [], []
    per_robot: dict[str, list[float]] = {}
    for watched in played.agents:
        key_name = f"{watched.team.lower()}_{watched.unum}"
        for belief in watched.beliefs:
            known = truth.get(_truth_key(key_name, belief.game_time_s))
            if known is None:
                continue
            error = math.dist((belief.x_m, belief.y_m), known[:2])
            position.append(error)
            per_robot.setdefault(watched.name, []).append(error)
            heading.append(abs(math.degrees(_wrap(belief.heading_rad - known[2]))))
    out["loc error median [m]"] = round(_percentile(position, 0.5), 3)
    out["loc error p90 [m]"] = round(_percentile(position, 0.9), 3)
    out["loc heading error median [deg]"] = round(_percentile(heading, 0.5), 1)
    out["loc heading error p90 [deg]"] = round(_percentile(heading, 0.9), 1)
    out["loc samples"] = len(position)
    for name, errors in per_robot.items():
        out[f"loc error median {name} [m]"] = round(_percentile(errors, 0.5), 3)
    firsts = [w.first_localized_s for w in played.agents if w.first_localized_s is not None]
    out["slowest first localization [s]"] = round(max(firsts), 2) if firsts else math.nan
    out["never localized"] = ", ".join(w.name for w in played.agents if w.first_localized_s is None) or "-"
    out["agent exceptions"] = sum(w.errors for w in played.agents)
    out["malformed sense messages"] = sum(w.bad_messages for w in played.agents)
    out["agent cycles"] = sum(w.cycles for w in played.agents)
    out["reconnections"] = sum(max(0, w.connections - 1) for w in played.agents)
    return out


def _near(by_cycle: dict[int, Any], time_s: float) -> Any:
    """The value at the cycle of ``time_s`` or the one next to it (our log holds every 2nd cycle)."""
    cycle = round(time_s / CYCLE_S)
    for k in (cycle, cycle + 1, cycle - 1):
        if k in by_cycle:
            return by_cycle[k]
    return None


def _truth_key(name: str, time_s: float) -> Any:
    return (name, round(time_s / CYCLE_S))


FOUL_TYPES = {"0": "crowding", "1": "touching", "2": "illegal defence", "3": "illegal attack", "4": "incapable",
              "5": "kick-off", "6": "charging", "7": "self-collision"}


#: Foul records of one player and type this close in time [s] are one incident: the real server sends a charging foul
#: as a record per cycle while the robot is being moved (measured: 26 records in 0.5 s, one robot, 11 v 11).
FOUL_INCIDENT_GAP_S = 1.0


def _fouls(path: Path, until_s: float) -> dict[str, tuple[int, int]]:
    """Referee fouls of the monitor stream by type (REFERENCE §4.5; each record reported once by its index) up to
    game time ``until_s``: type -> (incidents, records), an incident being the records of one player and type
    with less than ``FOUL_INCIDENT_GAP_S`` between them."""
    seen: dict[int, tuple[float, str, str, str]] = {}
    pattern = re.compile(rb"\(foul (\d+) (\d+) (\d+) (\d+)\)")
    time_pattern = re.compile(rb"\(time ([0-9.]+)\)")
    now = 0.0
    with open(path, "rb") as handle:
        for line in handle:
            found = time_pattern.search(line[:4000])
            if found:
                now = float(found.group(1))
                if now > until_s + CYCLE_S / 2:
                    break
            for index, kind, team, unum in pattern.findall(line[:4000]):
                seen.setdefault(int(index), (now, FOUL_TYPES.get(kind.decode(), kind.decode()), team.decode(),
                                             unum.decode()))
    incidents: collections.Counter[str] = collections.Counter()
    records: collections.Counter[str] = collections.Counter()
    last: dict[tuple[str, str, str], float] = {}
    for _, (time_s, kind, team, unum) in sorted(seen.items()):
        key = (kind, team, unum)
        records[kind] += 1
        if key not in last or time_s - last[key] >= FOUL_INCIDENT_GAP_S:
            incidents[kind] += 1
        last[key] = time_s
    return {kind: (incidents[kind], records[kind]) for kind in records}


def format_fouls(fouls: dict[str, tuple[int, int]]) -> str:
    """``charging 1 (26 records), touching 2``; ``-`` without fouls."""
    return ", ".join(f"{kind} {count}" + (f" ({records} records)" if records != count else "")
                     for kind, (count, records) in sorted(fouls.items())) or "-"


# ---- report --------------------------------------------------------------------------------------------
def _cell(value: Any) -> str:
    if isinstance(value, float):
        return "-" if math.isnan(value) else f"{value:.3f}".rstrip("0").rstrip(".")
    return str(value)


def table(real: dict[str, Any], ours: dict[str, Any]) -> str:
    long_keys = ("play modes", "motion starts", "kick details")
    keys = [k for k in dict.fromkeys([*real, *ours]) if k not in long_keys]
    rows = [f"{'figure':34s} {'real 0.7.3':>18s} {'ours':>18s}"]
    rows += [f"{k:34s} {_cell(real.get(k, '')):>18s} {_cell(ours.get(k, '')):>18s}" for k in keys]
    for key in long_keys:
        rows += [f"{key}:", f"  real: {real.get(key, '')}", f"  ours: {ours.get(key, '')}"]
    return "\n".join(rows)


def problems(played: Played) -> list[str]:
    """Exceptions (first tracebacks) and warnings, for the report."""
    lines = []
    for watched in played.agents:
        for text in watched.tracebacks:
            lines.append(f"{played.where} {watched.name}: exception\n{text}")
    lines += [f"{played.where}: {w}" for w in played.notes.get("first warnings", [])]
    return lines
