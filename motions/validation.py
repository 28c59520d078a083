"""Checks of a motion model against one robot type: joint names, angles, durations and phase names.

Readers check only what their format demands (numbers, names, structure), so a file whose angles sit beyond
a stop can still be opened and fixed in the editor; ``validate_motion`` is the stricter check the agent and
the tools run before playing a motion. Errors point back into the file when the motion was read from one.
"""

from __future__ import annotations

import math

from kinematics import JointSpec, SpecError, robot_spec

from motions.errors import MotionFormatError
from motions.model import WEBOTS, XML, Keyframe, Motion

# Degrees in the file -> radians inside can move a value on a limit by a few ulps; allow that, no more.
LIMIT_TOLERANCE_RAD = 1e-9


def _file_name(spec: JointSpec | None, wire: str, source_format: str | None) -> str:
    """The joint's name in the vocabulary of the motion's file, so the error matches what the user sees."""
    if spec is None:
        return wire
    if source_format == XML:
        return spec.effector
    if source_format == WEBOTS:
        return spec.nao_name
    return spec.perceptor


def _error(motion: Motion, keyframe: Keyframe | None, detail: str, field: str, joint: str | None = None
           ) -> MotionFormatError:
    path = motion.source.path if motion.source else None
    line = None
    if keyframe is not None and keyframe.source is not None:
        line = keyframe.source.target_lines.get(joint, keyframe.source.line) if joint else keyframe.source.line
    element = None
    if keyframe is not None:
        element = f"{'pose' if motion.source_format == WEBOTS else 'phase'} {keyframe.name!r}"
    return MotionFormatError(detail, path=path, line=line, field=field, element=element)


def _check_duration(motion: Motion, index: int, keyframe: Keyframe) -> None:
    duration = keyframe.duration_s
    # Only the first keyframe may take no time: a Webots pose at time 0 ("be here from the start").
    minimum_ok = duration >= 0.0 if index == 0 else duration > 0.0
    if not (isinstance(duration, (int, float)) and math.isfinite(duration) and minimum_ok):
        bound = ">= 0" if index == 0 else "> 0"
        raise _error(motion, keyframe, f"duration must be a finite number of seconds {bound}, got {duration!r}",
                     "duration")


def _check_target(motion: Motion, keyframe: Keyframe, wire: str, robot_type: int) -> None:
    try:
        spec = robot_spec(robot_type).joint(wire)
    except SpecError:
        known = ", ".join(robot_spec(robot_type).joint_names)
        raise _error(motion, keyframe, f"unknown joint {wire!r} for robot type {robot_type}; known: {known}",
                     wire, wire) from None
    if spec.perceptor != wire:
        raise _error(motion, keyframe, f"targets are keyed by wire perceptor names: use {spec.perceptor!r}, "
                     f"not {wire!r}", wire, wire)
    angle = keyframe.targets[wire].angle_rad
    name = _file_name(spec, wire, motion.source_format)
    if angle is None:
        return
    if not math.isfinite(angle):
        raise _error(motion, keyframe, f"angle must be finite, got {angle!r}", name, wire)
    if not spec.min_rad - LIMIT_TOLERANCE_RAD <= angle <= spec.max_rad + LIMIT_TOLERANCE_RAD:
        raise _error(motion, keyframe, f"{math.degrees(angle):.6g} deg is outside the joint range "
                     f"[{spec.min_deg:g}, {spec.max_deg:g}] deg of {spec.perceptor} ({spec.nao_name})", name, wire)


def validate_motion(motion: Motion, robot_type: int = 0) -> None:
    """Check ``motion`` against robot type ``robot_type`` (0-4).

    Checks: at least one keyframe; durations finite, > 0 (the first may be 0); joint keys are wire names of
    that robot type; angles finite and within the joint limits; phase names unique in XML motions;
    ``first_phase`` names a keyframe.

    Raises:
        MotionFormatError: the first problem found, with path, line and field when the motion came from a file.
    """
    if not motion.keyframes:
        raise _error(motion, None, f"motion {motion.name!r} has no keyframes", "keyframes")
    seen: set[str] = set()
    for index, keyframe in enumerate(motion.keyframes):
        _check_duration(motion, index, keyframe)
        for wire in keyframe.targets:
            _check_target(motion, keyframe, wire, robot_type)
        if motion.source_format == XML and keyframe.name in seen:
            raise _error(motion, keyframe, f"phase name {keyframe.name!r} is used twice", "name")
        seen.add(keyframe.name)
    if motion.first_phase is not None and motion.find_phase(motion.first_phase) is None:
        raise _error(motion, None, f"firstPhase {motion.first_phase!r} names no phase", "firstPhase")
