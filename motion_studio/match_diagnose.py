"""One match as ``motion-studio match`` plays it, watched closely: every fall with what the robot was doing
before it (role, skill, motion, phase, lean, contact with another robot), ball touches and robot contacts.

Why: the match runner counts falls (torso below 0.25 m) and possession, which says *that* robots fall but
not *why*; finding the causes (a transition between motions, a collision, a kick, a stand-up) needs the
agent's own state next to the physics. Falls here use REFERENCE §8.1's criterion (torso up-axis z < 0.6 or
torso below 0.25 m; upright again above 0.8 and 0.3 m), which also catches a robot that ends up sitting
or lying with its torso propped above 0.25 m.

Run::

    python -m motion_studio.match_diagnose --players 3 --duration 120 --seed 0
"""

from __future__ import annotations

import argparse
import collections
import math
from dataclasses import dataclass, field

from motion_studio.match_agents import make_agent
from sim.engine import SimEngine
from sim.inprocess import InProcessHost
from sim.match import MatchConfig

FALL_UP_Z, FALL_TORSO_Z_M = 0.6, 0.25
UPRIGHT_UP_Z, UPRIGHT_TORSO_Z_M = 0.8, 0.30
HISTORY_CYCLES = 150


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

    @property
    def falls_per_robot_minute(self) -> float:
        return len(self.falls) / max(1e-9, self.robots * self.game_time_s / 60.0)

    def causes(self) -> list[tuple[tuple, int]]:
        counter = collections.Counter((f.cause, f.contact) for f in self.falls)
        return counter.most_common()


def _phase_kind(phase: str | None) -> str | None:
    return None if phase is None else phase.rstrip("0123456789").rstrip("_")


def diagnose(config: MatchConfig) -> Diagnosis:
    """Play ``config``'s match (same connection order, kick-offs and robot types as ``sim.match.run_match``)."""
    engine = SimEngine(seed=config.seed)
    host = InProcessHost(engine)
    agents = {}
    for unum in range(1, config.players_per_team + 1):
        robot_type = config.robot_types[(unum - 1) % len(config.robot_types)]
        for team in (config.team_left, config.team_right):
            agent = make_agent(team, unum, robot_type)
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
    waited_s = 0.0
    while referee.play_mode != "GameOver" and referee.game_time_s < config.duration_s:
        host.run(1)
        if referee.play_mode == "BeforeKickOff":
            waited_s += world.params.cycle_s
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
            motion = behavior.motion
            if motion.motion_name != playing.get(key) and motion.motion_name is not None:
                played[motion.motion_name] += 1
            playing[key] = motion.motion_name
            skills = behavior.skills
            skill = "StandUp" if skills.recovering else type(skills.skill).__name__
            row = (round(engine.time_s, 2), behavior.role, skill, motion.motion_name, motion.phase_name,
                   round(motion._request.lean, 2), round(state.torso_up_z, 2), (side, unum) in in_contact,
                   round(math.dist(state.torso_pos_m[:2], ball[:2]), 2))
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
                     (referee.score_left, referee.score_right))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m motion_studio.match_diagnose", description=__doc__.split("\n\n")[0])
    parser.add_argument("--players", type=int, default=3)
    parser.add_argument("--duration", type=float, default=120.0)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--verbose", action="store_true", help="print each fall's recent transitions")
    args = parser.parse_args(argv)
    result = diagnose(MatchConfig(players_per_team=args.players, duration_s=args.duration, seed=args.seed))
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
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
