"""Stand-up generator: ``standup_front`` and ``standup_back``, from lying to the walk stance, as XML phases.

A stand-up is four parts, each keyframe symmetric (the right side mirrors the left):

0. **Ready** (optional, ``ready_ms`` > 0): every joint to the walk stance's angles while still lying
   (stretched by the controller's blending when the fall left the joints far away), so that what follows
   starts from one known lying configuration whatever pose the fall ended in.
1. **Ground phases** (``[[<motion>.ground]]`` in the parameter file): joint-space keyframes while the torso
   still lies; they push the torso up with the arms and bring the feet under it. Each one's meaning is
   checked with forward kinematics (``kinematics.fk.NaoKinematics``) in the lying torso's frame: how far
   the hand tips, shank centres and soles reach below the torso face on the ground (a limb reaching below it props
   the torso up by that much) is written into the file's header.
2. **Crouch**: feet flat under the body, the torso leaning ``crouch_pitch_deg`` forward with its centre at
   ``crouch_height_m``, the whole-body CoM ``crouch_com_forward_m`` ahead of the sole centres, i.e. inside
   the support polygon of the two feet. Solved with the sagittal IK below.
3. **Rise**: one keyframe halfway (height and lean) between the crouch and the walk stance, CoM again over
   the soles, then the walk stance itself (``[stand]`` of ``motions/params/gait.toml``, the walk's own, via
   ``motions.authoring.gait.stance_pose``); the last phase sets ``in_walk_position``, the first clears it.

Sagittal IK: with hip yaw, hip roll and ankle roll at zero the legs move in the sagittal plane, so a flat
foot at a given place under a torso of given lean is three equations in hip pitch, knee and ankle pitch,
solved by damped Gauss-Newton on Pinocchio forward kinematics; the torso then moves fore and aft (the
sole target relative to the torso) until the CoM lies over its target (fixed point, < 0.1 mm).

Parameters live in ``motions/params/standup.toml`` (one section per motion; tuned on our simulator by
``python -m motion_studio.tune_standup``). Run ``python -m motions.authoring.standup`` to write
``standup_front.xml``, ``standup_back.xml``, ``roll_to_back.xml`` (a robot lying on its side rolls onto its
back first) and ``lie_flat.xml`` (a robot on its back lies straight first) into ``motions/files/``.
"""

from __future__ import annotations

import argparse
import math
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, fields, replace
from pathlib import Path

import numpy as np

from kinematics.fk import NaoKinematics, torso_rotation
from motions.authoring.common import (ARMS, FILES_DIR, LEGS, PARAMS_DIR, KeyframeSolver, header, targets_deg,
                                      write_xml_motions)
from motions.authoring.gait import STANCE_FLAG, GaitParams, stance_pose
from motions.authoring.gait_params import GAIT_PARAMS_PATH, load_gait_params
from motions.authoring.toml_text import toml_value
from motions.model import BLEND_SPEED_CONSTANT, XML, Keyframe, Motion

PARAMS_PATH = PARAMS_DIR / "standup.toml"
#: The stand-ups: motion name = section name; the side the robot lies on.
STANDUPS: dict[str, str] = {"standup_front": "front", "standup_back": "back"}
#: Motions made of ground phases only (same section layout, crouch keys unused): a robot lying on its side
#: rolls onto its back with the arms spread while the hips and knees bend (one keyframe; measured on both servers
#: from both sides, see the section's provenance); a robot lying on its back lays
#: its legs and arms straight before its stand-up (lie_flat).
ROLLS: dict[str, str] = {"roll_to_back": "side", "lie_flat": "back"}
#: Section of the gait file that holds the walk stance.
STANCE_SECTION = "stand"
#: Keys of a section that record results, not parameters.
META_KEYS = ("provenance", "measured")
#: Sagittal IK: joint limits used (left leg, SimSpark degrees, 0.5 deg inside the spec's), iterations.
LEG_LIMITS_DEG = {"hip": (-24.5, 99.5), "knee": (-129.5, 0.5), "ankle": (-44.5, 74.5)}
IK_ITERATIONS = 60
IK_TOLERANCE = 1e-6
COM_ITERATIONS = 30
COM_TOLERANCE_M = 1e-4
#: Bodies whose reach below the lying torso's ground face is reported for the ground phases.
PROP_POINTS = {"hands": ("lhand", "rhand"), "shanks": ("lshank", "rshank"), "soles": ("lsole", "rsole")}
TORSO_HALF_DEPTH_M = 0.05  # torso box 0.10 deep (REFERENCE §2.1)
SOLE_HALF_THICKNESS_M = 0.01  # foot box 0.02 thick; the sole site is the box centre
#: A ground keyframe whose soles can lie within this of flat counts as standing on its feet [deg].
FLAT_TOLERANCE_DEG = 5.0
#: Ground keyframes with the knees bent more than this are checked as squats on flat feet [deg].
SQUAT_KNEE_DEG = 45.0
#: Bodies that must stay off the ground when the robot squats on its feet.
CLEARANCE_BODIES = ("torso", "lthigh", "rthigh", "lshank", "rshank")


@dataclass(frozen=True)
class GroundPose:
    """One ground-phase keyframe: left-side joint angles [deg, SimSpark signs]; the right side mirrors them
    (rolls and elbow yaw negated, as ``motions.authoring.common.ArmPose``)."""

    name: str
    duration_ms: int
    hip_yaw_pitch_deg: float = 0.0
    hip_roll_deg: float = 0.0
    hip_pitch_deg: float = 0.0
    knee_deg: float = 0.0
    ankle_pitch_deg: float = 0.0
    ankle_roll_deg: float = 0.0
    shoulder_pitch_deg: float = -90.0
    shoulder_roll_deg: float = 8.0
    elbow_yaw_deg: float = 0.0
    """+ turns the forearm's bending plane (ArmPose sign: left laj3 = -value)."""
    elbow_roll_deg: float = 0.0
    """+ bends the elbow (ArmPose sign: left laj4 = -value)."""

    def angles_rad(self) -> dict[str, float]:
        """Wire name -> angle [rad] of all legs and arms joints."""
        return symmetric_angles_rad(self.hip_yaw_pitch_deg, self.hip_roll_deg, self.hip_pitch_deg, self.knee_deg,
                                    self.ankle_pitch_deg, self.ankle_roll_deg, self.shoulder_pitch_deg,
                                    self.shoulder_roll_deg, self.elbow_yaw_deg, self.elbow_roll_deg)


@dataclass(frozen=True)
class StandUpParams:
    """Parameters of one stand-up (units in the names; angles SimSpark-signed, left side)."""

    ground: tuple[GroundPose, ...] = ()
    """Ground-phase keyframes, in order."""
    ready_ms: int = 200
    """Duration of the first keyframe, the walk stance's joint angles while lying [ms]; 0 = no such keyframe
    (the first ground phase starts at once)."""
    crouch_pitch_deg: float = 30.0
    """Torso lean forward in the crouch [deg]."""
    crouch_height_m: float = 0.27
    """Torso centre above the ground in the crouch [m]."""
    crouch_com_forward_m: float = 0.02
    """CoM ahead of the sole centres in the crouch [m] (the feet reach 0.08 either way)."""
    crouch_shoulder_pitch_deg: float = -60.0
    """Arms in the crouch (forward arms move the CoM forward) [deg]."""
    crouch_ms: int = 300
    """Duration of the move into the crouch [ms]."""
    rise_com_forward_m: float = 0.01
    """CoM ahead of the sole centres in the halfway rise keyframe [m]."""
    rise_ms: int = 300
    """Duration of the halfway rise keyframe [ms]."""
    stance_ms: int = 300
    """Duration of the move into the walk stance [ms]."""
    blend_speed_rad_s: float = 0.0
    """Joint speed bound of the move into the first keyframe [rad/s], written as the motion's constant of that
    name (``agent.motion.controller``: the first keyframe lasts at least as long as its largest joint move takes
    at this speed); 0 = no constant, the controller's own bound (3 rad/s, meant for walks and kicks started from
    anywhere). Why stand-ups set it: a robot that lies still can move its limbs at full speed without a jolt, and
    at 3 rad/s the first ground phase of the back stand-up (the arms from the sides to -114 deg) took 0.66 s
    instead of its 0.27."""


def symmetric_angles_rad(hip_yaw_pitch_deg: float = 0.0, hip_roll_deg: float = 0.0, hip_pitch_deg: float = 0.0,
                         knee_deg: float = 0.0, ankle_pitch_deg: float = 0.0, ankle_roll_deg: float = 0.0,
                         shoulder_pitch_deg: float = -90.0, shoulder_roll_deg: float = 8.0,
                         elbow_yaw_deg: float = 0.0, elbow_roll_deg: float = 0.0) -> dict[str, float]:
    """Both legs and arms from left-side values [deg]: wire name -> angle [rad].

    Mirroring (REFERENCE §2.2 limits): hip yaw-pitch, pitches and knees are equal on both sides; hip roll,
    ankle roll and shoulder roll are negated on the right; elbow yaw and roll follow ArmPose (left negated).
    """
    deg = {
        "llj1": hip_yaw_pitch_deg, "rlj1": hip_yaw_pitch_deg,
        "llj2": hip_roll_deg, "rlj2": -hip_roll_deg,
        "llj3": hip_pitch_deg, "rlj3": hip_pitch_deg,
        "llj4": knee_deg, "rlj4": knee_deg,
        "llj5": ankle_pitch_deg, "rlj5": ankle_pitch_deg,
        "llj6": ankle_roll_deg, "rlj6": -ankle_roll_deg,
        "laj1": shoulder_pitch_deg, "raj1": shoulder_pitch_deg,
        "laj2": shoulder_roll_deg, "raj2": -shoulder_roll_deg,
        "laj3": -elbow_yaw_deg, "raj3": elbow_yaw_deg,
        "laj4": -elbow_roll_deg, "raj4": elbow_roll_deg,
    }
    return {name: math.radians(value) for name, value in deg.items()}


# ---- sagittal IK --------------------------------------------------------------------------------------
class SagittalSolver:
    """Crouch and rise keyframes: flat feet under a leaning torso with the CoM over the soles (see the
    module docstring).

    Args:
        robot_type: 0-4.
    """

    def __init__(self, robot_type: int = 0) -> None:
        self.kinematics = NaoKinematics(robot_type)

    def _angles(self, leg_deg: np.ndarray, arms_rad: Mapping[str, float]) -> dict[str, float]:
        hip, knee, ankle = (float(v) for v in leg_deg)
        angles = symmetric_angles_rad(hip_pitch_deg=hip, knee_deg=knee, ankle_pitch_deg=ankle)
        angles.update(arms_rad)
        return angles

    def _residual(self, leg_deg: np.ndarray, rotation: np.ndarray, sole_forward_m: float, height_m: float,
                  arms_rad: Mapping[str, float]) -> np.ndarray:
        sole = self.kinematics.frame_pose("lsole", self._angles(leg_deg, arms_rad))
        position = rotation @ sole.position_m
        sole_rotation = rotation @ sole.rotation
        foot_pitch = math.atan2(sole_rotation[2, 1], sole_rotation[1, 1])
        return np.array([position[1] - sole_forward_m, position[2] + height_m, foot_pitch])

    def legs(self, pitch_deg: float, height_m: float, sole_forward_m: float, arms_rad: Mapping[str, float],
             start_deg: Sequence[float] = (60.0, -100.0, 40.0)) -> tuple[np.ndarray, float]:
        """Hip pitch, knee, ankle pitch [deg] putting the flat sole ``sole_forward_m`` ahead of and
        ``height_m`` below the torso centre (gravity frame, torso leaning ``pitch_deg``); and the residual."""
        rotation = torso_rotation(math.radians(pitch_deg))
        low = np.array([LEG_LIMITS_DEG[k][0] for k in ("hip", "knee", "ankle")])
        high = np.array([LEG_LIMITS_DEG[k][1] for k in ("hip", "knee", "ankle")])
        q = np.clip(np.array(start_deg, dtype=float), low, high)
        residual = self._residual(q, rotation, sole_forward_m, height_m, arms_rad)
        for _ in range(IK_ITERATIONS):
            if float(np.abs(residual).max()) < IK_TOLERANCE:
                break
            jacobian = np.zeros((3, 3))
            for i in range(3):
                step = np.zeros(3)
                step[i] = 1e-3
                jacobian[:, i] = (self._residual(q + step, rotation, sole_forward_m, height_m, arms_rad) - residual) / 1e-3
            delta = np.linalg.solve(jacobian.T @ jacobian + 1e-9 * np.eye(3), -jacobian.T @ residual)
            q = np.clip(q + np.clip(delta, -10.0, 10.0), low, high)
            residual = self._residual(q, rotation, sole_forward_m, height_m, arms_rad)
        return q, float(np.abs(residual).max())

    def com_over_soles(self, pitch_deg: float, height_m: float, com_forward_m: float,
                       arms_rad: Mapping[str, float]) -> dict[str, float]:
        """The keyframe (wire name -> rad): flat feet, torso centre ``height_m`` up and leaning ``pitch_deg``,
        the CoM ``com_forward_m`` ahead of the sole centres.

        Raises:
            ValueError: no leg pose within the joint limits reaches (the message gives the residual).
        """
        rotation = torso_rotation(math.radians(pitch_deg))
        sole_forward = 0.0
        q = np.array([60.0, -100.0, 40.0])
        residual = math.inf
        for _ in range(COM_ITERATIONS):
            q, residual = self.legs(pitch_deg, height_m, sole_forward, arms_rad, q)
            angles = self._angles(q, arms_rad)
            com = rotation @ (self.kinematics.com(angles) - self.kinematics.frame_pose("lsole", angles).position_m)
            error = com[1] - com_forward_m
            if abs(error) < COM_TOLERANCE_M:
                break
            sole_forward += error  # moving the soles forward moves the CoM back relative to them
        if residual > 1e-4:
            raise ValueError(f"no flat-footed crouch with the torso {height_m:.3f} m up, leaning {pitch_deg:.1f} deg "
                             f"(residual {residual:.4g}; joint limits reached: hip/knee/ankle {np.round(q, 1)} deg)")
        return self._angles(q, arms_rad)

    def com_margin_m(self, angles: Mapping[str, float], pitch_deg: float) -> float:
        """Distance of the CoM's ground projection inside the feet's support polygon [m] (negative outside),
        for a robot standing on flat feet with its torso leaning ``pitch_deg``."""
        rotation = torso_rotation(math.radians(pitch_deg))
        hull = self.kinematics.support_polygon(angles, rotation)
        com = (rotation @ self.kinematics.com(angles))[:2]
        return _inside_distance(hull, com)

    def on_flat_feet(self, angles: Mapping[str, float]) -> tuple[float, float, float] | None:
        """If the soles can both be flat on the ground at some torso lean, (lean [deg], CoM ahead of the
        sole centres [m], lowest point of the torso, thighs and shanks above the ground [m]); else None.

        Used to check squat-like keyframes (e.g. a frog squat with the knees apart) without solving for them.
        """
        best = None
        for pitch_deg in range(-60, 91):
            rotation = torso_rotation(math.radians(pitch_deg))
            tilt = math.acos(max(-1.0, min(1.0, (rotation @ self.kinematics.frame_pose("lsole", angles).rotation)[2, 2])))
            if best is None or tilt < best[0]:
                best = (tilt, pitch_deg)
        if best is None or math.degrees(best[0]) > FLAT_TOLERANCE_DEG:
            return None
        pitch_deg = best[1]
        rotation = torso_rotation(math.radians(pitch_deg))
        sole = rotation @ self.kinematics.frame_pose("lsole", angles).position_m
        com = rotation @ self.kinematics.com(angles)
        ground_z = sole[2] - SOLE_HALF_THICKNESS_M
        lowest = min(float((rotation @ _box_corners(self.kinematics, body, angles))[2].min())
                     for body in CLEARANCE_BODIES)
        return float(pitch_deg), float(com[1] - sole[1]), lowest - ground_z

    def prop_depths_m(self, angles: Mapping[str, float], side: str) -> dict[str, float]:
        """How far each limb group reaches below the face the torso lies on [m] (+ = it props the torso up).

        Lying on the front the chest (torso +y face) is on the ground, on the back the back (-y face).
        """
        down = np.array([0.0, 1.0, 0.0]) if side == "front" else np.array([0.0, -1.0, 0.0])
        depths = {}
        for group, frames in PROP_POINTS.items():
            reach = max(float(down @ self.kinematics.frame_pose(frame, angles).position_m) for frame in frames)
            depths[group] = round(reach - TORSO_HALF_DEPTH_M, 3)
        return depths


def _box_corners(kinematics: NaoKinematics, body: str, angles: Mapping[str, float]) -> np.ndarray:
    """The 8 corners of a body's box in the torso frame, 3 x 8 [m]."""
    sx, sy, sz = kinematics.spec.body(body).shape.size
    pose = kinematics.frame_pose(body, angles)
    corners = np.array([[x * sx / 2, y * sy / 2, z * sz / 2] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]).T
    return pose.rotation @ corners + pose.position_m[:, None]


def _inside_distance(hull: np.ndarray, point: np.ndarray) -> float:
    """Signed distance of a point inside a counter-clockwise convex polygon (k x 2) [m]."""
    if len(hull) < 3:
        return -math.inf
    distances = []
    for a, b in zip(hull, np.roll(hull, -1, axis=0)):
        edge = b - a
        normal = np.array([-edge[1], edge[0]]) / np.linalg.norm(edge)  # inward for counter-clockwise
        distances.append(float(normal @ (point - a)))
    return min(distances)


# ---- parameters ---------------------------------------------------------------------------------------
def parse_standup_params(text: str, path: str = "<string>") -> dict[str, StandUpParams]:
    """Section name -> StandUpParams; ground phases come from the ``[[<section>.ground]]`` tables.

    Raises:
        ValueError: bad TOML, an unknown key or a ground phase without name/duration (names the file and
            section, lists the known keys).
    """
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise ValueError(f"{path}: {error}") from None
    known = {f.name for f in fields(StandUpParams)}
    pose_known = {f.name for f in fields(GroundPose)}
    out = {}
    for section, table in data.items():
        where = f"{path} [{section}]"
        unknown = set(table) - known - set(META_KEYS)
        if unknown:
            raise ValueError(f"{where}: unknown keys {sorted(unknown)}; known: {', '.join(sorted(known))}")
        values = {k: v for k, v in table.items() if k not in META_KEYS and k != "ground"}
        ground = []
        for index, pose in enumerate(table.get("ground", [])):
            bad = set(pose) - pose_known
            if bad:
                raise ValueError(f"{where} ground[{index}]: unknown keys {sorted(bad)}; known: "
                                 f"{', '.join(sorted(pose_known))}")
            if "name" not in pose or "duration_ms" not in pose:
                raise ValueError(f"{where} ground[{index}]: needs 'name' and 'duration_ms'")
            ground.append(GroundPose(**pose))
        out[section] = StandUpParams(ground=tuple(ground), **values)
    return out


def load_standup_params(path: Path = PARAMS_PATH) -> dict[str, StandUpParams]:
    """Read a stand-up parameter file; see :func:`parse_standup_params`."""
    return parse_standup_params(Path(path).read_text(encoding="utf-8"), str(path))


def _toml_number(value: object) -> str:
    """A TOML literal (``toml_text.toml_value``) with floats at 4 decimals, as the stand-up file keeps them."""
    if isinstance(value, float):
        return toml_value(round(value, 4))
    return toml_value(value if isinstance(value, (bool, int, str)) else str(value))


def dumps_section(name: str, params: StandUpParams, meta: Mapping[str, str] | None = None) -> str:
    """TOML text of one section (meta keys first, then the parameters, then its ground tables)."""
    lines = [f"[{name}]"]
    for key, value in (meta or {}).items():
        lines.append(f"{key} = {_toml_number(value)}")
    for f in fields(StandUpParams):
        if f.name != "ground":
            lines.append(f"{f.name} = {_toml_number(getattr(params, f.name))}")
    for pose in params.ground:
        lines.append("")
        lines.append(f"[[{name}.ground]]")
        for f in fields(GroundPose):
            lines.append(f"{f.name} = {_toml_number(getattr(pose, f.name))}")
    return "\n".join(lines) + "\n"


def read_meta(path: Path, section: str) -> dict[str, str]:
    """The meta keys (provenance, measured) of one section ({} if none)."""
    data = tomllib.loads(Path(path).read_text(encoding="utf-8"))
    return {k: str(v) for k, v in data.get(section, {}).items() if k in META_KEYS}


def meta_comments(path: Path, section: str) -> tuple[str, ...]:
    """A section's meta keys as XML comment lines (``--`` may not appear inside an XML comment)."""
    return tuple(f" {key}: {value} ".replace("--", "- -") for key, value in read_meta(path, section).items())


def ground_phases_comment(params: StandUpParams) -> str:
    """A roll's header line: its ground phases and their durations (the angles are in the parameter file)."""
    return (" Ground phases only (left side, right mirrored): "
            + "; ".join(f"{g.name} {g.duration_ms} ms" for g in params.ground) + " ")


def stance_params(gait_path: Path = GAIT_PARAMS_PATH) -> GaitParams:
    """The walk stance: ``[stand]`` of the gait parameter file.

    Raises:
        ValueError: the file has no ``[stand]`` section.
    """
    sections = load_gait_params(gait_path)
    if STANCE_SECTION not in sections:
        raise ValueError(f"{gait_path}: no section [{STANCE_SECTION}] (the walk stance); known: "
                         f"{', '.join(sorted(sections))}")
    return sections[STANCE_SECTION]


# ---- motion -------------------------------------------------------------------------------------------
@dataclass
class KeyPose:
    """One keyframe as built, with what kinematics says about it (for the header and the tests)."""

    name: str
    duration_ms: int
    angles_rad: dict[str, float]
    note: str = ""
    com_margin_m: float | None = None
    prop_depths_m: dict[str, float] = field(default_factory=dict)
    squat: tuple[float, float, float] | None = None
    """For a ground keyframe that can stand on flat feet: (torso lean [deg], CoM ahead of the soles [m],
    body clearance [m]); see ``SagittalSolver.on_flat_feet``."""


def key_poses(params: StandUpParams, side: str, stance: GaitParams, solver: SagittalSolver | None = None,
              stance_solver: KeyframeSolver | None = None) -> list[KeyPose]:
    """Every keyframe of a stand-up (see the module docstring), with its kinematic notes.

    Raises:
        ValueError: a crouch or rise pose out of reach.
    """
    solver = solver or SagittalSolver()
    stance_solver = stance_solver or KeyframeSolver()
    stance_solver.ik.reset()
    stand = stance_pose(stance, stance_solver)
    poses = []
    if params.ready_ms > 0:
        depths = solver.prop_depths_m(stand, side)
        poses.append(KeyPose("ready", params.ready_ms, stand, "the walk stance's joint angles, lying: " + ", ".join(
            f"{group} {depth:+.3f} m" for group, depth in depths.items()), prop_depths_m=depths))
    for ground in params.ground:
        angles = ground.angles_rad()
        depths = solver.prop_depths_m(angles, side)
        note = "reach below the torso face: " + ", ".join(f"{group} {depth:+.3f} m" for group, depth in depths.items())
        squat = solver.on_flat_feet(angles) if ground.knee_deg < -SQUAT_KNEE_DEG else None
        if squat is not None:
            lean, com_forward, clearance = squat
            note += (f"; on flat feet at a {lean:.0f} deg lean the CoM is {com_forward * 1000:+.0f} mm ahead of the "
                     f"soles, the body {clearance * 1000:.0f} mm above the ground")
        poses.append(KeyPose(ground.name, ground.duration_ms, angles, note, prop_depths_m=depths, squat=squat))
    crouch_arms = {k: v for k, v in symmetric_angles_rad(shoulder_pitch_deg=params.crouch_shoulder_pitch_deg,
                                                          shoulder_roll_deg=stance.arm.shoulder_roll_deg).items()
                   if k in ARMS}
    crouch = solver.com_over_soles(params.crouch_pitch_deg, params.crouch_height_m, params.crouch_com_forward_m,
                                   crouch_arms)
    stance_arms = {k: v for k, v in stand.items() if k in ARMS}
    rise_pitch = (params.crouch_pitch_deg + stance.torso_pitch_deg) / 2.0
    rise_height = (params.crouch_height_m + stance.torso_height_m) / 2.0
    rise = solver.com_over_soles(rise_pitch, rise_height, params.rise_com_forward_m, stance_arms)
    for name, duration, angles, pitch, text in (
            ("crouch", params.crouch_ms, crouch, params.crouch_pitch_deg,
             f"feet flat, torso {params.crouch_height_m:.3f} m up leaning {params.crouch_pitch_deg:.1f} deg, "
             f"CoM {params.crouch_com_forward_m:+.3f} m ahead of the soles"),
            ("rise", params.rise_ms, rise, rise_pitch,
             f"halfway: torso {rise_height:.3f} m up leaning {rise_pitch:.1f} deg, CoM "
             f"{params.rise_com_forward_m:+.3f} m ahead of the soles"),
            ("stance", params.stance_ms, stand, stance.torso_pitch_deg, "the walk stance ([stand] of gait.toml)")):
        margin = solver.com_margin_m(angles, pitch)
        poses.append(KeyPose(name, duration, angles, f"{text}; CoM {margin * 1000:.0f} mm inside the support polygon",
                             com_margin_m=margin))
    return poses


def _phase(pose: KeyPose, **attributes: object) -> Keyframe:
    if pose.duration_ms < 20:
        raise ValueError(f"phase {pose.name!r}: duration {pose.duration_ms} ms is shorter than one 20 ms cycle")
    return Keyframe(pose.name, pose.duration_ms / 1000.0, targets_deg(pose.angles_rad, LEGS + ARMS),
                    **attributes)  # type: ignore[arg-type]


def blend_constants(params: StandUpParams) -> dict[str, float]:
    """The motion constants of a stand-up or roll: its blend speed when the section sets one."""
    return {BLEND_SPEED_CONSTANT: float(params.blend_speed_rad_s)} if params.blend_speed_rad_s > 0 else {}


def build_standup(name: str, params: StandUpParams, side: str, stance: GaitParams,
                  header_comments: tuple[str, ...] = (), solver: SagittalSolver | None = None,
                  poses: Sequence[KeyPose] | None = None) -> Motion:
    """The XML phase motion of one stand-up: ground phases, crouch, rise, stance (``in_walk_position``).

    ``poses``: the keyframes from :func:`key_poses` when the caller has them already (for its header), so
    the IK is not solved twice.

    Raises:
        ValueError: a pose out of reach or a phase shorter than one cycle.
    """
    if poses is None:
        poses = key_poses(params, side, stance, solver)
    phases = []
    for index, pose in enumerate(poses):
        last = index == len(poses) - 1
        phases.append(_phase(pose, next=None if last else poses[index + 1].name,
                             set_flag_false=STANCE_FLAG if index == 0 else None,
                             set_flag_true=STANCE_FLAG if last else None, is_final=True if last else None))
    return Motion(name, phases, source_format=XML, first_phase=poses[0].name, header_comments=header_comments,
                  constants=blend_constants(params))


def build_roll(name: str, params: StandUpParams, header_comments: tuple[str, ...] = ()) -> Motion:
    """A motion of ground phases only, played once (e.g. ``roll_to_back``).

    Raises:
        ValueError: no ground phases, or a phase shorter than one cycle.
    """
    if not params.ground:
        raise ValueError(f"{name}: needs at least one ground phase")
    poses = [KeyPose(g.name, g.duration_ms, g.angles_rad()) for g in params.ground]
    phases = [_phase(pose, next=None if i == len(poses) - 1 else poses[i + 1].name,
                     is_final=True if i == len(poses) - 1 else None) for i, pose in enumerate(poses)]
    return Motion(name, phases, source_format=XML, first_phase=poses[0].name, header_comments=header_comments,
                  constants=blend_constants(params))


def describe(poses: Sequence[KeyPose]) -> tuple[str, ...]:
    """Header lines: each keyframe with its duration and its kinematic note."""
    return tuple(f" {pose.name} ({pose.duration_ms} ms): {pose.note} " for pose in poses)


def section_params(sections: Mapping[str, StandUpParams], path: Path, name: str) -> StandUpParams:
    """Section ``name`` of the parameter file ``path`` (already read into ``sections``).

    Raises:
        ValueError: no such section (the message lists the known ones).
    """
    if name not in sections:
        raise ValueError(f"{path}: no section [{name}]; known: {', '.join(sorted(sections))}")
    return sections[name]


def build_all(path: Path = PARAMS_PATH, gait_path: Path = GAIT_PARAMS_PATH) -> dict[str, Motion]:
    """Both stand-ups: motion name -> Motion (with header comments)."""
    sections = load_standup_params(path)
    stance = stance_params(gait_path)
    solver = SagittalSolver()
    command = "python -m motions.authoring.standup"
    out = {}
    for name, side in STANDUPS.items():
        params = section_params(sections, path, name)
        flat = replace(params, ground=())
        comments = header("motions.authoring.standup", path, name, flat, command)
        comments = tuple(c.replace("IK with kinematics.ik.WholeBodyIK", "sagittal IK on kinematics.fk.NaoKinematics, stance by kinematics.ik.WholeBodyIK")
                         for c in comments)
        poses = key_poses(params, side, stance, solver)
        comments += (f" Lying on the {side}. Keyframes (ground phases in joint space, left side, right mirrored): ",)
        comments += describe(poses)
        comments += meta_comments(path, name)
        out[name] = build_standup(name, params, side, stance, comments, solver, poses)
    for name in ROLLS:
        params = section_params(sections, path, name)
        comments = tuple(c.replace("sagittal IK on kinematics.fk.NaoKinematics, stance by kinematics.ik.WholeBodyIK",
                                   "joint-space keyframes") for c in
                         header("motions.authoring.standup", path, name, replace(params, ground=()), command))
        comments += (ground_phases_comment(params),)
        comments += meta_comments(path, name)
        out[name] = build_roll(name, params, comments)
    return out


def write_all(out_dir: Path = FILES_DIR, path: Path = PARAMS_PATH, gait_path: Path = GAIT_PARAMS_PATH) -> list[Path]:
    """Generate and write both stand-up files; returns the paths written."""
    return write_xml_motions(build_all(path, gait_path), out_dir)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--params", type=Path, default=PARAMS_PATH, help="stand-up parameter file (TOML)")
    parser.add_argument("--gait-params", type=Path, default=GAIT_PARAMS_PATH, help="gait parameter file ([stand])")
    parser.add_argument("--out", type=Path, default=FILES_DIR, help="folder for the motion files")
    args = parser.parse_args(argv)
    for target in write_all(args.out, args.params, args.gait_params):
        print(f"wrote {target}")


if __name__ == "__main__":
    main()


__all__ = ["GroundPose", "KeyPose", "ROLLS", "SagittalSolver", "StandUpParams", "STANDUPS", "blend_constants",
           "build_all", "build_roll", "build_standup", "dumps_section", "ground_phases_comment", "key_poses",
           "load_standup_params", "meta_comments", "parse_standup_params", "stance_params", "symmetric_angles_rad",
           "write_all"]
