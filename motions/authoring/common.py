"""What every motion generator shares: the crouched stance, IK keyframes from foot/torso poses, parameter
files, and the header comment that says how a file was made.

Frames: the IK ground frame of ``kinematics.ik`` (x right, y forward, z up, soles on z = 0). A keyframe is
solved from a torso pose (height, pitch, roll) and the two sole poses relative to the torso's ground point;
arms and head are set joint by joint (they do not touch the ground).
"""

from __future__ import annotations

import datetime
import math
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, fields
from pathlib import Path

import numpy as np

from kinematics.fk import torso_rotation
from kinematics.ik import PoseTarget, WholeBodyIK
from motions.model import JointTarget, Motion

#: Parameter files of the generators.
PARAMS_DIR = Path(__file__).resolve().parents[1] / "params"
#: Generated motion files.
FILES_DIR = Path(__file__).resolve().parents[1] / "files"
#: Joints of each leg / arm (wire names), canonical order.
LEFT_LEG = ("llj1", "llj2", "llj3", "llj4", "llj5", "llj6")
RIGHT_LEG = ("rlj1", "rlj2", "rlj3", "rlj4", "rlj5", "rlj6")
LEGS = LEFT_LEG + RIGHT_LEG
ARMS = ("laj1", "laj2", "laj3", "laj4", "raj1", "raj2", "raj3", "raj4")
#: Angles are written with 0.01 deg resolution (the wire's HJ resolution).
ANGLE_DECIMALS = 2


@dataclass(frozen=True)
class FootPose:
    """A sole pose in the ground frame: centre (x right, y forward, z up) [m], yaw about z [rad] (+ = left),
    and optional pitch about the foot's x axis [rad] (+ = toes up)."""

    x_m: float
    y_m: float
    z_m: float = 0.0
    yaw_rad: float = 0.0
    pitch_rad: float = 0.0

    def rotation(self) -> np.ndarray:
        c, s = math.cos(self.yaw_rad), math.sin(self.yaw_rad)
        yaw = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        cp, sp = math.cos(self.pitch_rad), math.sin(self.pitch_rad)
        pitch = np.array([[1.0, 0.0, 0.0], [0.0, cp, -sp], [0.0, sp, cp]])
        return yaw @ pitch


@dataclass(frozen=True)
class ArmPose:
    """Arm joints of both arms [deg], SimSpark signs; the right arm mirrors the left (roll negated)."""

    shoulder_pitch_deg: float = -90.0
    shoulder_roll_deg: float = 8.0
    elbow_yaw_deg: float = 0.0
    elbow_roll_deg: float = 0.0

    def angles_rad(self, left_pitch_offset_deg: float = 0.0, right_pitch_offset_deg: float = 0.0) -> dict[str, float]:
        """Wire name -> angle [rad] for both arms, with optional shoulder pitch offsets (arm swing)."""
        return {
            "laj1": math.radians(self.shoulder_pitch_deg + left_pitch_offset_deg),
            "laj2": math.radians(self.shoulder_roll_deg), "laj3": math.radians(-self.elbow_yaw_deg),
            "laj4": math.radians(-self.elbow_roll_deg),
            "raj1": math.radians(self.shoulder_pitch_deg + right_pitch_offset_deg),
            "raj2": math.radians(-self.shoulder_roll_deg), "raj3": math.radians(self.elbow_yaw_deg),
            "raj4": math.radians(self.elbow_roll_deg),
        }


class KeyframeSolver:
    """Solves keyframes given as torso + feet poses with one warm-started WholeBodyIK.

    Args:
        robot_type: 0-4.
    """

    def __init__(self, robot_type: int = 0) -> None:
        self.robot_type = robot_type
        self.ik = WholeBodyIK(robot_type)

    def solve(self, torso_height_m: float, left: FootPose, right: FootPose, torso_pitch_rad: float = 0.0,
              torso_roll_rad: float = 0.0) -> dict[str, float]:
        """Joint angles (wire name -> rad) with the torso centre at (0, 0, height), tilted by pitch (+ =
        forward) and roll (+ = right), and the soles at ``left`` / ``right`` (ground frame).

        Raises:
            kinematics.IKError: a pose out of reach (names the task).
        """
        torso = PoseTarget((0.0, 0.0, torso_height_m), torso_rotation(torso_pitch_rad, torso_roll_rad))
        targets = {"torso": torso,
                   "lfoot": PoseTarget((left.x_m, left.y_m, left.z_m), left.rotation()),
                   "rfoot": PoseTarget((right.x_m, right.y_m, right.z_m), right.rotation())}
        return self.ik.solve(targets).angles_rad

    def com_m(self, angles_rad: Mapping[str, float]) -> np.ndarray:
        """Whole-body CoM in the IK's current ground frame [m] (after ``solve``)."""
        return np.asarray(self.ik.robot.com_world(), dtype=float)


def targets_deg(angles_rad: Mapping[str, float], joints: tuple[str, ...]) -> dict[str, JointTarget]:
    """JointTargets of ``joints`` rounded to ANGLE_DECIMALS degrees."""
    return {j: JointTarget.from_deg(round(math.degrees(angles_rad[j]), ANGLE_DECIMALS)) for j in joints}


def load_params(cls: type, path: Path, section: str) -> object:
    """Build dataclass ``cls`` from ``[section]`` of TOML file ``path`` (missing keys keep their defaults).

    Raises:
        ValueError: unknown section or key (the message names the file and lists the known ones).
    """
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    if section not in data:
        raise ValueError(f"{path}: no section [{section}]; sections: {', '.join(data)}")
    table = data[section]
    known = {f.name for f in fields(cls)}
    unknown = set(table) - known
    if unknown:
        raise ValueError(f"{path}: [{section}] has unknown keys {sorted(unknown)}; known: {sorted(known)}")
    return cls(**{k: tuple(v) if isinstance(v, list) else v for k, v in table.items()})


def sections(path: Path) -> list[str]:
    """Section names of a TOML parameter file, in file order."""
    return list(tomllib.loads(path.read_text(encoding="utf-8")))


def _shown_path(path: Path) -> str:
    """A parameter file as the header shows it: relative to the project for its own files (so headers do
    not carry a machine's folders), else as given (a user's file elsewhere)."""
    project = Path(__file__).resolve().parents[2]
    try:
        return str(Path(path).resolve().relative_to(project))
    except ValueError:
        return str(path)


def header(generator: str, params_path: Path | None, section: str | None, params: object,
           command: str = "motion-studio author") -> tuple[str, ...]:
    """Header comment lines: what made the file, from which parameters, when."""
    date = datetime.date.today().isoformat()
    source = f" [{section}] of {_shown_path(params_path)}" if params_path and section else ""
    values = ", ".join(f"{f.name}={getattr(params, f.name)}" for f in fields(params)) if params is not None else ""
    lines = (f" Generated by {generator} (nao3d-toolkit, IK with kinematics.ik.WholeBodyIK) on {date}. ",
             f" Command: {command}; parameters{source}: ",
             f" {values} ".replace("--", "- -"),
             " Do not edit by hand: change the parameters and regenerate. ")
    return tuple(line for line in lines if line.strip())


def write_xml_motions(motions_by_name: Mapping[str, Motion], out_dir: Path) -> list[Path]:
    """Validate and save each motion as ``out_dir/<name>.xml`` (XML phase format); returns the paths.

    Why validate first: a generator must never ship a file the agent's loader would refuse.
    """
    from motions.io import save

    out_dir.mkdir(parents=True, exist_ok=True)
    written = []
    for name, motion in motions_by_name.items():
        motion.validate()
        target = out_dir / f"{name}.xml"
        save(motion, target)
        written.append(target)
    return written

