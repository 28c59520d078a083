"""Turn in place: one motion = one turn of two steps, solved keyframe by keyframe with IK, written as Webots
``.motion`` files so that the controller's turn gain scales it (REFERENCE §7.3).

The turn (left; the right turn is its mirror image, ``motions.mirror``):

1. **Footsteps.** Both feet rotate by ``turn_deg`` about the torso's ground point, so the torso does not
   drift. The leading foot (the left one for a left turn) steps first and lands rotated outward; then the
   other foot steps and closes beside it, parallel. The hip yaw joints of the Nao turn a foot outward only
   (LHipYawPitch/RHipYawPitch range -90..1 deg, REFERENCE §2.2), and with the torso's yaw between the feet's
   yaws both feet stay turned outward (or straight) relative to the torso all the time.
2. **Torso.** At ``torso_height_m``, pitched ``torso_pitch_deg`` forward, ``torso_forward_m`` ahead of the
   mid-feet point (the walk's stance); its yaw is the mean of the feet's yaws at every instant (so it stays
   between them: neither foot ever turns inward relative to the torso), and it sways ``sway_m`` toward the
   stance foot (a sine over the step shifted by ``sway_phase``).
3. **Swing.** Each step starts with ``double_support_cycles`` on both feet; the swing foot then travels on a
   cycloid (zero speed at lift-off and touch-down), rises ``step_height_m`` on a raised cosine, and turns
   with the same cycloid.
4. **Keyframes.** One Webots pose per 20 ms cycle (played with the file's times, ``playback.toml``): the
   stance, ``settle_cycles`` stance poses, the two steps, ``settle_cycles`` stance poses at the end.
5. **Gain base.** ``turn_left_base`` / ``turn_right_base`` are the same motions with ``turn_deg = 0``
   (stepping in place, same lift and sway). The controller plays ``base + gain * (turn - base)`` pose by
   pose (``gain_bases`` in ``motions/files/playback.toml``), so a gain scales only the turn, never the
   lift, and gain 0 steps in place.

Webots files carry no comments (REFERENCE §6b), so how they were made is written into the ``[provenance]``
table of ``motions/files/playback.toml``, beside their gain bases and timings. Parameters: ``[turn]`` of
``motions/params/turn.toml``. Run ``python -m motions.authoring.turn``.
"""

from __future__ import annotations

import argparse
import datetime
import math
import tomllib
from dataclasses import dataclass, fields, replace
from pathlib import Path

from motions.authoring.common import (ARMS, FILES_DIR, LEGS, PARAMS_DIR, ArmPose, FootPose, KeyframeSolver,
                                      targets_deg)
from motions.io import save
from motions.mirror import mirrored_motion
from motions.model import SERVER_CYCLE_MS, WEBOTS, Keyframe, Motion

CYCLE_S = SERVER_CYCLE_MS / 1000.0
#: The parameter file and its section.
PARAMS_PATH = PARAMS_DIR / "turn.toml"
PARAMS_SECTION = "turn"
#: Playback settings of the shipped motions (gain bases, Webots timings, provenance of Webots files).
PLAYBACK_PATH = FILES_DIR / "playback.toml"
#: Motion names: the turns and the gain bases they are scaled from.
TURN_NAMES = {"left": "turn_left", "right": "turn_right"}
BASE_NAMES = {"left": "turn_left_base", "right": "turn_right_base"}
#: Head joints: held at 0 by the turn (a behaviour's head request overrides them in the controller).
HEAD = ("hj1", "hj2")
COMMAND = "python -m motions.authoring.turn"


@dataclass(frozen=True)
class TurnParams:
    """Parameters of the turn (units in the names; angles SimSpark-signed, + turn = left)."""

    turn_deg: float = 40.0
    """Turn of one motion at gain 1 [deg]."""
    step_cycles: int = 10
    """Cycles per step (double support plus swing) [cycles of 20 ms]."""
    double_support_cycles: int = 2
    """Cycles at the start of each step with both feet on the ground."""
    settle_cycles: int = 1
    """Stance poses before the first and after the second step [cycles]."""
    step_height_m: float = 0.02
    """Height of the swing sole at mid-swing [m]."""
    sway_m: float = 0.01
    """Sideways torso shift toward the stance foot at mid-step [m]."""
    sway_phase: float = 0.0
    """Shift of the sway curve against the step, as a fraction of a step (+ = later)."""
    torso_height_m: float = 0.345
    """Torso centre above the ground [m] (the walk's stance)."""
    torso_pitch_deg: float = 8.0
    """Torso lean forward [deg] (the walk's stance)."""
    torso_forward_m: float = 0.0
    """Torso centre ahead of the mid-feet point [m] (the walk's stance)."""
    foot_spacing_m: float = 0.11
    """Distance between the sole centres, side to side [m] (the walk's stance)."""
    arm: ArmPose = ArmPose()
    """Arm pose (the walk's stance)."""
    toe_out_deg: float = 0.0
    """Each foot turned outward by this in the stance [deg] (the walk's stance)."""

    def __post_init__(self) -> None:
        if self.step_cycles < 2 or not 0 <= self.double_support_cycles < self.step_cycles:
            raise ValueError(f"need step_cycles >= 2 and 0 <= double_support_cycles < step_cycles, got "
                             f"{self.step_cycles}, {self.double_support_cycles}")
        if self.settle_cycles < 0:
            raise ValueError(f"settle_cycles must be >= 0, got {self.settle_cycles}")
        if not -90.0 < self.turn_deg < 90.0:
            raise ValueError(f"turn_deg must lie in (-90, 90), got {self.turn_deg}")

    @property
    def cycles(self) -> int:
        """Poses (= cycles) of one motion."""
        return 1 + 2 * self.settle_cycles + 2 * self.step_cycles

    @property
    def duration_s(self) -> float:
        return self.cycles * CYCLE_S


#: Stance fields of TurnParams that come from the walk's stance (gait parameters) unless the turn sets them.
STANCE_FIELDS = ("torso_height_m", "torso_pitch_deg", "torso_forward_m", "foot_spacing_m", "arm", "toe_out_deg")
#: Key of the turn's section naming the gait section whose stance the turn uses.
STANCE_KEY = "stance_section"


def load_turn_params(path: Path = PARAMS_PATH, section: str = PARAMS_SECTION,
                     gait_path: Path | None = None) -> TurnParams:
    """TurnParams from ``[section]`` of a TOML file (``arm`` as a sub-table of ArmPose fields).

    ``stance_section = "stand"`` takes the stance fields (STANCE_FIELDS) of that section of the gait
    parameter file (``motions/params/gait.toml``, the walk's stance), so turns start and end where the walk
    stands; keys the turn's section sets itself override them.

    Raises:
        ValueError: missing section, unknown key or bad value (the message names the file).
    """
    data = tomllib.loads(Path(path).read_text(encoding="utf-8"))
    if section not in data:
        raise ValueError(f"{path}: no section [{section}]; sections: {', '.join(data) or 'none'}")
    table = dict(data[section])
    stance_section = table.pop(STANCE_KEY, None)
    known = {f.name for f in fields(TurnParams)}
    unknown = set(table) - known
    if unknown:
        raise ValueError(f"{path}: [{section}] has unknown keys {sorted(unknown)}; known: "
                         f"{sorted(known | {STANCE_KEY})}")
    values: dict[str, object] = {}
    if stance_section is not None:
        values.update(walk_stance(str(stance_section), gait_path))
    try:
        if "arm" in table:
            table["arm"] = ArmPose(**table["arm"])
        values.update(table)
        return TurnParams(**values)  # type: ignore[arg-type]
    except (TypeError, ValueError) as error:
        raise ValueError(f"{path}: [{section}]: {error}") from None


def walk_stance(section: str, gait_path: Path | None = None) -> dict[str, object]:
    """The stance fields of a section of the gait parameter file (the walk generator's own reading of it).

    Raises:
        ValueError: no such section (the message lists the known ones).
    """
    from motions.authoring.gait_params import GAIT_PARAMS_PATH, load_gait_params

    gait_path = gait_path or GAIT_PARAMS_PATH
    sections = load_gait_params(gait_path)
    if section not in sections:
        raise ValueError(f"{gait_path}: no gait section [{section}] for the turn's stance; known: "
                         f"{', '.join(sorted(sections))}")
    gait = sections[section]
    return {name: getattr(gait, name) for name in STANCE_FIELDS if hasattr(gait, name)}


# ---- geometry ----------------------------------------------------------------------------------------
@dataclass(frozen=True)
class TurnSample:
    """One keyframe's geometry: both soles in the torso's ground frame (x right, y forward, yaw + = left)."""

    left: FootPose
    right: FootPose


def _rotated(x_m: float, y_m: float, yaw_rad: float) -> tuple[float, float]:
    c, s = math.cos(yaw_rad), math.sin(yaw_rad)
    return c * x_m - s * y_m, s * x_m + c * y_m


def turn_samples(params: TurnParams) -> list[TurnSample]:
    """The geometry of every pose of a left turn (``turn_deg`` > 0 turns left), relative to the torso.

    Fixed frame: the torso's ground point at the origin, facing +y at the start. The feet end rotated by
    ``turn_deg`` about the origin; the left foot steps first.
    """
    half = params.foot_spacing_m / 2.0
    theta = math.radians(params.turn_deg)
    toe_out = math.radians(params.toe_out_deg)
    start = {"left": FootPose(-half, 0.0, 0.0, toe_out), "right": FootPose(half, 0.0, 0.0, -toe_out)}
    end = {}
    for side, foot in start.items():
        x, y = _rotated(foot.x_m, foot.y_m, theta)
        end[side] = FootPose(x, y, 0.0, foot.yaw_rad + theta)
    stance = _relative(start, 0.0, 0.0, params)
    samples = [stance] * (1 + params.settle_cycles)
    feet = dict(start)
    n, ds = params.step_cycles, params.double_support_cycles
    for swing_side, stance_sign in (("left", 1.0), ("right", -1.0)):  # torso sways toward the stance foot
        before = dict(feet)
        origin, landing = before[swing_side], end[swing_side]
        for cycle in range(1, n + 1):
            u = cycle / n
            swing_phase = 0.0 if cycle <= ds else (cycle - ds) / (n - ds)
            blend = swing_phase - math.sin(2.0 * math.pi * swing_phase) / (2.0 * math.pi)  # cycloid
            now = dict(before)
            now[swing_side] = FootPose(origin.x_m + blend * (landing.x_m - origin.x_m),
                                       origin.y_m + blend * (landing.y_m - origin.y_m),
                                       params.step_height_m * (1.0 - math.cos(2.0 * math.pi * swing_phase)) / 2.0,
                                       origin.yaw_rad + blend * (landing.yaw_rad - origin.yaw_rad))
            torso_yaw = (now["left"].yaw_rad + now["right"].yaw_rad) / 2.0
            sway = stance_sign * params.sway_m * math.sin(math.pi * ((u - params.sway_phase) % 1.0))
            samples.append(_relative(now, torso_yaw, sway, params))
        feet = dict(before)
        feet[swing_side] = landing
    samples += [_relative(end, theta, 0.0, params)] * params.settle_cycles  # mid-feet yaw = theta
    return samples


def _relative(feet: dict[str, FootPose], torso_yaw_rad: float, sway_m: float, params: TurnParams) -> TurnSample:
    """The feet in the frame of a torso ground point at the origin with yaw ``torso_yaw_rad``, shifted
    ``sway_m`` to its right and ``torso_forward_m`` forward."""
    relative = {}
    for side, foot in feet.items():
        x, y = _rotated(foot.x_m, foot.y_m, -torso_yaw_rad)
        relative[side] = FootPose(x - sway_m, y - params.torso_forward_m, foot.z_m, foot.yaw_rad - torso_yaw_rad)
    return TurnSample(relative["left"], relative["right"])


# ---- keyframes and files -------------------------------------------------------------------------------
def solve_turn(params: TurnParams, solver: KeyframeSolver | None = None) -> list[dict[str, float]]:
    """Joint angles (wire name -> rad) of every pose of the left turn: legs by IK, arms and head set.

    Raises:
        kinematics.IKError: a pose out of reach.
    """
    solver = solver or KeyframeSolver()
    pitch = math.radians(params.torso_pitch_deg)
    poses = []
    for sample in turn_samples(params):
        angles = dict(solver.solve(params.torso_height_m, sample.left, sample.right, pitch))
        angles.update(params.arm.angles_rad())
        angles.update({joint: 0.0 for joint in HEAD})
        poses.append(angles)
    return poses


def build_turn(name: str, params: TurnParams, solver: KeyframeSolver | None = None) -> Motion:
    """The left turn of ``params`` as a Webots motion called ``name``, one pose per cycle.

    Raises:
        kinematics.IKError: a pose out of reach.
    """
    poses = solve_turn(params, solver)
    ms = round(CYCLE_S * 1000)
    joints = HEAD + ARMS[:4] + LEGS + ARMS[4:]
    keyframes = [Keyframe(f"Pose{i + 1}", ms / 1000.0, targets_deg(pose, joints)) for i, pose in enumerate(poses)]
    return Motion(name, keyframes, source_format=WEBOTS, joint_order=joints)


def build_all(params: TurnParams) -> dict[str, Motion]:
    """turn_left, turn_right and their gain bases (name -> motion); the right ones mirror the left ones."""
    solver = KeyframeSolver()
    left = build_turn(TURN_NAMES["left"], params, solver)
    left_base = build_turn(BASE_NAMES["left"], replace(params, turn_deg=0.0), solver)
    right = replace(mirrored_motion(left), name=TURN_NAMES["right"])
    right_base = replace(mirrored_motion(left_base), name=BASE_NAMES["right"])
    return {m.name: m for m in (left, right, left_base, right_base)}


def provenance(params: TurnParams, params_path: Path = PARAMS_PATH, section: str = PARAMS_SECTION) -> str:
    """One line saying how the turn files were made (Webots files cannot carry it themselves)."""
    values = ", ".join(f"{f.name}={getattr(params, f.name)}" for f in fields(params))
    stance = tomllib.loads(params_path.read_text(encoding="utf-8")).get(section, {}).get(STANCE_KEY)
    if stance:
        values += f" (stance fields from the walk's [{stance}] of motions/params/gait.toml)"
    try:
        source = params_path.resolve().relative_to(FILES_DIR.parents[1])
    except ValueError:
        source = params_path
    return (f"generated by motions.authoring.turn (IK with kinematics.ik.WholeBodyIK) on "
            f"{datetime.date.today().isoformat()}; command: {COMMAND}; parameters [{section}] of {source}: "
            f"{values}; right turn = mirror of the left (motions.mirror); do not edit by hand")


# ---- playback.toml ----------------------------------------------------------------------------------
_PLAYBACK_HEADER = (
    "# Playback settings of the shipped motions, read by agent.motion.library.default_library.\n"
    "# [gain_bases]: motion -> motion its turn gain scales from (same pose count).\n"
    "# [webots_timing]: motion -> WebotsTiming fields (duration_cycles, pose_step, use_file_times).\n"
    "# [provenance]: motion -> how a Webots file was made (Webots files cannot carry comments, REFERENCE 6b).\n"
    "# Generators update their own entries and keep everyone else's.\n")


def _toml_string(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def _toml_inline(value: object) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, str):
        return _toml_string(value)
    if isinstance(value, dict):
        return "{ " + ", ".join(f"{k} = {_toml_inline(v)}" for k, v in value.items()) + " }"
    raise TypeError(f"cannot write {value!r} into playback.toml")


def update_playback(path: Path, entries: dict[str, dict[str, object]]) -> None:
    """Set ``entries`` (table -> key -> value) in the playback settings file, keeping all other entries.

    The file is rewritten from its parsed content (tables of plain values), so comments other than the
    standard header are not kept.
    """
    data: dict[str, dict[str, object]] = {}
    if path.is_file():
        data = {k: dict(v) for k, v in tomllib.loads(path.read_text(encoding="utf-8")).items()}
    for table, values in entries.items():
        data.setdefault(table, {}).update(values)
    lines = [_PLAYBACK_HEADER.rstrip("\n")]
    for table in sorted(data):
        lines += ["", f"[{table}]"]
        lines += [f"{key} = {_toml_inline(value)}" for key, value in sorted(data[table].items())]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def write_files(params: TurnParams, out_dir: Path = FILES_DIR, playback_path: Path | None = None,
                params_path: Path = PARAMS_PATH) -> list[Path]:
    """Build and write the turn motions and their playback entries; returns the motion files written."""
    out_dir.mkdir(parents=True, exist_ok=True)
    built = build_all(params)
    paths = []
    for name, motion in built.items():
        path = out_dir / f"{name}.motion"
        save(motion, path)
        paths.append(path)
    note = provenance(params, params_path)
    entries: dict[str, dict[str, object]] = {
        "gain_bases": {TURN_NAMES[s]: BASE_NAMES[s] for s in TURN_NAMES},
        "webots_timing": {name: {"use_file_times": True} for name in built},
        "provenance": {name: note for name in built},
    }
    update_playback(playback_path or out_dir / "playback.toml", entries)
    return paths


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--params", type=Path, default=PARAMS_PATH, help="parameter file (TOML)")
    parser.add_argument("--section", default=PARAMS_SECTION, help="section of the parameter file")
    parser.add_argument("--out", type=Path, default=FILES_DIR, help="folder of the motion files")
    args = parser.parse_args(argv)
    params = load_turn_params(args.params, args.section)
    for path in write_files(params, args.out, params_path=args.params):
        print(path)


if __name__ == "__main__":
    main()


__all__ = ["BASE_NAMES", "TURN_NAMES", "TurnParams", "TurnSample", "build_all", "build_turn", "load_turn_params",
           "provenance", "solve_turn", "turn_samples", "update_playback", "walk_stance", "write_files"]
