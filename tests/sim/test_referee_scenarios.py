"""The referee inside the real engine and MuJoCo world: agents connect with scene/init/beam as on the wire;
a ball pushed into a goal scores; a ball kicked over the touch line gives a kick-in to the right team."""

from __future__ import annotations

import pytest

from sim.engine import SimEngine
from sim.monitor import MujocoWorldScene
from sim.rules.params import FoulType


def join(engine: SimEngine, team: str, unum: int, beam: tuple[float, float, float]) -> int:
    """Connect an agent the way a TCP client does: scene, init, then beam (team frame) in BeforeKickOff."""
    agent = engine.connect()
    engine.receive(agent, b"(scene rsg/agent/nao/nao.rsg)")
    engine.step()
    engine.receive(agent, b"(init (unum %d)(teamname %s))" % (unum, team.encode()))
    engine.step()
    engine.receive(agent, b"(beam %g %g %g)(syn)" % beam)
    engine.step()
    return agent


def run_until(engine: SimEngine, predicate, max_cycles: int) -> int:
    for n in range(1, max_cycles + 1):
        engine.step()
        if predicate():
            return n
    raise AssertionError(f"not reached in {max_cycles} cycles; mode {engine.referee.play_mode}, "
                         f"ball {engine.world.ball_position()}")


def test_ball_pushed_into_the_goal_scores_then_conceding_team_kicks_off() -> None:
    engine = SimEngine(seed=1)
    referee, world = engine.referee, engine.world
    join(engine, "Lefties", 9, (-5.0, 3.0, 0.0))
    join(engine, "Righties", 1, (-14.0, 3.0, 0.0))  # right team frame: placed at (14, -3)
    assert [(r.team, r.unum) for r in world.robots()] == [("left", 9), ("right", 1)]
    assert referee.play_mode == "BeforeKickOff" and referee.game_time_s == 0.0
    referee.kick_off("Left")
    referee.set_play_mode("PlayOn")
    world.set_ball((13.0, 0.3, 0.042), (6.0, 0.0, 0.0))
    run_until(engine, lambda: referee.play_mode != "PlayOn", 100)
    assert referee.play_mode == "Goal_Left" and referee.play_mode_index == 13
    assert (referee.score_left, referee.score_right) == (1, 0)
    assert referee.allows_beam()
    goal_time = referee.game_time_s
    run_until(engine, lambda: referee.play_mode != "Goal_Left", 200)
    assert referee.play_mode == "KickOff_Right"
    assert referee.game_time_s - goal_time == pytest.approx(3.0, abs=0.021)
    x, y, z = world.ball_position()
    assert (x, y) == pytest.approx((0.0, 0.0), abs=0.01) and z == pytest.approx(0.042, abs=0.01)


def test_ball_over_the_touch_line_gives_a_kick_in_to_the_right_team() -> None:
    engine = SimEngine(seed=2)
    referee, world = engine.referee, engine.world
    join(engine, "Lefties", 9, (-3.0, 9.0, 0.0))
    referee.set_play_mode("PlayOn")
    for _ in range(30):  # let the robot settle on its feet
        engine.step()
    # The ball starts against the outer side of the left foot and rolls toward the touch line, so the left
    # player is the last to touch it.
    robot = world.robot_of("left", 9)
    foot = world.data.xpos[world.model.body(robot.prefix + "lfoot").id].copy()
    world.set_ball((foot[0], foot[1] + 0.078, 0.042), (0.0, 2.0, 0.0))
    run_until(engine, lambda: referee.play_mode != "PlayOn", 150)
    assert referee.play_mode == "KickIn_Right"
    run_until(engine, lambda: referee.mode_time_s > 1.1, 100)
    x, y, _ = world.ball_position()
    assert x == pytest.approx(foot[0], abs=0.05) and y == pytest.approx(10.0 - 0.042, abs=1e-3)
    # The left player was within FreeKickDistance of the spot: moved 2.5 m toward its own goal.
    (left,) = world.robots()
    assert left.torso_pos_m[0] == pytest.approx(x - 2.5, abs=0.01)


def test_robots_standing_still_commit_no_fouls() -> None:
    engine = SimEngine(seed=3)
    for team, unum, beam in (("A", 2, (-3.0, 1.0, 0.0)), ("A", 3, (-3.0, -1.0, 0.0)), ("B", 2, (-3.0, 1.0, 0.0)),
                             ("B", 3, (-3.0, -1.0, 0.0))):
        join(engine, team, unum, beam)
    engine.referee.body_pose_source = MujocoWorldScene(engine.world).robot_body_poses
    engine.referee.set_play_mode("PlayOn")
    for _ in range(100):
        engine.step()
    assert engine.referee.fouls == []
    assert all(robot.torso_pos_m[2] > 0.3 for robot in engine.world.robots())


def test_self_collision_is_called_in_process_and_freezes_once_per_foul() -> None:
    """The engine hands the referee its body poses (no monitor needed), and each foul freezes the joints
    once: the motors hold them for 1 s by themselves, the rule names them again only after 3 s."""
    import math

    import mujoco
    engine = SimEngine(seed=4)
    join(engine, "A", 2, (-3.0, 1.0, 0.0))
    world, referee = engine.world, engine.referee
    freezes: list[tuple[float, list[str]]] = []
    freeze = world.freeze_joints

    def counted_freeze(team: str, unum: int, effectors: list[str]) -> None:
        freezes.append((world.time_s, list(effectors)))
        freeze(team, unum, effectors)

    world.freeze_joints = counted_freeze  # type: ignore[method-assign]
    # Left lower arm turned into the torso (found by sampling arm poses; a pair the server's test reports).
    robot = world.robot_of("left", 2)
    arm = {"lae1": -77.6, "lae2": 2.4, "lae3": 16.4, "lae4": -56.0}
    index = {j.effector: i for i, j in enumerate(robot.spec.joints)}
    span = world.motors.span(robot.key)
    for effector, angle_deg in arm.items():
        world.data.qpos[world.motors.qadr[span][index[effector]]] = math.radians(angle_deg)
    mujoco.mj_kinematics(world.model, world.data)
    referee.set_play_mode("PlayOn")
    for _ in range(200):   # 4 s; the motors hold the arm where it is
        engine.step()
    fouls = [f for f in referee.fouls if f.type == FoulType.SELF_COLLISION]
    assert len(fouls) == 2 and fouls[1].game_time_s - fouls[0].game_time_s > 3.0
    assert len(freezes) == len(fouls)
    assert all(sorted(effectors) == ["lae1", "lae2", "lae3", "lae4"] for _, effectors in freezes)
