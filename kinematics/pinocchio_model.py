"""Pinocchio models of the Nao, parsed from the generated MJCF (the same text MuJoCo loads)."""

from __future__ import annotations

import tempfile
from functools import lru_cache
from pathlib import Path

import pinocchio as pin

from kinematics.mjcf import robot_mjcf_xml
from kinematics.spec import check_robot_type


@lru_cache(maxsize=None)
def mjcf_path(robot_type: int, free: bool) -> Path:
    """A cached file holding the MJCF text; Pinocchio's MJCF parser reads files, not strings."""
    directory = Path(tempfile.gettempdir()) / "nao3d_models"
    directory.mkdir(parents=True, exist_ok=True)
    path = directory / f"nao_type{robot_type}_{'free' if free else 'fixed'}.xml"
    # The fixed model welds the torso at the origin, so its frames are torso-relative.
    text = robot_mjcf_xml(robot_type, free=free, torso_pos_m=None if free else (0.0, 0.0, 0.0))
    if not path.exists() or path.read_text() != text:
        tmp = path.with_suffix(".tmp")
        tmp.write_text(text)
        tmp.replace(path)
    return path


@lru_cache(maxsize=None)
def pinocchio_model(robot_type: int = 0, free: bool = True) -> pin.Model:
    """Pinocchio model of one Nao type (free flyer at the torso, or torso fixed to the world).

    The free-flyer configuration is [x, y, z, qx, qy, qz, qw, 22 hinge angles] (Pinocchio's quaternion order
    differs from MuJoCo's [w, x, y, z]); its translation is relative to the MJCF torso position
    (0, 0, 0.385), whereas MuJoCo's free-joint qpos is absolute. Hinge order is the spec's canonical order.
    """
    check_robot_type(robot_type)
    return pin.buildModelFromMJCF(str(mjcf_path(robot_type, free)))
