"""Conversion between the XML phase format and Webots motions, where their meanings overlap.

XML -> Webots: Webots plays one pose sequence, once, with no flags and no run-time values, so the XML
motion must be (or be cut down to) the linear ``next`` chain from ``firstPhase``. Each phase becomes a pose
at the phase's end time. An XML phase holds the joints it does not list (velocity 0), so a pose repeats the
joint's previous target; a joint not yet listed by any phase is ``*`` (not commanded). Cycles, flags,
computed values and phases off the chain are errors unless an option says what to give up.

Webots -> XML: each pose becomes a phase that moves to it, ``next`` links them in time order and the last
ends the motion; ``*`` values leave the joint out of that phase; absolute times become durations in whole
milliseconds. A first pose at time 0 ("be there from the start") becomes a phase of ``zero_time_phase_ms``
(one 20 ms server cycle by default), since an XML phase must last at least 1 ms: the later phases keep their
durations, so the XML motion is that much longer.
"""

from __future__ import annotations

import dataclasses
import logging

from motions.errors import ConversionError
from motions.joints import canonical_sorted
from motions.model import SERVER_CYCLE_MS, WEBOTS, XML, JointTarget, Keyframe, Motion
from motions.numbers import is_whole

logger = logging.getLogger(__name__)



def _next_chain(motion: Motion, unroll_cycle: bool) -> list[Keyframe]:
    """The phases played while the motion stays requested, each once; a cycle is an error unless unrolled."""
    chain: list[Keyframe] = []
    current: Keyframe | None = motion.start_phase()
    while current is not None:
        if any(current is seen for seen in chain):
            if not unroll_cycle:
                loop = " -> ".join([k.name for k in chain] + [current.name])
                raise ConversionError(f"next={current.name!r} closes a cycle ({loop}); a Webots motion cannot "
                                      "loop: pass unroll_cycle=True to write one pass of the cycle", field="next",
                                      element=f"phase {chain[-1].name!r}")
            break
        chain.append(current)
        current = motion.find_phase(current.next)
    return chain


def _check_dynamic(chain: list[Keyframe], drop_dynamic: bool) -> None:
    if drop_dynamic:
        return
    for keyframe in chain:
        for attribute, value in (("skipIfFlag", keyframe.skip_if_flag), ("setFlagTrue", keyframe.set_flag_true),
                                 ("setFlagFalse", keyframe.set_flag_false)):
            if value is not None:
                raise ConversionError(f"Webots motions have no flags ({attribute}={value!r}); pass "
                                      "drop_dynamic=True to play every phase unconditionally", field=attribute,
                                      element=f"phase {keyframe.name!r}")
        for wire, target in keyframe.targets.items():
            if target.computed is not None:
                raise ConversionError(f"Webots motions have no run-time values (computed={target.computed!r} on "
                                      f"{wire}); pass drop_dynamic=True to use the 'end' fallback", field="computed",
                                      element=f"phase {keyframe.name!r}")


def to_webots(motion: Motion, *, unroll_cycle: bool = False, drop_dynamic: bool = False,
              drop_unreachable: bool = False) -> Motion:
    """The Webots equivalent of ``motion`` (a copy; Webots and code-built motions pass through).

    Args:
        motion: an XML phase motion (or any motion without phase features).
        unroll_cycle: write one pass of a ``next`` cycle instead of failing.
        drop_dynamic: ignore flags and use the ``end`` fallback of computed values instead of failing.
        drop_unreachable: leave out phases off the ``next`` chain (stop sequences reached through
            ``finalize``) instead of failing.

    Raises:
        ConversionError: a cycle, a flag, a computed value or a phase off the chain, naming the option.
    """
    if motion.source_format != XML and not any(k.uses_phase_features() for k in motion.keyframes):
        return dataclasses.replace(motion, source_format=WEBOTS, keyframes=list(motion.keyframes))
    chain = _next_chain(motion, unroll_cycle)
    off_chain = [k.name for k in motion.keyframes if not any(k is c for c in chain)]
    if off_chain and not drop_unreachable:
        raise ConversionError(f"phases {', '.join(map(repr, off_chain))} are not on the next chain from firstPhase "
                              f"{chain[0].name!r} (reached only through finalize, or not at all); a Webots motion "
                              "is one pose sequence: pass drop_unreachable=True to leave them out", field="phase",
                              element=f"phase {off_chain[0]!r}")
    _check_dynamic(chain, drop_dynamic)
    joints = canonical_sorted(name for k in chain for name, t in k.targets.items() if t.angle_rad is not None)
    held: dict[str, float | None] = {name: None for name in joints}
    keyframes = []
    for phase in chain:
        for name in joints:
            angle = phase.angle_rad(name)
            if angle is not None:
                held[name] = angle  # an unlisted joint keeps its target: XML gives it velocity 0
        keyframes.append(Keyframe(phase.name, phase.duration_s, {n: JointTarget(held[n]) for n in joints}))
    if motion.header_comments:
        logger.warning("motion %r: header comments dropped, Webots files have no comments", motion.name)
    return Motion(motion.name, keyframes, source_format=WEBOTS, joint_order=tuple(joints))


def _unique_names(names: list[str]) -> list[str]:
    """Pose names may repeat in Webots; phase names may not: the second ``Pose1`` becomes ``Pose1_2``."""
    seen: set[str] = set()
    result = []
    for name in names:
        candidate, suffix = name, 2
        while candidate in seen:
            candidate, suffix = f"{name}_{suffix}", suffix + 1
        seen.add(candidate)
        result.append(candidate)
    return result


def _durations_ms(motion: Motion, round_durations: bool, zero_time_phase_ms: int) -> list[int]:
    durations, worst_error_ms = [], 0.0
    for index, keyframe in enumerate(motion.keyframes):
        milliseconds = keyframe.duration_s * 1000.0
        if index == 0 and milliseconds == 0.0:
            durations.append(zero_time_phase_ms)
            continue
        if not is_whole(milliseconds):
            if not round_durations:
                raise ConversionError(f"XML durations are whole milliseconds, this keyframe lasts {milliseconds!r} ms;"
                                      " pass round_durations=True to round", field="duration",
                                      element=f"phase {keyframe.name!r}")
            worst_error_ms = max(worst_error_ms, abs(milliseconds - round(milliseconds)))
        durations.append(max(1, round(milliseconds)))
    if worst_error_ms > 0.0:
        logger.warning("motion %r: durations rounded to whole ms (largest change %.3f ms)", motion.name, worst_error_ms)
    return durations


def to_xml(motion: Motion, *, name: str | None = None, round_durations: bool = False,
           zero_time_phase_ms: int = SERVER_CYCLE_MS) -> Motion:
    """The XML phase equivalent of ``motion`` (a copy; XML motions pass through).

    Args:
        motion: a Webots (or code-built) motion.
        name: motion name to use; default ``motion.name``.
        round_durations: round durations that are not whole milliseconds (the largest change is logged)
            instead of failing.
        zero_time_phase_ms: duration of the phase made from a first pose at time 0.

    Raises:
        ConversionError: a duration that is not whole ms (without ``round_durations``).
    """
    if motion.source_format == XML:
        return dataclasses.replace(motion, keyframes=list(motion.keyframes), name=name or motion.name)
    if zero_time_phase_ms < 1:
        raise ConversionError(f"zero_time_phase_ms must be >= 1, got {zero_time_phase_ms}", field="zero_time_phase_ms")
    durations = _durations_ms(motion, round_durations, zero_time_phase_ms)
    names = _unique_names([k.name for k in motion.keyframes])
    keyframes = []
    for index, (keyframe, phase_name, duration_ms) in enumerate(zip(motion.keyframes, names, durations)):
        targets = {wire: t for wire, t in keyframe.targets.items() if t.angle_rad is not None}
        following = names[index + 1] if index + 1 < len(names) else None
        keyframes.append(Keyframe(phase_name, duration_ms / 1000.0, targets, next=following))
    return Motion(name if name is not None else motion.name, keyframes, source_format=XML, first_phase=names[0],
                  constants=dict(motion.constants), header_comments=motion.header_comments)


def convert(motion: Motion, target_format: str, **options: object) -> Motion:
    """``to_xml`` or ``to_webots`` by format name (``"xml"`` or ``"webots"``), passing ``options`` on."""
    if target_format == XML:
        return to_xml(motion, **options)  # type: ignore[arg-type]
    if target_format == WEBOTS:
        return to_webots(motion, **options)  # type: ignore[arg-type]
    raise ConversionError(f"unknown motion format {target_format!r}; known: {XML!r}, {WEBOTS!r}", field="format")
