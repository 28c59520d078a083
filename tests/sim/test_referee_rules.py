"""Rule-table tests of the referee against a tiny hand-made WorldView (no physics)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import pytest

from sim.referee import Referee
from sim.rules.params import PLAY_MODES, FoulType, default_config
from sim.world_api import RobotState
from agent.protocol.constants import CYCLE_S


@dataclass
class FakeRobot:
    team: str
    unum: int
    pos: list[float]
    vel: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    heading_deg: float = 0.0


class FakeWorld:
    """A WorldView with kinematic ball motion and robots that stay where they are put."""

    def __init__(self) -> None:
        self.ball = [0.0, 0.0, 0.042]
        self.ball_vel = [0.0, 0.0, 0.0]
        self.bots: dict[tuple[str, int], FakeRobot] = {}
        self.touchers: list[tuple[str, int]] = []
        self.pairs: list[tuple[tuple[str, int], tuple[str, int]]] = []
        self.moves: list[tuple[str, int, float, float, float]] = []
        self.frozen: list[tuple[str, int, list[str]]] = []

    def add(self, team: str, unum: int, x: float, y: float, z: float = 0.38) -> FakeRobot:
        robot = FakeRobot(team, unum, [x, y, z])
        self.bots[(team, unum)] = robot
        return robot

    def step(self) -> None:
        for i in range(3):
            self.ball[i] += self.ball_vel[i] * CYCLE_S

    # WorldView
    def ball_position(self) -> tuple[float, float, float]:
        return tuple(self.ball)  # type: ignore[return-value]

    def ball_velocity(self) -> tuple[float, float, float]:
        return tuple(self.ball_vel)  # type: ignore[return-value]

    def set_ball(self, position_m, velocity_m_s=(0.0, 0.0, 0.0)) -> None:
        self.ball = list(position_m)
        self.ball_vel = list(velocity_m_s)

    def robots(self) -> list[RobotState]:
        return [RobotState(r.team, r.unum, 0, tuple(r.pos), tuple(r.vel), 1.0, r.heading_deg)  # type: ignore[arg-type]
                for r in self.bots.values()]

    def move_robot(self, team, unum, x_m, y_m, heading_deg=None, z_m=0.4) -> None:
        robot = self.bots[(team, unum)]
        robot.pos = [x_m, y_m, z_m]
        robot.vel = [0.0, 0.0, 0.0]
        self.moves.append((team, unum, x_m, y_m, z_m))

    def shift_robot(self, team, unum, x_m, y_m) -> None:
        robot = self.bots[(team, unum)]
        self.move_robot(team, unum, x_m, y_m, None, robot.pos[2])

    def ball_touchers(self):
        return list(self.touchers)

    def touching_robot_pairs(self):
        return list(self.pairs)

    def freeze_joints(self, team, unum, effectors) -> None:
        self.frozen.append((team, unum, list(effectors)))


def run(referee: Referee, world: FakeWorld, cycles: int) -> None:
    for _ in range(cycles):
        world.step()
        referee.update(world)


def started(world: FakeWorld, side: str = "Left", **config: object) -> Referee:
    """A referee in PlayOn after a kick-off touched by the given side's player 9."""
    referee = Referee(default_config(**config), seed=1)
    referee.on_init("L", 0)
    referee.on_init("R", 0)
    referee.kick_off(side)
    taker = ("left" if side == "Left" else "right", 9)
    if taker not in world.bots:
        world.add(taker[0], 9, -0.2 if side == "Left" else 0.2, 0.0)
    world.touchers = [taker]
    run(referee, world, 1)
    world.touchers = []
    assert referee.play_mode == "PlayOn"
    return referee


def test_play_mode_table_matches_reference() -> None:
    assert PLAY_MODES[0] == "BeforeKickOff" and PLAY_MODES[3] == "PlayOn" and PLAY_MODES[12] == "GameOver"
    assert PLAY_MODES[13] == "Goal_Left" and PLAY_MODES[20] == "pass_right" and len(PLAY_MODES) == 21


def test_time_frozen_before_kick_off_then_runs() -> None:
    world = FakeWorld()
    world.add("left", 1, -14.0, 0.0)
    referee = Referee(seed=0)
    run(referee, world, 50)
    assert referee.play_mode == "BeforeKickOff" and referee.play_mode_index == 0
    assert referee.game_time_s == 0.0
    referee.kick_off("Left")
    assert referee.play_mode == "KickOff_Left"
    run(referee, world, 50)
    assert referee.game_time_s == pytest.approx(1.0)


def test_init_assigns_sides_numbers_and_spots() -> None:
    referee = Referee(seed=0)
    first = referee.on_init("Alpha", 0)
    second = referee.on_init("Alpha", 0)
    other = referee.on_init("Beta", 7)
    assert first is not None and second is not None and other is not None
    assert (first.side, first.unum, first.position_m[:2]) == ("left", 1, (-14.2, 9.2))
    assert second.unum == 2 and second.position_m[1] == pytest.approx(8.0)
    assert (other.side, other.unum, other.heading_deg) == ("right", 7, 180.0)
    assert referee.on_init("Gamma", 1) is None  # a third team
    assert referee.on_init("Beta", 7) is None  # number taken
    assert referee.team_names == {"left": "Alpha", "right": "Beta"}


def test_beam_allowed_only_in_beam_modes() -> None:
    referee = Referee(seed=0)
    assert referee.allows_beam()
    for mode in PLAY_MODES:
        referee.set_play_mode(mode)
        assert referee.allows_beam() == (mode in ("BeforeKickOff", "Goal_Left", "Goal_Right"))
    with pytest.raises(ValueError, match="known"):
        referee.set_play_mode("Playon")


def test_kick_off_none_gives_left_then_right_in_second_half() -> None:
    referee = Referee(seed=3)
    referee.kick_off(None)
    assert referee.play_mode == "KickOff_Left"
    referee.set_play_mode("BeforeKickOff")
    referee.half = 2
    referee.kick_off("None")
    assert referee.play_mode == "KickOff_Right"


def test_halves_and_game_over() -> None:
    world = FakeWorld()
    world.add("left", 2, -5.0, 0.0)
    referee = Referee(default_config(half_time_s=1.0), seed=0)
    referee.kick_off("Left")
    run(referee, world, 50)
    assert referee.play_mode == "BeforeKickOff" and referee.half == 2
    assert referee.game_time_s == pytest.approx(1.0)
    run(referee, world, 20)
    assert referee.game_time_s == pytest.approx(1.0)  # frozen again
    referee.kick_off("Right")
    run(referee, world, 50)
    assert referee.play_mode == "GameOver" and referee.game_time_s == pytest.approx(2.0)


def test_goal_pause_then_conceding_team_kicks_off() -> None:
    world = FakeWorld()
    world.add("left", 9, -0.2, 0.0)
    world.add("right", 9, 5.0, 0.0)
    referee = started(world)
    world.set_ball((14.5, 0.3, 0.042), (5.0, 0.0, 0.0))
    for _ in range(20):
        run(referee, world, 1)
        if referee.play_mode != "PlayOn":
            break
    assert referee.play_mode == "Goal_Left" and referee.score_left == 1
    assert referee.allows_beam()
    assert any(e.kind == "goal" and e.team == "left" for e in referee.events)
    run(referee, world, 149)
    assert referee.play_mode == "Goal_Left"
    run(referee, world, 1)
    assert referee.play_mode == "KickOff_Right"
    assert world.ball[:2] == [0.0, 0.0]


def test_goal_recorder_catches_a_ball_placed_in_the_goal() -> None:
    """REFERENCE §5.2 (measured): (ball (pos 15.5 0 0.042)) -> Goal_Left, sl 1."""
    world = FakeWorld()
    referee = started(world)
    world.set_ball((15.5, 0.0, 0.042))
    run(referee, world, 1)
    assert (referee.play_mode, referee.score_left, referee.score_right) == ("Goal_Left", 1, 0)


def test_ball_over_the_post_side_is_a_goal_kick_not_a_goal() -> None:
    world = FakeWorld()
    world.add("left", 9, -0.2, 0.0)
    referee = started(world)
    world.set_ball((14.9, 1.5, 0.042), (3.0, 0.0, 0.0))
    run(referee, world, 10)
    assert referee.play_mode == "goal_kick_right" and referee.score_left == 0
    run(referee, world, 60)
    assert world.ball[:2] == pytest.approx([14.0, 0.0])


def test_touch_line_kick_in_for_opponent_of_last_toucher_and_placement() -> None:
    world = FakeWorld()
    referee = started(world)
    world.set_ball((3.0, 9.8, 0.042), (0.0, 2.0, 0.0))
    run(referee, world, 10)
    assert referee.play_mode == "KickIn_Right"
    run(referee, world, 55)  # after the 1 s pause the ball is placed on the line
    assert world.ball[0] == pytest.approx(3.0) and world.ball[1] == pytest.approx(10 - 0.042)
    # A right player touches it after the pause: PlayOn.
    world.add("right", 4, 3.3, 9.9)
    world.touchers = [("right", 4)]
    run(referee, world, 1)
    assert referee.play_mode == "PlayOn"


def test_corner_for_attackers_when_defender_last_touched() -> None:
    world = FakeWorld()
    referee = started(world)
    world.add("left", 3, -14.0, -4.0)
    world.touchers = [("left", 3)]
    run(referee, world, 1)
    world.touchers = []
    world.set_ball((-14.9, -4.0, 0.042), (-3.0, 0.0, 0.0))
    run(referee, world, 10)
    assert referee.play_mode == "corner_kick_right"
    run(referee, world, 55)
    assert world.ball[:2] == pytest.approx([-14.958, -5.483])


def test_kick_off_team_cannot_score_directly() -> None:
    world = FakeWorld()
    for unum, x in ((9, -0.2), (2, -6.0)):
        world.add("left", unum, x, 0.0)
    world.add("right", 2, 6.0, 5.0)
    referee = started(world)
    world.set_ball((14.0, 0.0, 0.042), (10.0, 0.0, 0.0))
    run(referee, world, 20)
    assert referee.score_left == 0 and referee.play_mode == "goal_kick_right"


def test_drop_ball_after_15_s_without_touch() -> None:
    world = FakeWorld()
    world.add("left", 5, -1.0, 0.5)
    world.add("right", 5, 1.0, -0.5)
    referee = Referee(seed=0)
    referee.kick_off("Left")
    run(referee, world, int(15.0 / CYCLE_S) + 2)
    assert referee.play_mode == "PlayOn"
    for robot in world.bots.values():
        assert math.hypot(robot.pos[0], robot.pos[1]) >= 2.0


def test_kick_off_clears_opponents_from_the_kicking_half() -> None:
    world = FakeWorld()
    intruder = world.add("right", 6, -3.0, 2.0)
    in_circle = world.add("right", 7, 1.0, 0.0)
    referee = Referee(seed=0)
    referee.kick_off("Left")
    run(referee, world, 1)
    assert intruder.pos[0] >= 2.5 - 1e-9
    assert math.hypot(in_circle.pos[0], in_circle.pos[1]) > 2.0


def test_before_kick_off_pushes_players_into_their_half() -> None:
    world = FakeWorld()
    robot = world.add("left", 4, 3.0, 1.0)
    referee = Referee(seed=0)
    run(referee, world, 1)
    assert robot.pos[0] <= -2.5 + 1e-9
    assert world.ball == [0.0, 0.0, 0.042]


def test_incapable_field_player_is_lifted_then_placed_outside() -> None:
    world = FakeWorld()
    fallen = world.add("left", 5, -4.0, 3.0, z=0.1)
    referee = started(world, ground_max_time_s=0.2)
    run(referee, world, 12)
    fouls = [f for f in referee.fouls if f.type == FoulType.INCAPABLE]
    assert fouls and fouls[0].monitor_tuple() == (1, 4, 1, 5)
    assert fallen.pos[2] > 1.0  # lifted
    run(referee, world, 30)
    assert fallen.pos[:2] == pytest.approx([-0.6 * (7 - 5), -10.5])  # away from the ball (at y = 0 -> -y)
    assert fallen.pos[2] == pytest.approx(0.4)
    # The server records the foul in every cycle of the 0.5 s lift and in the one that places the robot outside
    # (26 records, indices 1..26, as the real monitor stream shows); it is one foul: one event.
    fouls = [f for f in referee.fouls if f.type == FoulType.INCAPABLE]
    assert [f.monitor_tuple() for f in fouls] == [(i, 4, 1, 5) for i in range(1, 27)]
    assert len([e for e in referee.events if e.kind == "foul"]) == 1


def test_goalie_gets_longer_incapable_time() -> None:
    world = FakeWorld()
    world.add("left", 1, -14.0, 0.0, z=0.1)
    referee = started(world, ground_max_time_s=0.2, goalie_ground_max_time_s=0.5)
    run(referee, world, 15)
    assert not referee.fouls
    run(referee, world, 15)
    assert {f.unum for f in referee.fouls} == {1}


def test_illegal_defence_moves_the_fourth_entrant_out() -> None:
    world = FakeWorld()
    for unum, y in ((1, 0.0), (2, 1.0), (3, -1.0)):
        world.add("left", unum, -14.5, y)
    referee = started(world)
    run(referee, world, 2)
    late = world.add("left", 4, -14.0, 2.0)
    run(referee, world, 1)
    assert [(f.type, f.unum) for f in referee.fouls] == [(FoulType.ILLEGAL_DEFENCE, 4)]
    assert late.pos[:2] == pytest.approx([-13.2 + 0.4, 2.0])  # nearest edge of the area + AgentRadius


def test_touching_group_of_three_moves_the_latest() -> None:
    world = FakeWorld()
    world.add("left", 2, 0.0, 4.0)
    world.add("right", 2, 0.3, 4.0)
    referee = started(world)
    world.pairs = [(("left", 2), ("right", 2))]
    run(referee, world, 2)
    third = world.add("right", 3, 0.15, 4.3)
    world.pairs = [(("left", 2), ("right", 2)), (("right", 3), ("left", 2))]
    run(referee, world, 1)
    assert [(f.type, f.team) for f in referee.fouls] == [(FoulType.TOUCHING, "right")]
    assert referee.fouls[0].unum == 3  # the one that just joined
    assert third.pos[:2] != [0.15, 4.3]
    assert world.bots[("right", 2)].pos[:2] == [0.3, 4.0]


def test_charging_by_a_fast_player_away_from_the_ball() -> None:
    world = FakeWorld()
    charger = world.add("left", 7, 4.0, 4.0)
    victim = world.add("right", 7, 4.3, 4.0)
    referee = started(world)
    run(referee, world, 60)  # past the 1 s moved-immunity of the kick-off clearing
    charger.vel = [1.0, 0.0, 0.0]
    world.pairs = [(("left", 7), ("right", 7))]
    run(referee, world, 15)
    assert [(f.type, f.team, f.unum) for f in referee.fouls][:1] == [(FoulType.CHARGING, "left", 7)]
    assert victim.pos[:2] == [4.3, 4.0]


def test_free_kick_double_touch() -> None:
    world = FakeWorld()
    referee = started(world)
    world.add("right", 8, 3.0, 9.9)
    world.set_ball((3.0, 9.8, 0.042), (0.0, 2.0, 0.0))
    run(referee, world, 60)
    assert referee.play_mode == "KickIn_Right"
    world.touchers = [("right", 8)]
    run(referee, world, 1)
    world.touchers = []
    run(referee, world, 10)
    world.touchers = [("right", 8)]
    run(referee, world, 1)
    assert referee.play_mode == "free_kick_left"


def test_trainer_commands() -> None:
    from sim.rules.trainer import apply_trainer_message

    world = FakeWorld()
    world.add("left", 3, -5.0, 0.0)
    referee = Referee(seed=0)
    assert apply_trainer_message(b"(kickOff Left)", referee, world) == ["kickOff"]
    assert referee.play_mode == "KickOff_Left"
    applied = apply_trainer_message(b"(playMode PlayOn)(ball (pos 1 2 0.042)(vel 0.5 0 0))(time 12.5)"
                                    b"(score (left 2)(right 1))(agent (unum 3)(team Left)(move -3 1 0.4 -90))",
                                    referee, world)
    assert applied == ["playMode", "ball", "time", "score", "agent"]
    assert referee.play_mode == "PlayOn" and referee.game_time_s == 12.5
    assert (referee.score_left, referee.score_right) == (2, 1)
    assert world.ball == [1.0, 2.0, 0.042] and world.ball_vel == [0.5, 0.0, 0.0]
    assert world.moves[-1] == ("left", 3, -3.0, 1.0, 0.4)
    # Bad commands are skipped, good ones in the same message still apply.
    assert apply_trainer_message(b"(playMode Nonsense)(ball (pos 1 nan 0))(foo)(kickOff Right)", referee,
                                 world) == ["kickOff"]
    import pytest as _pytest
    from agent.protocol.errors import ProtocolError
    with _pytest.raises(ProtocolError):
        apply_trainer_message(b"(kickOff Left", referee, world)


def test_self_collision_freezes_joints_once_per_immunity() -> None:
    import numpy as np

    from kinematics.spec import robot_spec

    class PoseWorld(FakeWorld):
        def __init__(self, poses) -> None:
            super().__init__()
            self.poses = poses

        def robot_body_poses(self):
            return [("left", 5, 0, self.poses)]

    spec = robot_spec(0)
    poses = {}
    for body in spec.bodies:
        x, y, z = spec.body_position_m(body.name)
        poses[body.name] = ((x - 2.0, y, z + 0.4), tuple(np.eye(3).ravel()))
    # Turn the left lower arm about a skewed axis and push it into the torso.
    axis = np.array([1.0, 2.0, 3.0]) / math.sqrt(14.0)
    angle = 0.7
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    rotation = np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k
    poses["llowerarm"] = (poses["torso"][0], tuple(rotation.ravel()))
    world = PoseWorld(poses)
    world.add("left", 5, -2.0, 0.0)
    referee = started(world)
    run(referee, world, 1)
    sc = [f for f in referee.fouls if f.type == FoulType.SELF_COLLISION]
    assert len(sc) == 1 and world.frozen and world.frozen[0][2] == ["lae1", "lae2", "lae3", "lae4"]
    run(referee, world, 100)  # within frozen + thaw (3 s): no new foul, and no new freeze
    assert len([f for f in referee.fouls if f.type == FoulType.SELF_COLLISION]) == 1
    assert len(world.frozen) == 1
    run(referee, world, 60)
    assert len([f for f in referee.fouls if f.type == FoulType.SELF_COLLISION]) == 2
    assert len(world.frozen) == 2


def test_parallel_boxes_never_report_a_self_collision() -> None:
    """The server's unnormalised separating-axis test: aligned boxes always 'separate'."""
    import numpy as np

    from sim.rules.self_collision import boxes_overlap

    eye = tuple(np.eye(3).ravel())
    assert not boxes_overlap(((0, 0, 0), eye), (0.1, 0.1, 0.1), ((0.01, 0, 0), eye), (0.1, 0.1, 0.1), 0.04)


@pytest.mark.parametrize("side, sign", [("left", 1.0), ("right", -1.0)])
def test_before_kick_off_moves_a_footprint_over_the_centre_line_and_nothing_short_of_it(side: str, sign: float) -> None:
    """The clearing looks at the robot's square footprint, not its torso point: a torso 1 cm inside its own half
    whose footprint reaches over the line is pushed back, one whose footprint stops 1 cm short is left alone
    (the referee skips building its placer when no footprint touches the other half)."""
    e = default_config().agent_half_extent_m
    world = FakeWorld()
    over = world.add(side, 4, -sign * (e - 0.01), 1.0)
    short = world.add(side, 5, -sign * (e + 0.01), -1.0)
    referee = Referee(seed=0)
    run(referee, world, 1)
    assert sign * over.pos[0] <= -2.5 + 1e-9
    assert short.pos[:2] == [-sign * (e + 0.01), -1.0]
    assert [move[:2] for move in world.moves] == [(side, 4)]
