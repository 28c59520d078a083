"""The replay page's compact animation: float32 tracks that reproduce the logged poses, unmoved bodies kept to
their two end keys, and the frame budget that keeps replay.html small."""

from __future__ import annotations

import base64
import gzip
import math
import re
from pathlib import Path

import numpy as np
import pytest
import umsgpack

from sim.monitor import GameView, MonitorLogWriter, RobotView, SceneSnapshot
from sim.monitor_scene import pose_matrix, robot_body_order, translation
from sim.replay import read_log, replay_log
from sim.replay_animation import FLOAT32_EXT


def _yaw(angle: float) -> tuple[float, ...]:
    c, s = math.cos(angle), math.sin(angle)
    return (c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)


def _write_log(path: Path, robots: int, cycles: int) -> None:
    """Robot 1 of the left team walks along x turning; the others stand still."""
    names = robot_body_order(0)
    snapshots = []
    for cycle in range(cycles):
        walking = {n: pose_matrix((-3.0 + 0.01 * cycle, 0.1 * i, 0.3), _yaw(0.01 * cycle)) for i, n in enumerate(names)}
        team = [RobotView("left", 1, 0, walking)]
        team += [RobotView("right", unum, 0, {n: translation(unum, 0.1 * i, 0.3) for i, n in enumerate(names)})
                 for unum in range(1, robots)]
        game = GameView(time_s=cycle * 0.02, play_mode_index=3, team_left="A", team_right="B")
        snapshots.append(SceneSnapshot(game, translation(0.02 * cycle, 0.0, 0.042), tuple(team)))
    with gzip.open(path, "wt") as out:
        writer = MonitorLogWriter(out, lambda: snapshots[cycle], step_cycles=2)
        for cycle in range(cycles):
            writer.on_cycle(cycle)


def _animation(html: str) -> list[dict]:
    blobs = [base64.b64decode(b) for b in re.findall(r"base64,([A-Za-z0-9+/=]+)", html)]
    blob = next(b for b in blobs if b"set_animation" in b)
    handlers = {FLOAT32_EXT: lambda ext: np.frombuffer(ext.data, dtype="<f4")}
    return umsgpack.unpackb(blob, ext_handlers=handlers)["animations"]


def test_tracks_reproduce_the_logged_poses_and_drop_unmoved_keys(tmp_path: Path) -> None:
    log = tmp_path / "match.log.gz"
    _write_log(log, robots=2, cycles=120)
    frames = list(read_log(log))
    html = tmp_path / "replay.html"
    replay_log(log, html_out=html)
    clips = {a["path"]: a["clip"] for a in _animation(html.read_text())}
    # Only bodies with a collision shape are animated (13 of 23 per robot), plus the ball.
    assert len(clips) == 1 + 2 * 13 and "/meshcat/robots/left_1/lhip1" not in clips
    tracks = {t["name"]: t for t in clips["/meshcat/robots/left_1/torso"]["tracks"]}
    times, values = tracks[".position"]["times"], tracks[".position"]["values"].reshape(-1, 3)
    truth = np.array([f.robots["left_1"].bodies["torso"][:3, 3] for f in frames])
    for axis in range(3):
        rebuilt = np.interp(np.arange(len(frames)), times, values[:, axis])
        assert rebuilt == pytest.approx(truth[:, axis], abs=0.002)
    quaternion = tracks[".quaternion"]["values"].reshape(-1, 4)
    yaw = 2 * np.arctan2(quaternion[-1, 2], quaternion[-1, 3])   # x, y, z, w about z
    assert yaw == pytest.approx(math.atan2(frames[-1].robots["left_1"].bodies["torso"][1, 0],
                                           frames[-1].robots["left_1"].bodies["torso"][0, 0]), abs=0.01)
    still = {t["name"]: t for t in clips["/meshcat/robots/right_1/torso"]["tracks"]}
    assert len(still[".position"]["times"]) == 2 and len(still[".quaternion"]["times"]) == 2


def test_the_frame_budget_bounds_the_page(tmp_path: Path) -> None:
    log = tmp_path / "match.log.gz"
    _write_log(log, robots=6, cycles=400)
    small, large = tmp_path / "small.html", tmp_path / "large.html"
    replay_log(log, html_out=large)
    replay_log(log, html_out=small, max_html_bytes=20_000)
    large_times = len(_animation(large.read_text())[0]["clip"]["tracks"][0]["times"])
    small_times = len(_animation(small.read_text())[0]["clip"]["tracks"][0]["times"])
    assert small_times < large_times / 3
    assert small.stat().st_size < large.stat().st_size
