"""The SimSpark monitor scene graph (REFERENCE §5.1, §5.4): node tree, full (RSG) and diff (RDS) writing.

The tree copies what rcssserver3d 0.7.3 sends, node for node, so RoboViz finds its meshes and materials:
two lights, field, skybox, both goals, four walls, four flag and 21 line transforms, the ball, then per
robot an identity transform holding one transform per body (torso, neck, head, right arm, left arm, right
leg, left leg), each with the mesh or sphere the server shows. Static transforms that the server computes
in float32 (mesh rotations of -90 0 180, the field rotation) are copied from the recorded sample
(samples/rcssserver3d-0.7.3_monitor_first_frames.txt) so the text matches byte for byte.

Numbers are printed as C++ ``ostream << float`` does: the value rounded to float32, then ``%g``.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import lru_cache
from operator import sub

from agent.protocol.numbers import format_g6, round_float32

#: 4x4 homogeneous transform, column-major, translation in elements 12-14 (SimSpark's SLT order).
Matrix = tuple[float, ...]

IDENTITY: Matrix = (1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0)
# A transform is re-sent in a diff when any element moved more than this (server: 0.005).
TRANSFORM_PRECISION = 0.005
_MOVED = TRANSFORM_PRECISION.__lt__   # x -> x > TRANSFORM_PRECISION (False for NaN, as the comparison)

# Measured float32 matrices of the real server (see the module docstring).
_FIELD_ROTATION: Matrix = (-1.0, -8.74228e-08, -3.82137e-15, 0.0, 0.0, -4.37114e-08, 1.0, 0.0, -8.74228e-08, 1.0,
                           4.37114e-08, -0.0, 0.0, 0.0, 0.0, 1.0)
_GOAL_MESH: Matrix = (-4.37114e-08, 1.0, 4.37114e-08, 0.0, 0.0, -4.37114e-08, 1.0, 0.0, 1.0, 4.37114e-08,
                      1.91069e-15, 0.0, 0.3, 0.0, -0.4, 1.0)
_RIGHT_GOAL: Matrix = (-1.0, -8.74228e-08, -0.0, -0.0, 8.74228e-08, -1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 15.3, 0.0,
                       0.4, 1.0)
_NAO_MESH_ROTATION: Matrix = (-1.0, 3.82137e-15, 8.74228e-08, -0.0, 8.74228e-08, 4.37114e-08, 1.0, 0.0, 0.0, 1.0,
                              -4.37114e-08, 0.0, 0.0, 0.0, 0.0, 1.0)

#: Body order of a robot in the scene (nao_hetero.rsg: torso, neck+head, right arm, left arm, right leg,
#: left leg); toes follow the foot for robot type 4.
ARM_BODIES = ("shoulder", "upperarm", "elbow", "lowerarm")
LEG_BODIES = ("hip1", "hip2", "thigh", "shank", "ankle", "foot")


def translation(x: float, y: float, z: float) -> Matrix:
    """A pure translation as a column-major matrix."""
    return (1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, float(x), float(y), float(z), 1.0)


def pose_matrix(position: tuple[float, float, float], rotation_row_major: tuple[float, ...]) -> Matrix:
    """Column-major 4x4 from a position and a row-major 3x3 rotation (MuJoCo's ``xmat`` layout)."""
    r = rotation_row_major
    return (r[0], r[3], r[6], 0.0, r[1], r[4], r[7], 0.0, r[2], r[5], r[8], 0.0,
            float(position[0]), float(position[1]), float(position[2]), 1.0)


def number(value: float) -> str:
    """A monitor number: float32 rounding, then C++ default formatting (``-8.74228e-08``, ``-0``)."""
    return format_g6(round_float32(value))


def compact_number(value: float, decimals: int) -> str:
    """A number rounded to ``decimals`` places with no trailing zeros and no ``-0`` (``0.995``, ``-3.1``, ``1``).

    Log files use it for transforms: the server's six significant digits spend most of a line on float
    noise (``-2.69199e-10``) that no viewer shows, and their last digits defeat compression.
    """
    text = f"{value:.{decimals}f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


#: Places of the rotation and the translation numbers of a transform (None: the server's spelling).
Decimals = tuple[int, int] | None


def _spell(matrix: Matrix, decimals: tuple[int, int]) -> list[str]:
    """`compact_number` of each element (translation places for elements 12-14).

    With places >= 1 the 16 numbers are printed by one ``%`` format and their zeros cut by two regular
    expressions over the whole text (the same strings: every number then has a point, so only the zeros after
    it go); a match log spells some 40 transforms per robot and line, and this was its main cost."""
    rotation, translation = decimals
    if rotation < 1 or translation < 1:
        return [compact_number(v, translation if 12 <= i <= 14 else rotation) for i, v in enumerate(matrix)]
    text = _matrix_format(rotation, translation) % tuple(matrix)
    return _NEGATIVE_ZERO.sub("0", _TRAILING_ZEROS.sub("", text)).split(" ")


@lru_cache(maxsize=16)
def _matrix_format(rotation: int, translation: int) -> str:
    return " ".join(f"%.{translation if 12 <= i <= 14 else rotation}f" for i in range(16))


# Zeros at the end of a number, with its point if nothing is left after it ("1.50" -> "1.5", "2.00" -> "2").
_TRAILING_ZEROS = re.compile(r"\.?0+(?= |$)")
# A number that is "-0" once its zeros are cut.
_NEGATIVE_ZERO = re.compile(r"(?<![^ ])-0(?= |$)")


def quantize(matrix: Matrix, decimals: Decimals) -> Matrix:
    """The values a reader gets back from `matrix_text` (float32 for the server's spelling)."""
    if decimals is None:
        return tuple(round_float32(v) for v in matrix)
    return tuple(float(text) for text in _spell(matrix, decimals))


def matrix_text(matrix: Matrix, decimals: Decimals = None) -> str:
    """``(SLT m0 ... m15)``: the server's spelling, or `compact_number` with (rotation, translation) places."""
    if decimals is None:
        return "(SLT " + " ".join(number(v) for v in matrix) + ")"
    return "(SLT " + " ".join(_spell(matrix, decimals)) + ")"


@dataclass
class Node:
    """One scene node: kind "TRF" (transform, ``matrix``), "StaticMesh"/"SMN" (``body`` = the text after
    ``(setVisible v)``), or "Light" (``body`` = its full text). ``key`` identifies it across frames."""

    kind: str
    key: str
    matrix: Matrix | None = None
    body: str = ""
    visible: bool = True
    transparent: bool = False
    children: list[Node] = field(default_factory=list)


def trf(key: str, matrix: Matrix, *children: Node) -> Node:
    return Node("TRF", key, matrix=matrix, children=list(children))


def static_mesh(key: str, model: str, scale: tuple[float, float, float], materials: tuple[str, ...],
                transparent: bool = False) -> Node:
    return Node("StaticMesh", key, body=_static_mesh_body(model, scale, materials), transparent=transparent)


def smn(key: str, load: str, scale: tuple[float, float, float], material: str, visible: bool = True,
        transparent: bool = False) -> Node:
    return Node("SMN", key, body=_smn_body(load, scale, material), visible=visible, transparent=transparent)


# The bodies are cached: a log line rebuilds every robot's nodes (about 500 meshes in 11 v 11), and spelling
# their constant scales again each time was a third of a match log's cost.
@lru_cache(maxsize=1024)
def _static_mesh_body(model: str, scale: tuple[float, float, float], materials: tuple[str, ...]) -> str:
    return f" (load {model}) (sSc {' '.join(number(s) for s in scale)})(resetMaterials {' '.join(materials)})"


@lru_cache(maxsize=1024)
def _smn_body(load: str, scale: tuple[float, float, float], material: str) -> str:
    return f" (load {load}) (sSc {' '.join(number(s) for s in scale)}) (sMat {material})"


def light(key: str, diffuse: tuple[float, ...], ambient: tuple[float, ...], specular: tuple[float, ...]) -> Node:
    def rgba(values: tuple[float, ...]) -> str:
        return " ".join(number(v) for v in values)
    return Node("Light", key, body=f" (setDiffuse {rgba(diffuse)}) (setAmbient {rgba(ambient)}) "
                                   f"(setSpecular {rgba(specular)})")


def _goal(side: str) -> Node:
    left = side == "l"
    model = "models/leftsoccergoal.obj" if left else "models/rightsoccergoal.obj"
    colour = "yellow" if left else "sky-blue"
    parts = [trf(f"goal{side}/{i}", translation(*offset)) for i, offset in enumerate(
        ((0, -1.07, 0), (0, 1.07, 0), (-0.28, 0, 0), (0, 0, 0.42), (0.3, 1.05, 0.4), (0.3, -1.05, 0.4)))]
    mesh = trf(f"goal{side}/mesh", _GOAL_MESH,
               static_mesh(f"goal{side}/mesh/m", model, (2.18, 0.88, 0.68), ("naogoalnet", colour), True))
    return trf(f"goal{side}", translation(-15.3, 0, 0.4) if left else _RIGHT_GOAL, mesh, *parts)


def static_scene() -> list[Node]:
    """Everything before the ball: lights, field, skybox, goals, walls, flags and line transforms."""
    nodes = [
        trf("light1", translation(-10, 10, 10), light("light1/l", (1, 1, 1, 1), (0.8, 0.8, 0.8, 1), (0.1, 0.1, 0.1, 1))),
        trf("light2", translation(10, -10, 10), light("light2/l", (1, 1, 1, 1), (0, 0, 0, 1), (0.1, 0.1, 0.1, 1))),
        trf("field", _FIELD_ROTATION, static_mesh("field/m", "models/naosoccerfield.obj", (2.5, 1, 2.5),
                                                  ("None_rcs-naofield.png",))),
        trf("sky", _FIELD_ROTATION, static_mesh("sky/m", "models/skybox.obj", (10, 10, 10), tuple(
            f"Material_skyrender_000{i}.tif" for i in range(1, 7)))),
        _goal("l"),
        _goal("r"),
    ]
    for i, (x, y, size) in enumerate(((-24.99, 0, (1, 51, 1)), (24.99, 0, (1, 51, 1)), (0, 25, (50.98, 1, 1)),
                                      (0, -25, (50.98, 1, 1)))):
        nodes.append(trf(f"wall{i}", translation(x, y, 0), smn(f"wall{i}/m", "StdUnitBox", size, "matGrey")))
    for i, (x, y) in enumerate(((-15, 10), (-15, -10), (15, 10), (15, -10))):
        nodes.append(trf(f"flag{i}", translation(x, y, 0)))
    nodes.extend(trf(f"line{i}", IDENTITY) for i in range(21))
    return nodes


def ball_node(matrix: Matrix) -> Node:
    return trf("ball", matrix, static_mesh("ball/m", "models/soccerball.obj", (0.042, 0.042, 0.042),
                                           ("soccerball_rcs-soccerball.png",)))


def robot_body_order(robot_type: int) -> list[str]:
    """SimSpark body names of one robot in scene order."""
    names = ["torso", "neck", "head"]
    for side in "rl":
        names.extend(side + part for part in ARM_BODIES)
    for side in "rl":
        names.extend(side + part for part in LEG_BODIES)
        if robot_type == 4:
            names.append(side + "toe")
    return names


def robot_node(side: str | None, unum: int, robot_type: int, bodies: Mapping[str, Matrix],
               foot_length_ratio: float = 1.0, toe_scale: tuple[float, float, float] | None = None) -> Node:
    """One robot: an identity transform holding a transform per body with the server's meshes.

    Args:
        side: "left"/"right" (None before init: materials keep their unrenamed names).
        unum, robot_type: uniform number and robot type (mesh and material names).
        bodies: world transform of each body (missing bodies are drawn at the identity).
        foot_length_ratio / toe_scale: type-4 foot mesh y scale and toe mesh scale (nao_hetero.rsg).
    """
    team = {"left": "matLeft", "right": "matRight"}.get(side or "", "matTeam")
    num = f"matNum{unum}" if side else "matNum"
    kind = f"matType{robot_type}"
    key = f"robot/{side}/{unum}"
    children: list[Node] = []
    for name in robot_body_order(robot_type):
        matrix = bodies.get(name, IDENTITY)
        k = f"{key}/{name}"
        part = name[1:] if name[0] in "rl" and name not in ("neck",) else name
        if name == "torso":
            node = trf(k, matrix,
                       trf(k + "/mesh", _NAO_MESH_ROTATION, static_mesh(k + "/mesh/m", f"models/naobody{robot_type}.obj",
                                                                      (0.1, 0.1, 0.1), (num, team, kind, "naowhite"))),
                       trf(k + "/select", IDENTITY, smn(k + "/select/m", "StdUnitCylinder 1 1", (0.2, 0.2, 0.02),
                                                        "matSelect", visible=False, transparent=True)))
        elif name == "neck":
            node = trf(k, matrix, smn(k + "/m", "StdCapsule 0.015 0.08", (1, 1, 1), "matDarkGrey"))
        elif name == "head":
            node = trf(k, matrix, trf(k + "/mesh", _NAO_MESH_ROTATION, static_mesh(
                k + "/mesh/m", "models/naohead.obj", (0.1, 0.1, 0.1), (team, "naoblack", "naogrey", "naowhite"))))
        elif part in ("shoulder", "elbow", "hip1", "hip2"):
            node = trf(k, matrix, smn(k + "/m", "StdUnitSphere", (0.01, 0.01, 0.01), "matYellow"))
        elif part == "ankle":
            node = trf(k, matrix, smn(k + "/m", "StdUnitSphere", (0.01, 0.01, 0.01), "matRed"))
        elif part == "upperarm":
            node = trf(k, matrix, static_mesh(k + "/m", f"models/{name}{robot_type}.obj", (0.07, 0.07, 0.07),
                                              (team, kind, "naowhite")))
        elif part == "lowerarm":
            node = trf(k, matrix, static_mesh(k + "/m", f"models/{name}.obj", (0.05, 0.05, 0.05), (team, "naowhite")))
        elif part == "thigh":
            materials = (num, team, "naowhite") if name == "rthigh" else (team, "naowhite")
            node = trf(k, matrix, static_mesh(k + "/m", f"models/{name}.obj", (0.07, 0.07, 0.07), materials))
        elif part == "shank":
            node = trf(k, matrix, static_mesh(k + "/m", f"models/{name}{robot_type}.obj", (0.08, 0.08, 0.08),
                                              (team, kind, "naowhite")))
        elif part == "foot":
            node = trf(k, matrix, static_mesh(k + "/m", f"models/{name}.obj", (0.08, 0.08 * foot_length_ratio, 0.08),
                                              (team, "naowhite")))
        else:  # toe (type 4): the foot mesh squeezed to the toe box
            node = trf(k, matrix, static_mesh(k + "/m", f"models/{name[0]}foot.obj", toe_scale or (0.08, 0.08, 0.08),
                                              (team, "naowhite")))
        children.append(node)
    return trf(key, IDENTITY, *children)


class SceneWriter:
    """Writes a node tree as a full scene or as a diff against what this writer sent before.

    One writer per consumer (a log file, a monitor connection): the diff depends on what it has sent.

    Args:
        decimals: places of the rotation and the translation numbers of a transform (None: the server's
            float32 ``%g``, byte for byte). What a reader holds after a diff is within ``TRANSFORM_PRECISION``
            plus half a last place of the truth.
    """

    def __init__(self, decimals: Decimals = None) -> None:
        self.decimals = decimals
        self._sent: dict[str, Matrix] = {}
        self._first_diff = False

    def full(self, nodes: list[Node]) -> str:
        self._sent.clear()
        out: list[str] = []
        for node in nodes:
            self._write(node, out, full=True)
        self._first_diff = True
        return "(" + "".join(out) + ")"

    def diff(self, nodes: list[Node]) -> str:
        out: list[str] = []
        for node in nodes:
            self._write(node, out, full=False)
        # The server repeats (setVisible v) only in the first diff after a full state (measured).
        self._first_diff = False
        return "(" + "".join(out) + ")"

    def _send(self, key: str, matrix: Matrix) -> str:
        """The transform's text; remembers the values a reader gets from it (what later diffs compare with)."""
        if self.decimals is None:
            self._sent[key] = quantize(matrix, None)
            return matrix_text(matrix)
        spelled = _spell(matrix, self.decimals)
        self._sent[key] = tuple(map(float, spelled))
        return "(SLT " + " ".join(spelled) + ")"

    def _write(self, node: Node, out: list[str], full: bool) -> None:
        if node.kind == "TRF":
            out.append("(nd TRF " if full else "(nd")
            assert node.matrix is not None
            if full:
                out.append(self._send(node.key, node.matrix))
            else:
                old = self._sent.get(node.key)
                # any(|a - b| > TRANSFORM_PRECISION) over the 16 elements, as map chains (no Python frame each)
                if old is None or any(map(_MOVED, map(abs, map(sub, old, node.matrix)))):
                    out.append(" " + self._send(node.key, node.matrix))
        elif node.kind == "Light":
            out.append("(nd Light" + node.body if full else "(nd")
        else:
            out.append(f"(nd {node.kind}")
            if full or self._first_diff:
                out.append(f" (setVisible {1 if node.visible else 0})")
            if full:
                if node.transparent:
                    out.append(" (setTransparent)")
                out.append(node.body)
        for child in node.children:
            self._write(child, out, full)
        out.append(")")
