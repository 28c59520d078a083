"""Reading monitor logs back (the real server's sample and ours) and the meshcat replay."""

from __future__ import annotations

import gzip
from pathlib import Path

import numpy as np
import pytest

from sim.monitor import GameView, MonitorLogWriter, RobotView, SceneSnapshot
from sim.monitor_scene import robot_body_order, translation
from sim.replay import read_log, replay_log

SAMPLE = Path(__file__).resolve().parents[3] / "shared" / "samples" / "rcssserver3d-0.7.3_monitor_first_frames.txt"


def test_reads_the_real_server_sample() -> None:
    if not SAMPLE.exists():
        pytest.skip("sample not available")
    frames = list(read_log(SAMPLE))
    assert len(frames) == 3
    first, second, third = frames
    robot = first.robots["left_1"]
    assert robot.robot_type == 0 and robot.unum == 1
    assert robot.bodies["torso"][:3, 3] == pytest.approx([-14.2, 9.2, 0.396077], abs=1e-5)
    assert second.robots["left_1"].bodies["torso"][:3, 3] == pytest.approx([-2.99858, 0.0304189, 0.396076])
    assert third.robots["left_1"].bodies["lfoot"][2, 3] == pytest.approx(0.00147267, abs=1e-6)
    assert first.ball[:3, 3] == pytest.approx([0, 0, 0.0417605])
    assert third.ball[:3, 3] == pytest.approx([0, 0, 0.0417605])  # unchanged transforms are kept


def _write_log(path: Path, cycles: int = 60) -> None:
    def bodies(x: float) -> dict:
        return {name: translation(x, 1.0, 0.3) for name in robot_body_order(0)}

    snapshots = []
    for i in range(cycles + 1):
        game = GameView(time_s=i * 0.02, play_mode_index=3, team_left="A", team_right="B", score_left=i // 40)
        robots = (RobotView("left", 3, 0, bodies(-1.0 + i * 0.01)),)
        if i >= 30:
            robots += (RobotView("right", 5, 0, bodies(2.0)),)
        snapshots.append(SceneSnapshot(game, translation(i * 0.05, 0.0, 0.042), robots))
    opener = gzip.open if path.suffix == ".gz" else open
    with opener(path, "wt") as out:
        writer = MonitorLogWriter(out, lambda: snapshots[cycle], step_cycles=2)
        for cycle in range(cycles + 1):
            writer.on_cycle(cycle)


@pytest.mark.parametrize("name", ["match.log", "match.log.gz"])
def test_round_trip_of_our_log(tmp_path: Path, name: str) -> None:
    path = tmp_path / name
    _write_log(path)
    frames = list(read_log(path))
    assert len(frames) == 31
    assert frames[-1].time_s == pytest.approx(1.2) and frames[-1].score == (1, 0) and frames[-1].play_mode == 3
    assert frames[10].ball[:3, 3] == pytest.approx([1.0, 0.0, 0.042], abs=1e-6)
    assert set(frames[10].robots) == {"left_3"} and set(frames[-1].robots) == {"left_3", "right_5"}
    assert frames[-1].robots["left_3"].bodies["head"][0, 3] == pytest.approx(-0.4, abs=1e-6)


def test_replay_writes_a_standalone_html_animation(tmp_path: Path) -> None:
    log = tmp_path / "match.log"
    _write_log(log, cycles=40)
    out = tmp_path / "replay.html"
    assert replay_log(log, html_out=out) == str(out)
    html = out.read_text()
    assert "<html>" in html and "handle_command_bytearray" in html
    import base64
    import re


    blobs = [base64.b64decode(blob) for blob in re.findall(r"base64,([A-Za-z0-9+/=]+)", html)]
    animations = [blob for blob in blobs if b"set_animation" in blob]
    assert len(animations) == 1
    assert b"/meshcat/ball" in animations[0] and b"/meshcat/robots/right_5/torso" in animations[0]


def test_replay_of_a_log_without_full_state_is_an_error(tmp_path: Path) -> None:
    log = tmp_path / "empty.log"
    log.write_text("((time 0))(RDS 0 1)((nd))\n")
    with pytest.raises(ValueError, match="no full-state"):
        replay_log(log, html_out=tmp_path / "x.html")
    assert np.isfinite(0.0)


def test_log_of_the_real_world_reads_back_with_the_body_poses(tmp_path: Path) -> None:
    from sim.monitor import MujocoWorldScene, snapshot_of
    from sim.referee import Referee
    from sim.world import World

    world, referee = World(), Referee(seed=0)
    world.add_robot(1, 4)
    assignment = referee.on_init("Toes", 0, robot_type=4)
    world.set_team(1, assignment.side, assignment.unum)
    world.place_robot(1, -3.0, 1.0, 30.0, 0.4)
    world.end_cycle()
    scene = MujocoWorldScene(world)
    log = tmp_path / "world.log"
    with open(log, "w") as out:
        writer = MonitorLogWriter(out, lambda: snapshot_of(scene, referee))
        for cycle in range(20):
            world.begin_cycle()
            world.step()
            referee.update(world)
            world.end_cycle()
            writer.on_cycle(cycle)
    frames = list(read_log(log))
    robot = frames[-1].robots["left_1"]
    assert robot.robot_type == 4 and set(robot.bodies) == set(robot_body_order(4))
    m, d = world.model, world.data
    for body in ("torso", "head", "ltoe", "rfoot"):
        index = m.body("r1_" + body).id
        assert robot.bodies[body][:3, 3] == pytest.approx(d.xpos[index], abs=0.006)
        assert robot.bodies[body][:3, :3] == pytest.approx(d.xmat[index].reshape(3, 3), abs=0.006)
