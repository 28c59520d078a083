"""Replay a SimSpark monitor log (ours or rcssserver3d's ``sparkmonitor.log``) as a meshcat animation.

`read_log` mirrors the scene graph line by line (full states replace it, diffs update transforms by tree
position, as RoboViz does) and yields one `ReplayFrame` per line: game time and state, the ball pose and
every robot's body poses, robots being found by their materials (matLeft/matRight, matNum<n>) and mesh
(naobody<type>). `replay_log` draws the field and the robots' SimSpark shapes and plays the frames in a
meshcat viewer on 127.0.0.1, or writes a standalone HTML file with the animation.
"""

from __future__ import annotations

import bz2
import gzip
import logging
import math
import time
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from agent.protocol.monitor import parse_monitor
from sim.monitor_scene import robot_body_order
from sim.errors import MonitorLogError

logger = logging.getLogger(__name__)

#: Frames of an animation at most by default; longer logs are sampled evenly (a 10-minute match logged
#: every 0.2 s has 3000 frames).
DEFAULT_MAX_FRAMES = 3000
#: Animation bytes of a replay page at most (the field, meshes and viewer add about 1 MB): issue 16's
#: 10 MB for replay.html.
DEFAULT_MAX_ANIMATION_BYTES = 8_000_000
TEAM_COLOURS = {"left": 0x3060D0, "right": 0xD04030, None: 0x909090}
_HIDDEN = np.diag([1.0, 1.0, 1.0, 1.0])
_HIDDEN[2, 3] = -50.0  # robots not in a frame are parked under the field


@dataclass
class _SceneNode:
    kind: str
    matrix: np.ndarray | None = None
    model: str | None = None
    materials: tuple[str, ...] = ()
    children: list[_SceneNode] = field(default_factory=list)


@dataclass
class RobotPose:
    """One robot in a frame: side "left"/"right" (None if unknown), number, type, body name -> 4x4 pose."""

    side: str | None
    unum: int
    robot_type: int
    bodies: dict[str, np.ndarray]


@dataclass
class ReplayFrame:
    """One log line: game time [s], play mode index, scores, ball pose (4x4) and robots by "side_unum"."""

    time_s: float
    play_mode: int | None
    score: tuple[int, int]
    ball: np.ndarray | None
    robots: dict[str, RobotPose]


def _open(path: Path):
    if path.suffix == ".gz":
        return gzip.open(path, "rt", encoding="ascii", errors="replace")
    if path.suffix == ".bz2":
        return bz2.open(path, "rt", encoding="ascii", errors="replace")
    return open(path, encoding="ascii", errors="replace")


def _build(expression: list) -> _SceneNode:
    """A scene node from a full-state ``(nd KIND ...)`` expression."""
    kind = expression[1] if len(expression) > 1 and isinstance(expression[1], str) else "BN"
    node = _SceneNode(kind)
    for item in expression[1:]:
        if not isinstance(item, list) or not item:
            continue
        head = item[0]
        if head == "nd":
            node.children.append(_build(item))
        elif head == "SLT" and len(item) == 17:
            node.matrix = np.array([float(v) for v in item[1:]]).reshape(4, 4).T
        elif head == "load" and len(item) > 1:
            node.model = item[1]
        elif head in ("resetMaterials", "sMat"):
            node.materials = tuple(str(v) for v in item[1:])
    return node


def _update(node: _SceneNode, expression: list) -> None:
    """Apply a diff ``(nd [(SLT ...)] children...)`` to the mirrored node, children by position."""
    index = 0
    for item in expression[1:]:
        if not isinstance(item, list) or not item:
            continue
        if item[0] == "SLT" and len(item) == 17:
            node.matrix = np.array([float(v) for v in item[1:]]).reshape(4, 4).T
        elif item[0] == "nd":
            if index < len(node.children):
                _update(node.children[index], item)
            index += 1


def _meshes(node: _SceneNode) -> Iterator[_SceneNode]:
    if node.model is not None:
        yield node
    for child in node.children:
        yield from _meshes(child)


def _robot_identity(node: _SceneNode) -> tuple[str | None, int, int] | None:
    """(side, unum, type) when ``node`` is a robot's top node (its first body holds naobody<type>)."""
    if not node.children or node.children[0].kind != "TRF":
        return None
    for mesh in _meshes(node.children[0]):
        if mesh.model and mesh.model.startswith("models/naobody"):
            digits = mesh.model[len("models/naobody"):].split(".")[0]
            robot_type = int(digits) if digits.isdigit() else 0
            side = "left" if "matLeft" in mesh.materials else "right" if "matRight" in mesh.materials else None
            unum = next((int(m[6:]) for m in mesh.materials if m.startswith("matNum") and m[6:].isdigit()), 0)
            return side, unum, robot_type
    return None


def _world(matrix: np.ndarray | None, parent: np.ndarray) -> np.ndarray:
    return parent if matrix is None else parent @ matrix


def _frame(roots: list[_SceneNode], state: dict[str, str]) -> ReplayFrame:
    ball = None
    robots: dict[str, RobotPose] = {}
    for root in roots:
        top = _world(root.matrix, np.eye(4))
        if any(m.model == "models/soccerball.obj" for m in _meshes(root)):
            ball = top
            continue
        identity = _robot_identity(root)
        if identity is None:
            continue
        side, unum, robot_type = identity
        names = robot_body_order(robot_type)
        bodies = {name: _world(child.matrix, top) for name, child in zip(names, root.children)}
        robots[f"{side}_{unum}"] = RobotPose(side, unum, robot_type, bodies)
    mode = state.get("play_mode")
    return ReplayFrame(float(state.get("time", "0")), int(mode) if mode is not None else None,
                       (int(state.get("score_left", "0")), int(state.get("score_right", "0"))), ball, robots)


def read_log(path: str | Path) -> Iterator[ReplayFrame]:
    """Frames of a monitor log (plain, .gz or .bz2); lines before the first full state and lines that do
    not parse are skipped (logged with their line number)."""
    roots: list[_SceneNode] | None = None
    state: dict[str, str] = {}
    with _open(Path(path)) as lines:
        for number, line in enumerate(lines, start=1):
            if not line.strip():
                continue
            try:
                message = parse_monitor(line)
            except ValueError as error:
                logger.warning("%s:%d: skipped: %s", path, number, error)
                continue
            for key, values in message.entries:
                if values and key in ("time", "play_mode", "score_left", "score_right"):
                    state[key] = values[0]
            scene = message.scene or []
            if message.is_full:
                roots = [_build(item) for item in scene if isinstance(item, list) and item and item[0] == "nd"]
            elif roots is None:
                continue
            else:
                nodes = [item for item in scene if isinstance(item, list) and item and item[0] == "nd"]
                for node, item in zip(roots, nodes):
                    _update(node, item)
            yield _frame(roots, state)


# ---- meshcat ---------------------------------------------------------------------------------------
def _field(vis, config=None) -> None:
    import meshcat.geometry as g
    import meshcat.transformations as tf

    from sim.rules.params import default_config

    c = config or default_config()
    grass = g.MeshLambertMaterial(color=0x3A8A3A)
    white = g.MeshLambertMaterial(color=0xFFFFFF)
    vis["field/grass"].set_object(g.Box([c.field_length_m + 2, c.field_width_m + 2, 0.01]), grass)
    vis["field/grass"].set_transform(tf.translation_matrix([0, 0, -0.006]))
    hl, hw, w = c.half_length_m, c.half_width_m, 0.05
    area_x, area_y = c.penalty_length_m, (c.penalty_width_m + c.goal_width_m) / 2
    segments = [((-hl, -hw), (hl, -hw)), ((-hl, hw), (hl, hw)), ((-hl, -hw), (-hl, hw)), ((hl, -hw), (hl, hw)),
                ((0, -hw), (0, hw))]
    for s in (-1, 1):
        x0, x1 = s * hl, s * (hl - area_x)
        segments += [((x1, -area_y), (x1, area_y)), ((x0, area_y), (x1, area_y)), ((x0, -area_y), (x1, -area_y))]
    chords = 10
    for i in range(chords):
        a, b = 2 * math.pi * i / chords, 2 * math.pi * (i + 1) / chords
        segments.append(((2 * math.cos(a), 2 * math.sin(a)), (2 * math.cos(b), 2 * math.sin(b))))
    for i, ((x0, y0), (x1, y1)) in enumerate(segments):
        length = math.hypot(x1 - x0, y1 - y0)
        vis[f"field/line{i}"].set_object(g.Box([length, w, 0.002]), white)
        vis[f"field/line{i}"].set_transform(tf.translation_matrix([(x0 + x1) / 2, (y0 + y1) / 2, 0.0])
                                            @ tf.rotation_matrix(math.atan2(y1 - y0, x1 - x0), [0, 0, 1]))
    # Goal collision boxes of REFERENCE §4.1, relative to the goal centre (local x points out of the field).
    parts = (((0, -1.07, 0), (0.6, 0.04, 0.8)), ((0, 1.07, 0), (0.6, 0.04, 0.8)), ((-0.28, 0, 0), (0.04, 2.1, 0.8)),
             ((0, 0, 0.42), (0.6, 2.18, 0.04)))
    for s, colour in ((-1, 0xE0D040), (1, 0x40A0E0)):
        for i, ((x, y, z), size) in enumerate(parts):
            name = f"field/goal{'l' if s < 0 else 'r'}{i}"
            vis[name].set_object(g.Box(list(size)), g.MeshLambertMaterial(color=colour, opacity=0.7, transparent=True))
            vis[name].set_transform(tf.translation_matrix([s * (15.3 - x), y, 0.4 + z]))


def replay_log(path: str | Path, html_out: str | Path | None = None, *, max_frames: int = DEFAULT_MAX_FRAMES,
               max_html_bytes: int = DEFAULT_MAX_ANIMATION_BYTES, block: bool = True) -> str:
    """Show a monitor log in meshcat (server on 127.0.0.1) or write it as a standalone HTML animation.

    Args:
        path: the log (one monitor message per line; .gz and .bz2 are read too).
        html_out: write a standalone HTML file here instead of serving.
        max_frames: longest animation; longer logs are sampled evenly.
        max_html_bytes: fewer frames still when the animation of every body would pass this size (the
            replay of a 10-minute 11 v 11 match gets about one frame per 1.5 s; three.js interpolates).
        block: when serving, wait for Ctrl-C before returning (the viewer lives as long as this process).

    Returns:
        The viewer URL, or the HTML path.

    Raises:
        ValueError: the log holds no full state (nothing to show).
    """
    import meshcat.geometry as g
    from meshcat.commands import SetAnimation

    from kinematics.meshcat_server import loopback_visualizer
    from kinematics.meshcat_view import add_nao
    from kinematics.spec import robot_spec
    from sim.replay_animation import BYTES_PER_BODY_FRAME, CompactAnimation

    frames = list(read_log(path))
    if not frames:
        raise MonitorLogError(f"{path}: no full-state line, nothing to replay")
    robots: dict[str, RobotPose] = {}
    for frame in frames:
        for name, robot in frame.robots.items():
            robots.setdefault(name, robot)
    # Only the bodies with a collision shape are drawn: the 1 cm joint spheres vanish at field scale and would
    # cost 10 of every 23 tracks.
    shown = {name: [b.name for b in robot_spec(robot.robot_type).bodies if b.collider] for name, robot in robots.items()}
    tracks = 1 + sum(len(bodies) for bodies in shown.values())
    budget_frames = max(2, int(max_html_bytes // (tracks * BYTES_PER_BODY_FRAME)))
    stride = max(1, math.ceil(len(frames) / max(1, min(max_frames, budget_frames))))
    frames = frames[::stride]
    vis = loopback_visualizer()  # 127.0.0.1 only, ends with this process
    _field(vis)
    vis["ball"].set_object(g.Sphere(0.042), g.MeshLambertMaterial(color=0xFF8000))
    for name, robot in robots.items():
        add_nao(vis, f"robots/{name}", robot.robot_type, colour=TEAM_COLOURS.get(robot.side, 0x909090))
        for body in robot_spec(robot.robot_type).bodies:
            if not body.collider:
                vis[f"robots/{name}/{body.name}"].delete()
    animation = CompactAnimation(fps=1.0 / max(1e-3, _frame_period(frames)))
    ball_path = vis["ball"].path.lower()
    body_paths = {name: [(body, vis[f"robots/{name}/{body}"].path.lower()) for body in bodies]
                  for name, bodies in shown.items()}
    for index, frame in enumerate(frames):
        if frame.ball is not None:
            animation.set_transform(ball_path, index, frame.ball)
        for name, paths in body_paths.items():
            present = frame.robots.get(name)
            for body, body_path in paths:
                pose = present.bodies.get(body, _HIDDEN) if present is not None else _HIDDEN
                animation.set_transform(body_path, index, pose)
    vis.window.send(SetAnimation(animation, play=html_out is None, repetitions=1))
    last = frames[-1]
    logger.info("replaying %d frames of %s (%d robots), final time %.2f s, score %d:%d", len(frames), path,
                len(robots), last.time_s, *last.score)
    if html_out is not None:
        try:
            Path(html_out).write_text(vis.static_html())
        finally:
            _stop_meshcat(vis)
        return str(html_out)
    url = vis.url()
    logger.info("meshcat viewer: %s (Ctrl-C to stop)", url)
    if block:
        try:
            while True:
                time.sleep(1.0)
        except KeyboardInterrupt:
            pass
        finally:
            _stop_meshcat(vis)
    return url


def _stop_meshcat(vis) -> None:
    """End the meshcat server child of a ``loopback_visualizer``."""
    vis.close()


def _frame_period(frames: list[ReplayFrame]) -> float:
    """Seconds between frames from the logged game time, 0.04 s when the clock did not move."""
    times = [f.time_s for f in frames]
    steps = [b - a for a, b in zip(times, times[1:]) if b > a]
    return float(np.median(steps)) if steps else 0.04
