"""The referee on the real MuJoCo world: a ball pushed into a goal scores; a ball kicked over the touch line
gives a kick-in to the right team."""

from __future__ import annotations

import pytest

from sim.referee import Referee
from sim.world import World


def cycle(world: World, referee: Referee) -> None:
    """One cycle in the engine's order (sim.world module docstring): sample, physics, referee, poses."""
    world.begin_cycle()
    world.step()
    referee.update(world)
    world.end_cycle()


def setup(robots: list[tuple[int, str, int, float, float, float]]) -> tuple[World, Referee]:
    world = World()
    referee = Referee(seed=0)
    for key, team, unum, x, y, heading in robots:
        world.add_robot(key, 0)
        assignment = referee.on_init(team, unum)
        assert assignment is not None
        world.set_team(key, assignment.side, assignment.unum)
        world.place_robot(key, x, y, heading, 0.4)
    world.end_cycle()
    return world, referee


def run_until(world: World, referee: Referee, predicate, max_cycles: int) -> int:
    for n in range(1, max_cycles + 1):
        cycle(world, referee)
        if predicate():
            return n
    raise AssertionError(f"not reached in {max_cycles} cycles; mode {referee.play_mode}, ball {world.ball_position()}")


def test_ball_pushed_into_the_goal_scores_then_conceding_team_kicks_off() -> None:
    world, referee = setup([(1, "Lefties", 9, 10.0, 3.0, 0.0), (2, "Righties", 1, 14.0, -3.0, 180.0)])
    referee.kick_off("Left")
    referee.set_play_mode("PlayOn")
    world.set_ball((13.0, 0.3, 0.042), (6.0, 0.0, 0.0))
    run_until(world, referee, lambda: referee.play_mode != "PlayOn", 100)
    assert referee.play_mode == "Goal_Left" and referee.play_mode_index == 13
    assert (referee.score_left, referee.score_right) == (1, 0)
    assert referee.allows_beam()
    goal_time = referee.game_time_s
    run_until(world, referee, lambda: referee.play_mode != "Goal_Left", 200)
    assert referee.play_mode == "KickOff_Right"
    assert referee.game_time_s - goal_time == pytest.approx(3.0, abs=0.021)
    x, y, z = world.ball_position()
    assert (x, y) == pytest.approx((0.0, 0.0), abs=0.01) and z == pytest.approx(0.042, abs=0.01)


def test_ball_over_the_touch_line_gives_a_kick_in_to_the_right_team() -> None:
    world, referee = setup([(1, "Lefties", 9, 3.0, 9.0, 0.0)])
    referee.set_play_mode("PlayOn")
    for _ in range(30):  # let the robot settle on its feet
        cycle(world, referee)
    # The ball starts against the left foot (outer side) and rolls toward the touch line: the left player
    # is the last to touch it.
    world.set_ball((3.03, 9.13, 0.042), (0.0, 2.0, 0.0))
    run_until(world, referee, lambda: referee.play_mode != "PlayOn", 150)
    assert referee.play_mode == "KickIn_Right"
    run_until(world, referee, lambda: referee.mode_time_s > 1.1, 100)
    x, y, _ = world.ball_position()
    assert x == pytest.approx(3.03, abs=0.05) and y == pytest.approx(10.0 - 0.042, abs=1e-3)


def test_robots_standing_still_commit_no_fouls() -> None:
    from sim.monitor import MujocoWorldScene

    world, referee = setup([(1, "A", 2, -3.0, 1.0, 0.0), (2, "A", 3, -3.0, -1.0, 0.0), (3, "B", 2, 3.0, 1.0, 180.0),
                            (4, "B", 3, 3.0, -1.0, 180.0)])
    referee.body_pose_source = MujocoWorldScene(world).robot_body_poses
    referee.set_play_mode("PlayOn")
    for _ in range(100):
        cycle(world, referee)
    assert referee.fouls == []
    assert all(robot.torso_pos_m[2] > 0.3 for robot in world.robots())
