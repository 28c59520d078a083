"""Walks for the robot types with other leg geometry (REFERENCE §2.5: types 1 and 3 have longer legs, type 3
a wider hip), written to ``motions/files/type<N>/``.

Why: a type-0 walk file replays type 0's joint angles, which on a longer leg put the torso higher and the
feet elsewhere than the gait was tuned for; measured on our simulator, type 1 fell in 10 and type 3 in 11
of 12 forward-walk transition trials (``python -m motion_studio.walk_trials --motion walk_forward
--robot-type N``). Each type's walks are solved with its own kinematics from the type-0 gait parameters,
with the posture (torso height, torso forward offset, foot spacing) taken from forward kinematics of
``stand``'s joint angles on that type: so the type's walks start from and stop in exactly the pose of the
shared ``stand`` file (which the turns, kicks and stand-ups also end in), only the legs are longer.
Optional per-type overrides and measured figures live in ``motions/params/gait_type<N>.toml`` (sections
named by motion, as in ``gait.toml``).

Run ``python -m motions.authoring.gait_types`` to write every type's files.
"""

from __future__ import annotations

import tomllib
from dataclasses import replace
from pathlib import Path

import numpy as np

from motions.authoring.common import FILES_DIR, PARAMS_DIR, KeyframeSolver, header
from motions.authoring.gait import MEASURED_KEYS, GaitParams, build_walk, stance_pose

#: Robot types whose leg geometry differs from type 0 (types 2 and 4 share type 0's leg lengths).
TYPES_WITH_OWN_WALKS = (1, 3)
#: The walks written per type (``stand`` stays the shared type-0 file).
WALK_NAMES = ("walk_forward", "walk_fast", "walk_backward", "walk_left", "walk_right", "orbit_left", "orbit_right")
COMMAND = "python -m motions.authoring.gait_types"


def type_params_path(robot_type: int) -> Path:
    """The optional override file of a robot type."""
    return PARAMS_DIR / f"gait_type{robot_type}.toml"


def type_posture(robot_type: int, stand: GaitParams) -> dict[str, float]:
    """Posture keys (``torso_height_m``, ``torso_forward_m``, ``foot_spacing_m``) that put a robot of
    ``robot_type`` in the same joint angles as the type-0 stance of ``stand`` [m]."""
    from kinematics.fk import NaoKinematics

    angles = stance_pose(stand, KeyframeSolver(0))
    kinematics = NaoKinematics(robot_type)
    left, right = kinematics.frame_pose("lsole", angles), kinematics.frame_pose("rsole", angles)
    mid = (left.position_m + right.position_m) / 2.0
    torso_in_sole = left.rotation.T @ (-mid)  # torso centre in the (level) sole frame: x right, y forward, z up
    return {"torso_height_m": round(float(torso_in_sole[2]), 4), "torso_forward_m": round(float(torso_in_sole[1]), 4),
            "foot_spacing_m": round(float(np.linalg.norm(left.position_m - right.position_m)), 4)}


def type_gait_params(robot_type: int, table: dict[str, GaitParams],
                     overrides_path: Path | None = None) -> tuple[dict[str, GaitParams], dict[str, dict]]:
    """(motion -> GaitParams for ``robot_type``, motion -> its override section): type-0 parameters with the
    type's posture, then the section of the type's override file.

    Raises:
        ValueError: an unknown key in the override file (names the file and section).
    """
    from motions.authoring.gait_params import _gait_values

    posture = type_posture(robot_type, table["stand"])
    path = overrides_path or type_params_path(robot_type)
    raw = tomllib.loads(path.read_text(encoding="utf-8")) if path.is_file() else {}
    out = {"stand": replace(table["stand"], **posture)}
    for name in WALK_NAMES:
        section = raw.get(name, {})
        out[name] = replace(table[name], **{**posture, **_gait_values(section, f"{path} [{name}]")})
    return out, raw


def write_type_gait_files(robot_type: int, params_path: Path | None = None, out_root: Path | None = None,
                          names: tuple[str, ...] = WALK_NAMES) -> list[Path]:
    """Write ``type<N>/<walk>.xml`` for one robot type; returns the paths.

    Raises:
        ValueError: a bad parameter file; kinematics.IKError: a keyframe out of reach.
    """
    from motions import save
    from motions.authoring.gait_params import GAIT_PARAMS_PATH, load_gait_params

    params_path = Path(params_path or GAIT_PARAMS_PATH)
    table = load_gait_params(params_path)
    params, raw = type_gait_params(robot_type, table)
    out_dir = Path(out_root or FILES_DIR) / f"type{robot_type}"
    out_dir.mkdir(parents=True, exist_ok=True)
    solver = KeyframeSolver(robot_type)
    written = []
    for name in names:
        section = raw.get(name, {})
        lines = header("motions.authoring.gait_types", params_path, name, params[name], f"{COMMAND} {robot_type}")
        note = (f" Robot type {robot_type}: solved with its kinematics; posture from the type-0 stance angles "
                f"(motions.authoring.gait_types.type_posture); overrides: {type_params_path(robot_type).name} ")
        if section.get("provenance"):
            note += f"- {section['provenance']} "
        lines = lines[:-1] + (note.replace("--", "- -"),) + lines[-1:]
        measured = {key: float(section[key]) for key in MEASURED_KEYS if key in section}
        motion = build_walk(name, params[name], solver, lines, measured, params["stand"])
        path = out_dir / f"{name}.xml"
        save(motion, path)
        written.append(path)
    return written


def main(argv: list[str] | None = None) -> int:
    """``python -m motions.authoring.gait_types [TYPE ...]``: write the walks of the types (default: all)."""
    import argparse

    parser = argparse.ArgumentParser(prog=COMMAND, description=main.__doc__)
    parser.add_argument("types", nargs="*", type=int, default=list(TYPES_WITH_OWN_WALKS))
    args = parser.parse_args(argv)
    for robot_type in args.types or TYPES_WITH_OWN_WALKS:
        for path in write_type_gait_files(robot_type):
            print(path)
    return 0


__all__ = ["TYPES_WITH_OWN_WALKS", "WALK_NAMES", "type_gait_params", "type_params_path", "type_posture",
           "write_type_gait_files"]


if __name__ == "__main__":
    raise SystemExit(main())
