"""Reads joint angles given by a user (command line or file) into SimSpark-signed radians keyed by wire name."""

from __future__ import annotations

import json
import math
from pathlib import Path

from kinematics import SpecError, robot_spec


def parse_joint_assignments(assignments: list[str], robot_type: int = 0) -> dict[str, float]:
    """``["llj3=30", "LKneePitch=-60"]`` (degrees, SimSpark sign) -> {wire name: rad}.

    Raises:
        SpecError: a malformed assignment, unknown joint or non-finite value (the message quotes it).
    """
    spec = robot_spec(robot_type)
    angles: dict[str, float] = {}
    for item in assignments:
        name, sep, value = item.partition("=")
        if not sep:
            raise SpecError(f"joint assignment {item!r}: expected NAME=DEGREES, e.g. llj3=30", field="joint")
        try:
            degrees = float(value)
        except ValueError:
            raise SpecError(f"joint assignment {item!r}: {value!r} is not a number of degrees",
                            field=name) from None
        if not math.isfinite(degrees):
            raise SpecError(f"joint assignment {item!r}: angle must be finite", field=name)
        angles[spec.joint(name.strip()).perceptor] = math.radians(degrees)
    return angles


def read_pose_file(path: Path, robot_type: int = 0) -> dict[str, float]:
    """A JSON pose file ``{"llj3": 30, ...}`` or ``{"joints_deg": {...}}`` (degrees) -> {wire name: rad}."""
    try:
        data = json.loads(Path(path).read_text())
    except json.JSONDecodeError as error:
        raise SpecError(f"{path}:{error.lineno}: not valid JSON ({error.msg})", field="pose") from None
    if isinstance(data, dict) and "joints_deg" in data:
        data = data["joints_deg"]
    if not isinstance(data, dict):
        raise SpecError(f"{path}: expected an object of joint name -> degrees", field="pose")
    return parse_joint_assignments([f"{k}={v}" for k, v in data.items()], robot_type)
