"""Keyframe-list edits on a motion: insert, remove, move, mirror, keeping the XML phase graph consistent.

Pure functions that change the motion in place and return a note for the user (None when there is
nothing to say). An XML motion whose ``next`` chain follows the list order (``firstPhase`` is the first phase,
each phase's ``next`` the following one) is relinked after a change so that it still plays in list order; its
last phase keeps its ``next`` (a walk cycle), which follows the first phase if it pointed there. Any other
phase graph is left as it was, and the note says so. Webots motions have no graph: their pose times follow
from the durations, and only the first pose may have duration 0 (time 0).
"""

from __future__ import annotations

import dataclasses
import re

from motions import WEBOTS, XML, JointTarget, Keyframe, Motion
from motions.joints import CANONICAL_JOINT_ORDER

#: Duration given to a keyframe that cannot keep a zero duration (it no longer comes first) [s].
DEFAULT_DURATION_S = 0.5
_NAME_SUFFIX = re.compile(r"^(.*?)(\d*)$")
_FIRST = "\0first"  # a chain tail that cycles back to whichever phase comes first


def unique_name(motion: Motion, base: str) -> str:
    """``base`` with the first number suffix no keyframe uses (``walk3`` -> ``walk2``, ``walk4``...)."""
    stem = _NAME_SUFFIX.match(base).group(1) or "phase"  # type: ignore[union-attr]
    used = {k.name for k in motion.keyframes}
    number = 2
    while f"{stem}{number}" in used:
        number += 1
    return f"{stem}{number}"


def insert_keyframe(motion: Motion, position: int, keyframe: Keyframe) -> str | None:
    """Insert ``keyframe`` at ``position`` of the list."""
    linear, tail = _chain_state(motion)
    motion.keyframes.insert(position, keyframe)
    _fix_zero_durations(motion)
    if linear:
        _relink(motion, tail)
        return None
    if motion.source_format == XML:
        return (f"the phase graph is not a chain: set next/finalize of {keyframe.name!r} and of the phase "
                "before it by hand")
    return None


def remove_keyframe(motion: Motion, index: int) -> str | None:
    """Remove keyframe ``index`` (the caller keeps at least one). References to it move to its ``next``."""
    linear, tail = _chain_state(motion)
    removed = motion.keyframes.pop(index)
    if index == 0 and motion.source_format == WEBOTS:
        motion.keyframes[0].duration_s += removed.duration_s  # the later poses keep their absolute times
    if linear:
        _relink(motion, tail if tail != removed.name else None)
        return None
    if motion.source_format != XML:
        return None
    successor = removed.next if removed.next != removed.name else None
    for keyframe in motion.keyframes:
        keyframe.next = successor if keyframe.next == removed.name else keyframe.next
        keyframe.finalize = keyframe.name if keyframe.finalize == removed.name else keyframe.finalize
    if motion.first_phase == removed.name:
        motion.first_phase = successor or motion.keyframes[0].name
    return f"references to {removed.name!r} now go to {successor!r} (the phase graph is not a chain)"


def move_keyframe(motion: Motion, index: int, to_index: int) -> str | None:
    """Move keyframe ``index`` to ``to_index``; durations travel with their keyframes."""
    linear, tail = _chain_state(motion)
    keyframes = motion.keyframes
    keyframes.insert(to_index, keyframes.pop(index))
    _fix_zero_durations(motion)
    if linear:
        _relink(motion, tail)
        return None
    if motion.source_format == XML:
        return "the phase graph is not a chain: next/finalize left as they were"
    return None


def mirror_keyframe(motion: Motion, index: int) -> None:
    """Replace keyframe ``index`` by its left/right mirror image (``motions.mirror``)."""
    single = Motion(motion.name, [motion.keyframes[index]], source_format=motion.source_format)
    mirrored = single.mirrored().keyframes[0]
    motion.keyframes[index] = dataclasses.replace(mirrored, targets=dict(mirrored.targets))
    if motion.joint_order is not None:
        missing = tuple(j for j in mirrored.targets if j not in motion.joint_order)
        motion.joint_order = motion.joint_order + missing


def rename_keyframe(motion: Motion, index: int, name: str) -> None:
    """Rename keyframe ``index``; XML ``next``/``finalize``/``firstPhase`` references follow the new name."""
    old = motion.keyframes[index].name
    motion.keyframes[index].name = name
    if motion.source_format == XML:
        for keyframe in motion.keyframes:
            keyframe.next = name if keyframe.next == old else keyframe.next
            keyframe.finalize = name if keyframe.finalize == old else keyframe.finalize
        if motion.first_phase == old:
            motion.first_phase = name


def put_target(motion: Motion, keyframe: Keyframe, wire: str, angle_rad: float) -> None:
    """Set one joint's target in ``keyframe`` (a keyframe of ``motion``), keeping its ``computed`` name.

    A joint the keyframe did not list yet goes in canonical order if the keyframe's list was canonical (so a
    written phase stays readable), else last; a Webots motion gains the column if it lacked it.
    """
    old = keyframe.targets.get(wire)
    target = JointTarget(angle_rad, old.computed if old is not None else None)
    if old is not None:
        keyframe.targets[wire] = target
    else:
        rank = {name: i for i, name in enumerate(CANONICAL_JOINT_ORDER)}
        items = list(keyframe.targets.items())
        ranks = [rank.get(name, len(rank)) for name, _ in items]
        position = len(items)
        if ranks == sorted(ranks):
            position = next((i for i, r in enumerate(ranks) if r > rank[wire]), len(items))
        items.insert(position, (wire, target))
        keyframe.targets.clear()
        keyframe.targets.update(items)
    if motion.source_format == WEBOTS and motion.joint_order is not None and wire not in motion.joint_order:
        motion.joint_order = motion.joint_order + (wire,)


def _fix_zero_durations(motion: Motion) -> None:
    for position, keyframe in enumerate(motion.keyframes):
        if position > 0 and keyframe.duration_s <= 0:
            keyframe.duration_s = DEFAULT_DURATION_S  # a zero-time pose can only come first


def _chain_state(motion: Motion) -> tuple[bool, str | None]:
    """(whether the XML ``next`` chain follows list order, where the last phase's ``next`` goes: its name, or
    ``_FIRST`` when it pointed at the first phase)."""
    keyframes = motion.keyframes
    if motion.source_format != XML or not keyframes:
        return False, None
    if motion.first_phase not in (None, keyframes[0].name):
        return False, None
    linear = all(keyframes[i].next == keyframes[i + 1].name for i in range(len(keyframes) - 1))
    tail = keyframes[-1].next
    return linear, (_FIRST if tail is not None and tail == keyframes[0].name else tail)


def _relink(motion: Motion, tail: str | None) -> None:
    """Make the ``next`` chain follow list order again, ending in ``tail`` (see _chain_state)."""
    keyframes = motion.keyframes
    names = {k.name for k in keyframes}
    for current, following in zip(keyframes, keyframes[1:]):
        current.next = following.name
    if tail == _FIRST:
        tail = keyframes[0].name
    keyframes[-1].next = tail if tail in names else None
    if motion.first_phase is not None:
        motion.first_phase = keyframes[0].name
