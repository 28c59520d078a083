"""Compact match logs (issue 16 item 4): full state, then diffs, numbers at log precision, read back as the full
log reads; the real server's log still parses and our compact full state keeps its scene-graph tree."""

from __future__ import annotations

import gzip
import math
import re
from pathlib import Path

import numpy as np
import pytest

from agent.protocol.sexpr import parse_sexpr
from sim.monitor import GameView, MonitorLogWriter, MonitorStream, RobotView, SceneSnapshot
from sim.monitor_scene import TRANSFORM_PRECISION, compact_number, pose_matrix, robot_body_order
from sim.replay import read_log

SAMPLE = Path(__file__).resolve().parents[3] / "shared" / "samples" / "rcssserver3d-0.7.3_monitor_first_frames.txt"
CYCLES = 120


def _rotation(yaw: float, pitch: float, roll: float) -> tuple[float, ...]:
    cy, sy, cp, sp, cr, sr = math.cos(yaw), math.sin(yaw), math.cos(pitch), math.sin(pitch), math.cos(roll), math.sin(roll)
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    return tuple((rz @ ry @ rx).ravel())


def _snapshots(seed: int = 7) -> list[SceneSnapshot]:
    """A walking robot (every body turning and moving a little each cycle), a robot standing still, a ball
    rolling: random walks from a fixed seed."""
    rng = np.random.default_rng(seed)
    names = robot_body_order(0)
    angles = rng.uniform(-math.pi, math.pi, (len(names), 3))
    positions = rng.uniform(-5, 5, (len(names), 3))
    still = {name: pose_matrix((2.0, float(i) * 0.01, 0.3), _rotation(0.3 * i, 0.1, 0.0)) for i, name in enumerate(names)}
    out = []
    for cycle in range(CYCLES):
        angles += rng.normal(0.0, 0.02, angles.shape)
        positions += rng.normal(0.0, 0.004, positions.shape)
        walking = {name: pose_matrix(tuple(positions[i]), _rotation(*angles[i])) for i, name in enumerate(names)}
        ball = pose_matrix((0.01 * cycle, -0.002 * cycle, 0.042), _rotation(0.05 * cycle, 0.0, 0.0))
        game = GameView(time_s=cycle * 0.02, play_mode_index=3, team_left="A", team_right="B")
        out.append(SceneSnapshot(game, ball, (RobotView("left", 2, 0, walking), RobotView("right", 7, 0, still))))
    return out


def _write(path: Path, snapshots: list[SceneSnapshot], **options) -> list[str]:
    with gzip.open(path, "wt") as out:
        writer = MonitorLogWriter(out, lambda: snapshots[cycle], step_cycles=1, **options)
        for cycle in range(len(snapshots)):
            writer.on_cycle(cycle)
    return gzip.open(path, "rt").read().splitlines()


def test_the_diff_log_reads_back_as_the_full_log(tmp_path: Path) -> None:
    snapshots = _snapshots()
    full_lines = _write(tmp_path / "full.log.gz", snapshots, full_state_every_s=0.001, decimals=None)
    diff_lines = _write(tmp_path / "diff.log.gz", snapshots)
    assert all("(RSG 0 1)" in line for line in full_lines)
    assert "(RSG 0 1)" in diff_lines[0] and all("(RDS 0 1)" in line for line in diff_lines[1:])
    # The still robot's transforms are sent once, in the full state; the walking robot's again and again.
    assert diff_lines[1].count("(SLT") < len(robot_body_order(0)) + 2
    full_frames = list(read_log(tmp_path / "full.log.gz"))
    diff_frames = list(read_log(tmp_path / "diff.log.gz"))
    assert len(full_frames) == len(diff_frames) == CYCLES
    worst = 0.0
    for full, diff in zip(full_frames, diff_frames):
        assert diff.time_s == pytest.approx(full.time_s) and set(diff.robots) == set(full.robots) == {"left_2", "right_7"}
        worst = max(worst, float(np.abs(diff.ball - full.ball).max()))
        for key, robot in full.robots.items():
            for name, pose in robot.bodies.items():
                worst = max(worst, float(np.abs(diff.robots[key].bodies[name] - pose).max()))
    # Within the server's own diff tolerance (plus float32 rounding of the full log), and not trivially exact.
    assert 1e-4 < worst <= TRANSFORM_PRECISION + 1e-6


def test_the_compact_log_is_a_fraction_of_the_servers_spelling(tmp_path: Path) -> None:
    snapshots = _snapshots()
    _write(tmp_path / "server.log.gz", snapshots, decimals=None)
    _write(tmp_path / "compact.log.gz", snapshots)
    server, compact = ((tmp_path / name).stat().st_size for name in ("server.log.gz", "compact.log.gz"))
    assert compact < 0.6 * server


def test_compact_numbers() -> None:
    assert [compact_number(v, 3) for v in (-8.74228e-08, 0.99483, -2.99858, 1.0, -0.0004, 12.5)] == \
        ["0", "0.995", "-2.999", "1", "0", "12.5"]


def _sample_lines() -> list[str]:
    if not SAMPLE.exists():
        pytest.skip("the recorded monitor sample is not available")
    return [line for line in SAMPLE.read_text().split("\n") if line]


def _skeleton(line: str) -> str:
    """The scene graph with every transform's numbers taken out."""
    scene = line[line.index(")(R") + 1:]
    return re.sub(r"\(SLT[^)]*\)", "(SLT)", scene[scene.index(")") + 1:])


def test_a_real_server_log_still_parses_plain_and_gzipped(tmp_path: Path) -> None:
    lines = _sample_lines()
    packed = tmp_path / "sparkmonitor.log.gz"
    with gzip.open(packed, "wt") as out:
        out.write("\n".join(lines) + "\n")
    plain, zipped = list(read_log(SAMPLE)), list(read_log(packed))
    assert len(plain) == len(zipped) == 3
    assert zipped[2].robots["left_1"].bodies["lfoot"][2, 3] == pytest.approx(0.00147267, abs=1e-6)
    assert np.array_equal(plain[2].robots["left_1"].bodies["torso"], zipped[2].robots["left_1"].bodies["torso"])


def test_the_compact_full_state_keeps_the_real_servers_scene_tree() -> None:
    """Same nodes, meshes, materials and order as rcssserver3d's own full state: only the numbers of the
    transforms are spelled shorter, so RoboViz reads our logs as the server's."""
    real = _sample_lines()[0]
    scene = parse_sexpr(real)[2]
    names = robot_body_order(0)
    robot_nodes = [item for item in scene[36][1:] if isinstance(item, list) and item[0] == "nd"]
    bodies = {name: tuple(float(v) for v in node[2][1:]) for name, node in zip(names, robot_nodes)}
    ball = tuple(float(v) for v in scene[35][2][1:])
    game = GameView(time_s=0.0, team_left="Capture")
    ours = MonitorStream(decimals=(2, 3)).message(SceneSnapshot(game, ball, (RobotView("left", 1, 0, bodies),)),
                                                  full=True)
    assert _skeleton(ours) == _skeleton(real)
    assert len(ours) < 0.85 * len(real)


def test_the_last_cycle_is_logged_when_the_log_closes(tmp_path: Path) -> None:
    """A line every 10 cycles, and the state of the last cycle at close: a final score is never lost."""
    snapshots = _snapshots()[:25]
    path = tmp_path / "end.log"
    with open(path, "w") as out:
        writer = MonitorLogWriter(out, lambda: snapshots[cycle])
        for cycle in range(len(snapshots)):
            writer.on_cycle(cycle)
        writer.close()
    times = [frame.time_s for frame in read_log(path)]
    assert times == pytest.approx([0.0, 0.2, 0.4, 0.48])
