"""One match as ``motion-studio match`` plays it, watched closely: every fall with what the robot was doing
before it (role, skill, motion, phase, lean, contact with another robot), ball touches, robot contacts, and
where each team's on-ball time goes (by where the ball lies and what the on-ball player's skill is doing).

Why: the match runner counts falls (torso below 0.25 m) and possession, which says *that* robots fall but
not *why*; finding the causes (a transition between motions, a collision, a kick, a stand-up) needs the
agent's own state next to the physics. Falls here use REFERENCE §8.1's criterion (torso up-axis z < 0.6 or
torso below 0.25 m; upright again above 0.8 and 0.3 m), which also catches a robot that ends up sitting
or lying with its torso propped above 0.25 m.

The on-ball breakdown answers "why so few goals": in PlayOn, each cycle of a player holding the on-ball role
goes to (ball zone, activity), the zone counted along the team's attack (``ZONE_EDGES_M``), the activity the
dribble's mode (push, approach, avoid, turn, near:<motion>, blocked, search), else the skill's name, or
StandUp while it recovers. Earlier stops measured this with throw-away scripts each time (pushing, turns and
the opponents' kick-offs were where a 3 v 3 against standing robots spent its 120 s).

Run::

    python -m motion_studio.match_diagnose --players 3 --duration 120 --seed 0 --right standing

With ``--matches N --out DIR`` it watches seeds --seed.. and prints per-match means
(``motion_studio.match_diagnose_batch``).
"""

from __future__ import annotations

import argparse
import collections
import math
from dataclasses import dataclass, field
from pathlib import Path

from motion_studio.match_agents import TEAM_KINDS, SideAgents, make_agent
from sim.engine import SimEngine
from sim.inprocess import InProcessHost
from sim.match import AgentFactory, MatchConfig, connection_order

FALL_UP_Z, FALL_TORSO_Z_M = 0.6, 0.25
UPRIGHT_UP_Z, UPRIGHT_TORSO_Z_M = 0.8, 0.30
HISTORY_CYCLES = 150
#: Rows of the on-ball table the command prints per side.
ON_BALL_ROWS = 14
#: Ball zone edges along a team's attack (team frame x, the opponent goal line at 15 m) [m] ...
ZONE_EDGES_M = (0.0, 10.0, 13.0)
#: ... and the zones' names: the own half, the opponent half to 10 m, 10-13 m, the last 2 m.
ZONE_NAMES = ("own half", "0-10 m", "10-13 m", "13 m-goal line")


def ball_zone(ball_x_team_m: float) -> str:
    """The zone of a ball at team-frame x [m] (``ZONE_NAMES``)."""
    return ZONE_NAMES[sum(ball_x_team_m >= edge for edge in ZONE_EDGES_M)]


def on_ball_activity(behavior: object) -> str:
    """What a player's skill is doing this cycle: StandUp while it recovers, the skill's ``mode`` when it has one
    (``agent.skills.dribble.Dribble``), else the skill's class name (or "-" without a skill)."""
    skills = getattr(behavior, "skills", None)
    if skills is None:
        return "-"
    if skills.recovering:
        return "StandUp"
    skill = skills.skill
    mode = getattr(skill, "mode", None)
    return mode if isinstance(mode, str) and mode else type(skill).__name__ if skill is not None else "-"


@dataclass
class Fall:
    """One fall: when, who, and the agent's state since the torso last stood straight (up-axis z >= 0.9)."""

    time_s: float
    team: str
    unum: int
    robot_type: int
    cause: tuple[str, str | None, str | None]
    """(skill, motion, phase kind) when the tilt began."""
    ball_m: float
    """Ground distance torso - ball when the tilt began [m] (a robot stepping on the ball falls)."""
    contact: bool
    """Touching another robot in the 1.5 s before the fall."""
    transitions: list[tuple] = field(default_factory=list)


@dataclass
class Diagnosis:
    """What one watched match produced."""

    robots: int
    game_time_s: float
    falls: list[Fall]
    touches: dict[str, int]
    """Ball touch events (a robot starting to touch the ball) per team."""
    contacts: int
    """Robot-pair contact events (a pair starting to touch)."""
    motions_played: dict[str, int]
    """Motion name -> times a robot started it (to set the falls during a motion against its uses)."""
    score: tuple[int, int]
    on_ball_s: dict[str, dict[tuple[str, str], float]] = field(default_factory=dict)
    """Side ("left"/"right") -> (ball zone, activity) -> game time in PlayOn with a player of that side in the
    on-ball role doing it [s] (two on-ball players of a side count twice)."""
    play_modes_s: dict[str, float] = field(default_factory=dict)
    """Play mode -> game time spent in it [s] (BeforeKickOff counts the kick-off wait)."""

    def on_ball_rows(self, side: str) -> list[tuple[str, str, float]]:
        """(zone, activity, seconds) of one side, longest first."""
        return sorted(((zone, activity, s) for (zone, activity), s in self.on_ball_s.get(side, {}).items()),
                      key=lambda row: -row[2])

    @property
    def falls_per_robot_minute(self) -> float:
        return len(self.falls) / max(1e-9, self.robots * self.game_time_s / 60.0)

    def causes(self) -> list[tuple[tuple, int]]:
        counter = collections.Counter((f.cause, f.contact) for f in self.falls)
        return counter.most_common()


def _phase_kind(phase: str | None) -> str | None:
    return None if phase is None else phase.rstrip("0123456789").rstrip("_")


def diagnose(config: MatchConfig, agents_of: AgentFactory = make_agent) -> Diagnosis:
    """Play ``config``'s match (same connection order, kick-offs and robot types as ``sim.match.run_match``)
    with the agents ``agents_of`` builds (our agent on both sides by default; ``SideAgents`` for others)."""
    engine = SimEngine(seed=config.seed)
    host = InProcessHost(engine)
    agents = {}
    for unum, robot_type, team in connection_order(config):
        agent = agents_of(team, unum, robot_type)
        agents[host.add(agent)] = (agent, "left" if team == config.team_left else "right", unum, robot_type)
        host.run(2)
    world, referee = engine.world, engine.referee
    history: dict[int, collections.deque] = collections.defaultdict(lambda: collections.deque(maxlen=HISTORY_CYCLES))
    fallen: dict[int, bool] = {}
    falls: list[Fall] = []
    touches: collections.Counter[str] = collections.Counter()
    touching_ball: set = set()
    pairs: set = set()
    contacts = 0
    played: collections.Counter[str] = collections.Counter()
    playing: dict[int, str | None] = {}
    on_ball: dict[str, collections.Counter[tuple[str, str]]] = {"left": collections.Counter(),
                                                                "right": collections.Counter()}
    modes: collections.Counter[str] = collections.Counter()
    cycle_s = world.params.cycle_s
    waited_s = 0.0
    while referee.play_mode != "GameOver" and referee.game_time_s < config.duration_s:
        host.run(1)
        modes[referee.play_mode] += cycle_s
        if referee.play_mode == "BeforeKickOff":
            waited_s += cycle_s
            if waited_s >= config.kick_off_wait_s:
                referee.kick_off(None)
                waited_s = 0.0
        now_touching = set(world.ball_touchers())
        for team, _ in now_touching - touching_ball:
            touches[team] += 1
        touching_ball = now_touching
        now_pairs = {frozenset(p) for p in world.touching_robot_pairs()}
        contacts += len(now_pairs - pairs)
        pairs = now_pairs
        in_contact = {robot for pair in now_pairs for robot in pair}
        states = {(r.team, r.unum): r for r in world.robots()}
        ball = world.ball_position()
        for key, (agent, side, unum, robot_type) in agents.items():
            state = states.get((side, unum))
            if state is None:
                continue
            behavior = agent.behavior
            if referee.play_mode == "PlayOn" and getattr(behavior, "role", None) == "on_ball":
                zone = ball_zone(ball[0] if side == "left" else -ball[0])
                on_ball[side][(zone, on_ball_activity(behavior))] += cycle_s
            motion = getattr(behavior, "motion", None)  # None: an agent that only stands
            if motion is not None and motion.motion_name != playing.get(key) and motion.motion_name is not None:
                played[motion.motion_name] += 1
            playing[key] = None if motion is None else motion.motion_name
            skills = getattr(behavior, "skills", None)
            skill = "-" if skills is None else "StandUp" if skills.recovering else type(skills.skill).__name__
            row = (round(engine.time_s, 2), getattr(behavior, "role", None), skill,
                   None if motion is None else motion.motion_name, None if motion is None else motion.phase_name,
                   0.0 if motion is None else round(motion._request.lean, 2), round(state.torso_up_z, 2),
                   (side, unum) in in_contact, round(math.dist(state.torso_pos_m[:2], ball[:2]), 2))
            history[key].append(row)
            z = state.torso_pos_m[2]
            if not fallen.get(key) and (state.torso_up_z < FALL_UP_Z or z < FALL_TORSO_Z_M):
                fallen[key] = True
                rows = list(history[key])
                straight = max((i for i, r in enumerate(rows) if r[6] >= 0.9), default=-1)
                tilt = rows[min(straight + 1, len(rows) - 1)]
                transitions, last = [], None
                for r in rows:
                    if r[1:4] + (_phase_kind(r[4]),) != last:
                        transitions.append(r)
                        last = r[1:4] + (_phase_kind(r[4]),)
                falls.append(Fall(engine.time_s, side, unum, robot_type, (tilt[2], tilt[3], _phase_kind(tilt[4])),
                                  tilt[8], any(r[7] for r in rows[-75:]), transitions[-12:]))
            elif fallen.get(key) and state.torso_up_z > UPRIGHT_UP_Z and z > UPRIGHT_TORSO_Z_M:
                fallen[key] = False
    return Diagnosis(len(agents), referee.game_time_s, falls, dict(touches), contacts, dict(played),
                     (referee.score_left, referee.score_right), {side: dict(c) for side, c in on_ball.items()},
                     dict(modes))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m motion_studio.match_diagnose", description=__doc__.split("\n\n")[0])
    parser.add_argument("--players", type=int, default=3)
    parser.add_argument("--duration", type=float, default=120.0)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--left", default="ours", choices=TEAM_KINDS, help="left team (default: ours)")
    parser.add_argument("--right", default="ours", choices=TEAM_KINDS, help="right team (default: ours)")
    parser.add_argument("--verbose", action="store_true", help="print each fall's recent transitions")
    parser.add_argument("--matches", type=int, default=1,
                        help="watch this many matches (seeds --seed..) and print per-match means (needs --out)")
    parser.add_argument("--out", type=Path, help="folder of the matches' checkpoint (diagnoses.jsonl) and plot")
    parser.add_argument("--workers", type=int, default=1, help="processes for --matches")
    args = parser.parse_args(argv)
    config = MatchConfig(players_per_team=args.players, duration_s=args.duration, seed=args.seed)
    if args.matches > 1 or args.out is not None:
        return _batch(args, config)
    result = diagnose(config, SideAgents(args.left, args.right, team_left=config.team_left))
    for fall in result.falls:
        print(f"fall t={fall.time_s:.2f} {fall.team} {fall.unum} (type {fall.robot_type}) during {fall.cause}, "
              f"ball {fall.ball_m:.2f} m" + (" in contact" if fall.contact else ""))
        if args.verbose:
            for row in fall.transitions:
                print("    ", row)
    print(f"seed {args.seed}: {len(result.falls)} falls in {result.game_time_s:.0f} s x {result.robots} robots = "
          f"{result.falls_per_robot_minute:.3f} per robot-minute; ball touches {result.touches}; robot contacts "
          f"{result.contacts}; score {result.score[0]}:{result.score[1]}")
    for (cause, contact), count in result.causes():
        print(f"  {count} x {cause}" + (" in contact" if contact else "")
              + f" ({result.motions_played.get(cause[1] or '', 0)} starts of {cause[1]})")
    print("motion starts:", dict(sorted(result.motions_played.items())))
    modes = sorted(result.play_modes_s.items(), key=lambda kv: -kv[1])
    print("play modes [s]:", {mode: round(seconds, 1) for mode, seconds in modes})
    for side, kind in (("left", args.left), ("right", args.right)):
        rows = result.on_ball_rows(side)
        if not rows:
            continue
        total = sum(s for _, _, s in rows)
        print(f"{side} ({kind}) on-ball time in PlayOn, {total:.1f} s, by ball zone and activity:")
        for zone, activity, seconds in rows[:ON_BALL_ROWS]:
            print(f"  {zone:15s} {activity:22s} {seconds:6.1f} s  {100 * seconds / total:4.0f} %")
    return 0


def _batch(args: argparse.Namespace, config: MatchConfig) -> int:
    from motion_studio import match_diagnose_batch as batch

    if args.out is None:
        raise SystemExit("error: --matches needs --out (the folder of its checkpoint and plot)")
    if args.matches < 1 or args.workers < 1:
        raise SystemExit("error: --matches and --workers must be at least 1")
    kinds = (args.left, args.right)
    rows = batch.run(config, SideAgents(*kinds, team_left=config.team_left), args.matches, args.seed, args.out,
                     args.workers)
    figures = batch.aggregate(rows)
    print(batch.report(figures, kinds))
    if figures.matches:
        print("plot:", batch.plot(figures, kinds, args.out / batch.PLOT_NAME))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
