"""Kick generator: a standing kick (right foot; mirrored for the left) solved keyframe by keyframe with IK.

The kick, phase by phase (one keyframe each, all solved with ``kinematics.ik.WholeBodyIK``):

1. ``stance``: the walk stance (``motions.authoring.gait.stance_pose`` of ``[stand]`` in
   ``motions/params/gait.toml``, the walk's own; skipped while ``in_walk_position`` is set, so a kick
   straight after a walk or a ``stand`` starts at once).
2. ``shift``: both feet down, the torso moves sideways until the whole-body CoM lies over the support
   (left) sole, ``com_inset_m`` toward the inside and ``com_forward_m`` ahead of its centre.
3. ``lift``: the kicking foot leaves the ground and moves to ``kick_foot_x_m`` beside the support sole
   (under the hip, closer to the ball's line); the CoM stays over the support sole (every keyframe from
   here re-solves the torso position for it); the torso is at ``torso_height_m``.
4. ``windup``: the foot draws back and up, toes down (``windup_pitch_deg``), the torso may lean forward.
5. ``swing`` (optional, ``swing_ms`` > 0) / ``strike``: the foot swings forward, through a via point under
   the hip if there is one, then through the ball to ``strike_forward_m``; the phases are shorter than the
   joints can follow, so hip pitch and knee run at their speed limit (6.14 rad/s) through the contact.
6. ``follow``: the strike pose held briefly while the leg decelerates.
7. ``retract`` / ``land``: the foot comes back under the hip and down beside the support foot.
8. ``recover``: the CoM returns to the middle: the walk stance again, ``in_walk_position`` set.

The kick's geometry is given relative to the support sole (so it keeps working when the walk stance
changes): the ball lies ``ball_ahead_m`` ahead of and ``ball_side_m`` beside the support sole's centre. Its
place relative to the robot (ego frame: forward, left of the torso's ground point at the walk stance) is
written as the constants ``ball_forward_m`` / ``ball_left_m``, so the kick skill knows where to stand. Parameters live in ``motions/params/kick.toml`` (one section per motion, each over ``[common]``).

Run ``python -m motions.authoring.kick`` to write kick.xml, kick_strong.xml, kick_left.xml and
kick_strong_left.xml into ``motions/files/``.
"""

from __future__ import annotations

import argparse
import math
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, fields, replace
from pathlib import Path

import numpy as np

from kinematics.errors import IKError
from kinematics.fk import torso_rotation
from kinematics.ik import PoseTarget
from motions.authoring.common import ARMS, FILES_DIR, LEGS, PARAMS_DIR, FootPose, KeyframeSolver, header, targets_deg, write_xml_motions
from motions.authoring.gait import STANCE_FLAG, GaitParams, stance_pose
from motions.authoring.gait_params import GAIT_PARAMS_PATH, load_gait_params
from motions.model import XML, Keyframe, Motion

PARAMS_PATH = PARAMS_DIR / "kick.toml"
#: Motion name (right foot) -> its section in the parameter file; the left-foot versions are mirrors.
KICKS: dict[str, str] = {"kick": "kick", "kick_strong": "kick_strong"}
#: Section shared by the kicks; section of the gait file that holds the walk stance.
COMMON = "common"
STANCE_SECTION = "stand"
#: Keys of a section that record results, not parameters.
META_KEYS = ("provenance", "measured")
LEFT_SUFFIX = "_left"
#: Fixed-point iterations that move the torso until the CoM lies over its target (converges to < 0.1 mm).
COM_ITERATIONS = 12
COM_TOLERANCE_M = 1e-4
#: The torso is a soft task whose place is only a means to put the CoM over the support foot, so it may miss
#: its target by a little (where hip yaw limits or reach bind); the feet (hard tasks) must be met exactly.
TORSO_TOLERANCE_M = 0.005
TORSO_TOLERANCE_DEG = 3.0
FOOT_TOLERANCE_M = 0.001
#: Phases whose kicking-leg targets get the joint offsets (``strike_ankle_offset_deg``, ...) after the IK.
STRIKE_PHASES = ("strike", "follow")
#: Joint-space offsets added to the IK's targets: parameter -> (phases, joint's perceptor name). Each is
#: clamped to the joint's range; all 0 leaves the IK's kick as it is.
JOINT_OFFSETS: dict[str, tuple[tuple[str, ...], str]] = {
    "windup_hip_pitch_offset_deg": (("windup",), "rlj3"),
    "windup_knee_offset_deg": (("windup",), "rlj4"),
    "windup_ankle_offset_deg": (("windup",), "rlj5"),
    "windup_support_yaw_offset_deg": (("windup",), "llj1"),
    "swing_hip_pitch_offset_deg": (("swing",), "rlj3"),
    "swing_knee_offset_deg": (("swing",), "rlj4"),
    "swing_support_hip_pitch_offset_deg": (("swing",), "llj3"),
    "strike_ankle_offset_deg": (STRIKE_PHASES, "rlj5"),
    "strike_hip_offset_deg": (STRIKE_PHASES, "rlj1"),
    "strike_hip_pitch_offset_deg": (STRIKE_PHASES, "rlj3"),
    "strike_knee_offset_deg": (STRIKE_PHASES, "rlj4"),
    "support_hip_pitch_offset_deg": (STRIKE_PHASES, "llj3"),
    "support_knee_offset_deg": (STRIKE_PHASES, "llj4"),
    "support_ankle_offset_deg": (STRIKE_PHASES, "llj5"),
}


@dataclass(frozen=True)
class KickParams:
    """One kick (right foot kicks, left foot supports); ground frame x right, y forward, z up."""

    shift_ms: int = 500
    """Weight shift onto the support foot [ms]."""
    com_inset_m: float = 0.005
    """CoM target inside (toward the kicking side) of the support sole's centre [m]."""
    com_forward_m: float = 0.01
    """CoM target ahead of the support sole's centre [m]."""
    torso_pitch_deg: float = 0.0
    """Torso pitch from the shift to the landing [deg] (+ = forward). Near 0: with a pitched torso the hip
    roll axis is tilted, so shifting sideways needs hip yaw toward the inside, which the Nao's hip yaw-pitch
    joints cannot do (range -90..1 deg); IK then fails beyond about 1.5 cm of shift at the walk's 8 deg."""
    torso_height_m: float = 0.342
    """Torso centre height from the shift to the landing [m] (the walk stance's own height is in
    gait.toml; a higher torso lets the kicking leg swing lower and farther)."""
    shift_torso_roll_deg: float = 0.0
    """Torso roll toward the kicking side while on one foot [deg] (+ = the top leans right)."""
    lift_ms: int = 200
    """Lifting the kicking foot [ms]."""
    lift_height_m: float = 0.03
    """Sole height after the lift (and during the retract) [m]."""
    kick_foot_x_m: float = 0.07
    """Kicking sole centre beside the support sole centre while in the air [m] (the stance has them a foot
    spacing apart; less = closer to the support foot, under the hip)."""
    windup_ms: int = 200
    """Draw-back [ms]."""
    windup_back_m: float = -0.07
    """Kicking sole centre at the windup, ahead of the support sole centre [m] (negative = behind)."""
    windup_height_m: float = 0.05
    """Kicking sole centre height at the windup [m]."""
    windup_pitch_deg: float = -20.0
    """Kicking foot pitch at the windup [deg] (+ = toes up)."""
    windup_yaw_deg: float = -8.0
    """Kicking foot yaw at the windup relative to the torso's twist [deg] (+ = toes to the left): the right
    foot's toes turn out as the leg swings back about its rolled hip, and turning them in would need hip
    yaw beyond its 1 deg limit."""
    windup_torso_yaw_deg: float = 0.0
    """Torso yaw at the windup [deg] (- = twisted toward the kicking side, which pulls its hip back: the
    support leg's hip yaw-pitch can turn the torso that way only); the strike untwists it to
    ``strike_torso_yaw_deg``, so the pelvis rotation adds to the foot's speed. The kicking foot turns with
    the twist (its yaw is ``windup_yaw_deg`` on top): its hip yaw-pitch cannot turn it back in."""
    strike_torso_yaw_deg: float = 0.0
    """Torso yaw from the swing to the follow-through [deg]."""
    windup_torso_pitch_deg: float = 0.0
    """Torso pitch added to the stance pitch from the windup to the follow-through [deg]."""
    strike_torso_pitch_deg: float = 0.0
    """Torso pitch added on top of that at the strike and follow-through [deg] (+ = forward): the support
    hip pitches the torso into the kick during the strike; the kicking hip lies on the same pitch axis,
    so the torso's rotation adds to the kicking thigh's own (the joints are capped at 6.14 rad/s each)."""
    swing_ms: int = 40
    """Swing from the windup to the via point under the hip [ms] (shorter than the joints can follow);
    0 = no via point (the foot goes straight from the windup to the strike pose)."""
    swing_forward_m: float = 0.0
    """Kicking sole centre at the via point, ahead of the support sole centre [m]."""
    swing_height_m: float = 0.035
    """Kicking sole centre height at the via point [m]: the foot passes the ball's lower half level or
    rising, never descending onto it (a foot that pins the ball against the ground stops dead)."""
    swing_pitch_deg: float = 0.0
    """Kicking foot pitch at the via point [deg]."""
    strike_ms: int = 80
    """Strike phase [ms] (shorter than the joints can follow: they run at their speed limit)."""
    strike_forward_m: float = 0.10
    """Kicking sole centre at the end of the strike, ahead of the support sole centre [m]."""
    strike_height_m: float = 0.03
    """Kicking sole centre height at the end of the strike [m]."""
    strike_pitch_deg: float = 0.0
    """Kicking foot pitch at the end of the strike [deg]."""
    strike_yaw_deg: float = 0.0
    """Kicking foot yaw at the end of the strike [deg] (+ = toes to the left)."""
    strike_ankle_offset_deg: float = 0.0
    """Added to the kicking ankle pitch target of the strike and follow-through, after the IK [deg] (+ = toes
    up). The IK holds the foot's pitch in the ground frame, so while hip and knee swing the leg forward the
    ankle turns the toes down just as fast (measured: -6.1 rad/s at the contact, costing 0.3 m/s of toe
    speed and pushing the toe down onto the ball); an offset lets the foot turn with the shank. Measured:
    below about 80 deg the ankle still turns down at its limit through the contact (its target stays far
    off); on the previous kick, offsets of 80-114 deg that stop it there gave 0.7-2.4 m means over 9
    placements with up to 4 falls (heel and sole reach the ground and the ball), so the tuner kept 50."""
    strike_hip_offset_deg: float = 0.0
    """Added to the kicking hip yaw-pitch target of the strike and follow-through, after the IK [deg] (- = the
    leg swings in and forward about the joint's 45 deg axis: 0.2 m/s of toe speed per rad/s at the contact)."""
    windup_hip_pitch_offset_deg: float = 0.0
    """Added to the kicking hip pitch target of the windup, after the IK [deg] (- = the thigh further back):
    joint-space offsets reach leg poses the foot-pose IK clamps away (a thigh drawn far back with the knee
    folded gives the swing a longer arc at the joints' 6.14 rad/s cap)."""
    windup_knee_offset_deg: float = 0.0
    """Added to the kicking knee target of the windup [deg] (- = more bent, the heel up behind)."""
    windup_ankle_offset_deg: float = 0.0
    """Added to the kicking ankle pitch target of the windup [deg] (+ = toes up)."""
    windup_support_yaw_offset_deg: float = 0.0
    """Added to the support hip yaw-pitch target of the windup [deg] (- = the pelvis twisted further toward
    the kicking side): the untwist during the strike turns the pelvis, and the kicking leg with it, about the
    support hip's 45 deg axis at the joint's speed cap, adding to the kicking foot's speed."""
    swing_hip_pitch_offset_deg: float = 0.0
    """Added to the kicking hip pitch target of the swing (the via point) [deg] (+ = the thigh further
    forward): with ``swing_knee_offset_deg`` the thigh can lead while the shank stays folded, and the knee
    snaps straight in the strike (the shank then turns at the hip's and the knee's speed caps together)."""
    swing_knee_offset_deg: float = 0.0
    """Added to the kicking knee target of the swing [deg] (- = more bent)."""
    swing_support_hip_pitch_offset_deg: float = 0.0
    """Added to the support hip pitch target of the swing [deg] (- = the torso starts leaning back before the
    strike, so the support hip's extension runs at its cap through the contact)."""
    strike_hip_pitch_offset_deg: float = 0.0
    """Added to the kicking hip pitch target of the strike and follow-through [deg] (+ = the thigh further
    forward and up: the joint keeps running at its cap through the contact instead of braking into it)."""
    strike_knee_offset_deg: float = 0.0
    """Added to the kicking knee target of the strike and follow-through [deg] (+ = straighter)."""
    support_hip_pitch_offset_deg: float = 0.0
    """Added to the support hip pitch target of the strike and follow-through [deg] (+ = the torso pitches
    forward over the support thigh)."""
    support_knee_offset_deg: float = 0.0
    """Added to the support knee target of the strike and follow-through [deg] (+ = straighter: the hips rise
    and move forward into the kick)."""
    support_ankle_offset_deg: float = 0.0
    """Added to the support ankle pitch target of the strike and follow-through [deg] (- = the shank tips
    forward over the foot, carrying the hips toward the ball)."""
    follow_ms: int = 100
    """Holding the strike pose while the leg decelerates [ms]."""
    retract_ms: int = 300
    """Bringing the foot back under the hip [ms]."""
    land_ms: int = 300
    """Putting the foot down at its stance place [ms]."""
    recover_ms: int = 500
    """CoM back to the middle: the walk stance [ms]."""
    arm_swing_deg: float = 0.0
    """Shoulder pitch swing during the strike [deg]: the support-side arm forward, the other back."""
    ball_ahead_m: float = 0.134
    """Ball centre ahead of the support sole's centre when the kick starts [m]."""
    ball_side_m: float = 0.083
    """Ball centre beside (toward the kicking foot) the support sole's centre when the kick starts [m]."""
    ball_direction_deg: float = 0.0
    """Measured, not a shape parameter: the direction the ball leaves in, against the robot's heading [deg] (+ =
    left; mirrored for the left foot). Written as the constant ``ball_direction_deg``: the kick skill faces that
    much the other way of its aim (``agent.skills.kick_lineup.Spot``)."""


@dataclass(frozen=True)
class Pose:
    """One keyframe's geometry in a ground frame fixed to the support foot's start."""

    right: FootPose
    left: FootPose
    com_xy_m: tuple[float, float] | None
    torso_pitch_deg: float
    torso_roll_deg: float = 0.0
    arm_offsets_deg: tuple[float, float] = (0.0, 0.0)
    torso_lift_m: float = 0.0
    torso_yaw_deg: float = 0.0


def stance_params(gait_path: Path = GAIT_PARAMS_PATH) -> GaitParams:
    """The walk stance: ``[stand]`` of the gait parameter file (so kicks start and end where the walk stands).

    Raises:
        ValueError: the file has no ``[stand]`` section (the message lists the sections it has).
    """
    sections = load_gait_params(gait_path)
    if STANCE_SECTION not in sections:
        raise ValueError(f"{gait_path}: no section [{STANCE_SECTION}] (the walk stance); known: "
                         f"{', '.join(sorted(sections))}")
    return sections[STANCE_SECTION]


def parse_kick_params(text: str, path: str = "<string>") -> dict[str, KickParams]:
    """Section name -> KickParams of every section but ``[common]`` (defaults <- common <- section).

    Raises:
        ValueError: bad TOML or an unknown key (the message names the file and section, lists the known keys).
    """
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise ValueError(f"{path}: {error}") from None
    common = kick_values(data.get(COMMON, {}), f"{path} [{COMMON}]")
    return {name: KickParams(**{**common, **kick_values(table, f"{path} [{name}]")})  # type: ignore[arg-type]
            for name, table in data.items() if name != COMMON}


def kick_values(table: Mapping[str, object], where: str) -> dict[str, object]:
    """The KickParams values of one TOML table (``provenance`` and ``measured`` left out).

    Raises:
        ValueError: an unknown key (``where`` names the file and section; the known keys are listed).
    """
    known = {f.name for f in fields(KickParams)}
    unknown = set(table) - known - set(META_KEYS)
    if unknown:
        raise ValueError(f"{where}: unknown keys {sorted(unknown)}; known: {', '.join(sorted(known))}")
    return {k: v for k, v in table.items() if k not in META_KEYS}


def kick_params(section: str, path: Path = PARAMS_PATH) -> KickParams:
    """The parameters of one kick section.

    Raises:
        ValueError: no such section, or a bad file (see :func:`parse_kick_params`).
    """
    sections = parse_kick_params(Path(path).read_text(encoding="utf-8"), str(path))
    if section not in sections:
        raise ValueError(f"{path}: no section [{section}]; known: {', '.join(sorted(sections))}")
    return sections[section]


class PoseSolver:
    """Solves kick keyframes in one ground frame fixed to the support foot, by continuation.

    The IK's feet are hard constraints and each QP step is bounded, so a foot target far from the last
    solution is infeasible in one solve; the solver walks there through poses interpolated from the
    previous keyframe (at most ``STEP_M`` of foot travel each), then moves the torso's ground point until the
    CoM lies over the pose's target (feet fixed in the ground frame). A target beyond reach (leg length,
    joint limits) is clamped to the farthest interpolated pose the IK meets, so that every parameter set
    gives a motion (the tuner needs that) and a parameter means "toward here, as far as the leg goes".

    Args:
        stance: the walk stance (torso height, the torso's place ahead of the feet, arm pose).
        solver: the keyframe solver (a new one by default).
    """

    STEP_M = 0.01

    def __init__(self, stance: GaitParams, solver: KeyframeSolver | None = None, clamp_to_reach: bool = True) -> None:
        self.stance = stance
        self.solver = solver or KeyframeSolver()
        self.clamp_to_reach = clamp_to_reach
        self.reached: list[float] = []
        """Per solved pose, the fraction of the way from the previous pose that was reached (1 = all)."""
        self._last: Pose | None = None
        self._torso = np.zeros(2)

    def _solve_at(self, pose: Pose, torso: np.ndarray) -> dict[str, float]:
        yaw = math.radians(pose.torso_yaw_deg)
        c, s = math.cos(yaw), math.sin(yaw)
        yaw_rotation = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        rotation = yaw_rotation @ torso_rotation(math.radians(pose.torso_pitch_deg), math.radians(pose.torso_roll_deg))
        targets = {"torso": PoseTarget((0.0, 0.0, self.stance.torso_height_m + pose.torso_lift_m), rotation)}
        for name, foot in (("lfoot", pose.left), ("rfoot", pose.right)):
            targets[name] = PoseTarget((foot.x_m - torso[0], foot.y_m - torso[1], foot.z_m), foot.rotation())
        # The arms are written from the arm pose, so the IK's CoM must see them there (no task moves them).
        robot = self.solver.ik.robot
        for wire, angle in self.stance.arm.angles_rad(*pose.arm_offsets_deg).items():
            robot.set_joint(wire, angle)
        robot.update_kinematics()
        result = self.solver.ik.solve(targets, position_tol_m=TORSO_TOLERANCE_M,
                                      rotation_tol_rad=math.radians(TORSO_TOLERANCE_DEG))
        worst_foot = max(result.residuals[name][0] for name in ("lfoot", "rfoot"))
        if worst_foot > FOOT_TOLERANCE_M:
            raise IKError(f"foot target missed by {worst_foot:.4g} m", task="foot", residual=worst_foot)
        return result.angles_rad

    def solve(self, pose: Pose) -> dict[str, float]:
        """Joint angles (wire -> rad) for ``pose`` (the torso's ground point stays at the mid-feet point
        when ``pose.com_xy_m`` is None). With ``clamp_to_reach``, a pose beyond reach is replaced by the
        farthest pose on the way to it that the IK meets (``reached`` records the fraction of the way).

        Raises:
            kinematics.IKError: a pose out of reach (without ``clamp_to_reach``, or not even its start).
            ValueError: the CoM does not converge.
        """
        start = self._last
        torso = self._torso.copy()
        if start is None:
            torso = np.array([(pose.left.x_m + pose.right.x_m) / 2.0, self.stance.torso_forward_m])
            candidates = [(1.0, pose)]
        else:
            travel = max(_distance(start.left, pose.left), _distance(start.right, pose.right))
            steps = max(1, math.ceil(travel / self.STEP_M))
            reachable = 0
            for k in range(1, steps):
                try:
                    self._solve_at(_blend(start, pose, k / steps), torso)
                except IKError:
                    if not self.clamp_to_reach:
                        raise
                    break
                reachable = k
            else:
                reachable = steps
            candidates = [(k / steps, _blend(start, pose, k / steps)) for k in range(reachable, -1, -1)]
        error: Exception | None = None
        for fraction, candidate in candidates:
            saved = self.solver.ik.robot.state.q.copy()
            try:
                angles, torso_at = self._solve_over_com(candidate, torso)
            except IKError as failure:
                error = failure
                self.solver.ik.robot.state.q = saved
                self.solver.ik.robot.update_kinematics()
                if not self.clamp_to_reach:
                    raise
                continue
            self._last, self._torso = candidate, torso_at
            self.reached.append(fraction)
            angles.update(self.stance.arm.angles_rad(*pose.arm_offsets_deg))
            return angles
        assert error is not None  # the loop ran at least once: candidates is never empty
        raise error

    def _solve_over_com(self, pose: Pose, torso: np.ndarray) -> tuple[dict[str, float], np.ndarray]:
        """Solve ``pose`` moving the torso until the CoM lies over ``pose.com_xy_m``; (angles, torso point)."""
        if pose.com_xy_m is None:
            torso = np.array([(pose.left.x_m + pose.right.x_m) / 2.0, self.stance.torso_forward_m])
            return dict(self._solve_at(pose, torso)), torso
        for _ in range(COM_ITERATIONS):
            angles = self._solve_at(pose, torso)
            error = np.asarray(pose.com_xy_m) - (self.solver.com_m(angles)[:2] + torso)
            if float(np.hypot(*error)) < COM_TOLERANCE_M:
                return dict(angles), torso
            torso = torso + error
        raise ValueError(f"CoM did not converge to {pose.com_xy_m} within {COM_ITERATIONS} iterations")


def _distance(a: FootPose, b: FootPose) -> float:
    return math.dist((a.x_m, a.y_m, a.z_m), (b.x_m, b.y_m, b.z_m)) + 0.05 * abs(a.pitch_rad - b.pitch_rad)


def _blend_foot(a: FootPose, b: FootPose, u: float) -> FootPose:
    return FootPose(*(x + u * (y - x) for x, y in ((a.x_m, b.x_m), (a.y_m, b.y_m), (a.z_m, b.z_m),
                                                    (a.yaw_rad, b.yaw_rad), (a.pitch_rad, b.pitch_rad))))


def _blend(a: Pose, b: Pose, u: float) -> Pose:
    return Pose(_blend_foot(a.right, b.right, u), _blend_foot(a.left, b.left, u), b.com_xy_m,
                a.torso_pitch_deg + u * (b.torso_pitch_deg - a.torso_pitch_deg),
                a.torso_roll_deg + u * (b.torso_roll_deg - a.torso_roll_deg), b.arm_offsets_deg,
                a.torso_lift_m + u * (b.torso_lift_m - a.torso_lift_m),
                a.torso_yaw_deg + u * (b.torso_yaw_deg - a.torso_yaw_deg))


def kick_poses(params: KickParams, stance: GaitParams) -> list[tuple[str, int, Pose]]:
    """The keyframes of a right-foot kick after the stance: (phase name, duration ms, geometry)."""
    half = stance.foot_spacing_m / 2.0
    left = FootPose(-half, 0.0)
    home = FootPose(half, 0.0)
    com = (left.x_m + params.com_inset_m, left.y_m + params.com_forward_m)
    base_pitch = params.torso_pitch_deg
    lean = base_pitch + params.windup_torso_pitch_deg
    strike_lean = lean + params.strike_torso_pitch_deg
    roll = params.shift_torso_roll_deg
    air_x = left.x_m + params.kick_foot_x_m
    lifted = FootPose(air_x, 0.0, params.lift_height_m)
    windup = FootPose(air_x, params.windup_back_m, params.windup_height_m,
                      yaw_rad=math.radians(params.windup_torso_yaw_deg + params.windup_yaw_deg),
                      pitch_rad=math.radians(params.windup_pitch_deg))
    via = FootPose(air_x, params.swing_forward_m, params.swing_height_m,
                   pitch_rad=math.radians(params.swing_pitch_deg))
    strike = FootPose(air_x, params.strike_forward_m, params.strike_height_m,
                      yaw_rad=math.radians(params.strike_yaw_deg), pitch_rad=math.radians(params.strike_pitch_deg))
    swing = params.arm_swing_deg
    lift = params.torso_height_m - stance.torso_height_m

    def pose(foot: FootPose, pitch: float, arms: tuple[float, float] = (0.0, 0.0), yaw: float = 0.0) -> Pose:
        return Pose(foot, left, com, pitch, roll, arms, lift, yaw)

    twist, untwist = params.windup_torso_yaw_deg, params.strike_torso_yaw_deg
    poses = [("shift", params.shift_ms, pose(home, base_pitch)),
             ("lift", params.lift_ms, pose(lifted, base_pitch)),
             ("windup", params.windup_ms, pose(windup, lean, (-swing, swing), twist))]
    if params.swing_ms > 0:
        poses.append(("swing", params.swing_ms, pose(via, lean, yaw=untwist)))
    poses += [("strike", params.strike_ms, pose(strike, strike_lean, (swing, -swing), untwist)),
              ("follow", params.follow_ms, pose(strike, strike_lean, (swing, -swing), untwist)),
              ("retract", params.retract_ms, pose(lifted, base_pitch)),
              ("land", params.land_ms, pose(home, base_pitch))]
    return poses


def _phase(name: str, angles: Mapping[str, float], duration_ms: int, **attributes: object) -> Keyframe:
    if duration_ms < 20:
        raise ValueError(f"phase {name!r}: duration {duration_ms} ms is shorter than one 20 ms cycle")
    return Keyframe(name, duration_ms / 1000.0, targets_deg(angles, LEGS + ARMS), **attributes)  # type: ignore[arg-type]


def build_kick(name: str, params: KickParams, stance: GaitParams, solver: KeyframeSolver | None = None,
               header_comments: tuple[str, ...] = ()) -> Motion:
    """The XML phase motion of a right-foot kick (see the module docstring for the phases).

    Raises:
        kinematics.IKError: a keyframe out of reach.
    """
    solver = solver or KeyframeSolver()
    solver.ik.reset()
    stand = stance_pose(stance, solver)
    poses = kick_poses(params, stance)
    half = stance.foot_spacing_m / 2.0
    pose_solver = PoseSolver(stance, solver)
    pose_solver.solve(Pose(FootPose(half, 0.0), FootPose(-half, 0.0), None, stance.torso_pitch_deg))
    names = ["stance"] + [p[0] for p in poses] + ["recover"]
    phases = [_phase("stance", stand, stance.stance_ms, next=names[1], skip_if_flag=STANCE_FLAG)]
    limits = {joint.perceptor: (joint.min_rad, joint.max_rad) for joint in solver.ik.spec.joints}
    for index, (phase_name, duration_ms, pose) in enumerate(poses, start=1):
        angles = pose_solver.solve(pose)
        for parameter, (offset_phases, wire) in JOINT_OFFSETS.items():
            offset_deg = getattr(params, parameter)
            if phase_name in offset_phases and offset_deg:
                low, high = limits[wire]
                angles[wire] = min(high, max(low, angles[wire] + math.radians(offset_deg)))
        phases.append(_phase(phase_name, angles, duration_ms, next=names[index + 1],
                             set_flag_false=STANCE_FLAG if index == 1 else None))
    phases.append(_phase("recover", stand, params.recover_ms, is_final=True, set_flag_true=STANCE_FLAG))
    constants = ball_constants(params, stance)
    return Motion(name, phases, source_format=XML, first_phase="stance", constants=constants,
                  header_comments=header_comments)


def ball_constants(params: KickParams, stance: GaitParams) -> dict[str, float]:
    """The ball's spot in the ego frame of the robot in the walk stance: ``ball_forward_m``, ``ball_left_m``; and
    ``ball_direction_deg`` where the kick has a measured direction.

    The stance puts the soles ``torso_forward_m`` behind the torso's ground point and half the foot spacing
    to each side; the support (left) sole is the origin of the kick's geometry.
    """
    half = stance.foot_spacing_m / 2.0
    constants = {"ball_forward_m": round(params.ball_ahead_m - stance.torso_forward_m, 4),
                 "ball_left_m": round(half - params.ball_side_m, 4)}
    if params.ball_direction_deg:
        constants["ball_direction_deg"] = round(params.ball_direction_deg, 2)
    return constants


def mirrored_kick(motion: Motion, name: str, header_comments: tuple[str, ...] = ()) -> Motion:
    """The left-foot kick: the mirror image, with the ball on the other side."""
    mirrored = motion.mirrored()
    constants = dict(mirrored.constants)
    constants["ball_left_m"] = -constants.get("ball_left_m", 0.0)
    if "ball_direction_deg" in constants:
        constants["ball_direction_deg"] = -constants["ball_direction_deg"]
    return replace(mirrored, name=name, constants=constants, header_comments=header_comments)


def build_all(path: Path = PARAMS_PATH, gait_path: Path = GAIT_PARAMS_PATH,
              solver: KeyframeSolver | None = None) -> dict[str, Motion]:
    """Every kick of the parameter file and its mirror: motion name -> Motion (with header comments)."""
    solver = solver or KeyframeSolver()
    stance = stance_params(gait_path)
    command = "python -m motions.authoring.kick"
    out = {}
    for name, section in KICKS.items():
        params = kick_params(section, path)
        stance_note = f" Stance: [{STANCE_SECTION}] of {gait_path.name}: " + ", ".join(
            f"{f.name}={getattr(stance, f.name)}" for f in fields(stance)
            if f.name in ("torso_height_m", "torso_pitch_deg", "torso_forward_m", "foot_spacing_m", "arm",
                          "stance_ms"))
        comments = header("motions.authoring.kick", path, section, params, command) + (stance_note + " ",)
        motion = build_kick(name, params, stance, solver, comments)
        out[name] = motion
        left_comments = comments + (f" Left-foot version: mirror image of {name} (motions.mirror). ",)
        out[name + LEFT_SUFFIX] = mirrored_kick(motion, name + LEFT_SUFFIX, left_comments)
    return out


def write_all(out_dir: Path = FILES_DIR, path: Path = PARAMS_PATH, gait_path: Path = GAIT_PARAMS_PATH) -> list[Path]:
    """Generate and write every kick file; returns the paths written."""
    return write_xml_motions(build_all(path, gait_path), out_dir)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--params", type=Path, default=PARAMS_PATH, help="kick parameter file (TOML)")
    parser.add_argument("--gait-params", type=Path, default=GAIT_PARAMS_PATH, help="gait parameter file ([stand])")
    parser.add_argument("--out", type=Path, default=FILES_DIR, help="folder for the motion files")
    args = parser.parse_args(argv)
    for target in write_all(args.out, args.params, args.gait_params):
        print(f"wrote {target}")


if __name__ == "__main__":
    main()


__all__ = ["KICKS", "STRIKE_PHASES", "KickParams", "Pose", "build_all", "build_kick", "kick_params", "kick_poses",
           "ball_constants", "mirrored_kick", "parse_kick_params", "PoseSolver", "stance_params", "write_all"]
