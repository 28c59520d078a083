"""The motion model shared by both file formats: a named sequence of keyframes over the Nao's hinges.

One model serves the XML phase format and Webots ``.motion`` files so that the controller, the editor and
the tuner see one thing. Inside, angles are SimSpark-signed radians and times are seconds; degrees (XML) and
real-Nao signs (Webots) exist only in the files and are converted by the readers and writers.

A keyframe is reached at the *end* of its duration: keyframe i ends at ``keyframe_times_s()[i]``, and during
its duration the joints travel from the previous keyframe's targets to its own. For an XML phase the duration
is the phase length; for a Webots pose it is the time since the previous pose (for the first pose, its
absolute time, so a first pose at time 0 has duration 0: "be at this pose from the start").
"""

from __future__ import annotations

import bisect
import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field

from motions.errors import MotionFormatError
from motions.joints import canonical_sorted

#: One server cycle [ms] (REFERENCE §1): the motions room's one definition of it (agent.protocol.constants.CYCLE_S
#: is the protocol's; this room may not import the agent's).
SERVER_CYCLE_MS = 20
XML = "xml"
WEBOTS = "webots"
FORMATS: tuple[str, ...] = (XML, WEBOTS)
#: Motion constant bounding the joint speed of the move into a motion's first keyframe [rad/s] (written by the
#: stand-up generator, read by ``agent.motion.controller`` in place of its own bound).
BLEND_SPEED_CONSTANT = "blend_speed_rad_s"


@dataclass(frozen=True)
class JointTarget:
    """The target of one joint in one keyframe.

    angle_rad: target angle, SimSpark sign, radians; None = not commanded (Webots ``*``).
    computed: XML only: name of a run-time value that replaces ``angle_rad`` when the controller knows it
        (``headAngle1``, ``left_walk_lean_lle3``, REFERENCE §6a/§7.2); ``angle_rad`` is then the fallback.
    """

    angle_rad: float | None
    computed: str | None = None

    @classmethod
    def from_deg(cls, angle_deg: float | None, computed: str | None = None) -> JointTarget:
        """A target given in degrees (as XML files and the wire use them)."""
        return cls(None if angle_deg is None else math.radians(angle_deg), computed)

    @property
    def angle_deg(self) -> float | None:
        """The target in degrees, None if not commanded."""
        return None if self.angle_rad is None else math.degrees(self.angle_rad)


@dataclass(frozen=True)
class KeyframeSource:
    """How a keyframe was written in its file, so that writing it again changes only what was edited.

    Writers reuse a text only while it still reads as the model's current value, so an edited value is
    written fresh and a stale text can never leak. Not part of equality.

    line: line of the ``<phase>`` element or the Webots pose line.
    attribute_order: XML phase attribute names in file order.
    duration_text: XML ``<duration>`` text; time_text: Webots time token (``00:00:400`` or ``400``).
    value_texts: wire name -> number text as written (degrees in XML, real-Nao radians in Webots).
    target_lines: wire name -> line of the XML effector element.
    extra_attributes: XML phase attributes outside REFERENCE §6a (FIIT's ``opposite``), in file order: ignored by
        playback, written back.
    """

    line: int | None = None
    attribute_order: tuple[str, ...] = ()
    duration_text: str | None = None
    time_text: str | None = None
    value_texts: Mapping[str, str] = field(default_factory=dict)
    target_lines: Mapping[str, int] = field(default_factory=dict)
    extra_attributes: tuple[tuple[str, str], ...] = ()


@dataclass
class Keyframe:
    """One XML phase or one Webots pose.

    name: phase name (unique in an XML file) or Webots pose name.
    duration_s: time from the previous keyframe's end to this keyframe's end, seconds (>= 0; only the first
        keyframe may be 0).
    targets: wire perceptor name (``llj3``) -> target; in file order. An XML phase lists only the joints it
        moves (unlisted joints hold still); a Webots pose has every column, None for ``*``.
    next, finalize: XML successor names (REFERENCE §6a; see ``Motion.successor``).
    is_final: XML ``isFinal``; None when the attribute is absent (so writing gives back the same file).
    skip_if_flag, set_flag_true, set_flag_false: XML flag attributes, None when absent.
    source: file layout details for exact re-writing; not part of equality.
    """

    name: str
    duration_s: float
    targets: dict[str, JointTarget] = field(default_factory=dict)
    next: str | None = None
    finalize: str | None = None
    is_final: bool | None = None
    skip_if_flag: str | None = None
    set_flag_true: str | None = None
    set_flag_false: str | None = None
    source: KeyframeSource | None = field(default=None, compare=False, repr=False)

    def angle_rad(self, joint: str) -> float | None:
        """Target of ``joint`` (wire name) in this keyframe; None if not listed or not commanded."""
        target = self.targets.get(joint)
        return None if target is None else target.angle_rad

    def uses_phase_features(self) -> bool:
        """Whether this keyframe uses anything only the XML phase format can express."""
        return (any(t.computed is not None for t in self.targets.values())
                or any(v is not None for v in (self.next, self.finalize, self.is_final, self.skip_if_flag,
                                               self.set_flag_true, self.set_flag_false)))


@dataclass(frozen=True)
class UnknownColumn:
    """A Webots column whose joint name the Nao does not have; kept only to write the file back.

    index: position among the value columns (0-based); name: the column header; texts: one token per pose.
    """

    index: int
    name: str
    texts: tuple[str, ...]


@dataclass(frozen=True)
class MotionSource:
    """Where a motion was read from and how its file was laid out; not part of equality.

    path: the file as the caller named it (``"<string>"`` for text); used in error messages.
    line_ending / final_newline: kept so a CRLF file or one without a last newline is written back as such.
    xml_declaration: the declaration text as written, None if the file had none.
    root_attributes: attributes of ``<robot>`` in file order (FIIT files carry ``xsi:noNamespaceSchemaLocation``).
    constant_texts: constant name -> value text as written.
    unknown_columns: Webots columns with an unknown joint name (ignored by playback, kept for writing).
    warnings: non-fatal problems found while reading (unknown ``next`` phase, ignored column, ...).
    low_skill_notes: FIIT's descriptive elements in ``<low_skills>`` (``type``, ``author``, ``extendedFromMove``,
        ``description``) as (tag, text, inside ``<low_skill>``) in file order: not played, written back.
    """

    path: str | None = None
    line_ending: str = "\n"
    final_newline: bool = True
    xml_declaration: str | None = None
    root_attributes: tuple[tuple[str, str], ...] = ()
    constant_texts: Mapping[str, str] = field(default_factory=dict)
    unknown_columns: tuple[UnknownColumn, ...] = ()
    warnings: tuple[str, ...] = ()
    low_skill_notes: tuple[tuple[str, str, bool], ...] = ()


@dataclass
class Motion:
    """A motion: keyframes in file order plus what the XML phase format adds.

    name: motion name (XML ``low_skill@name``; for Webots the file stem).
    keyframes: phases or poses in file order.
    source_format: ``"xml"``, ``"webots"`` or None for a motion built in code.
    first_phase: XML ``firstPhase``; None means the first keyframe.
    constants: XML named numbers, which ``end`` and ``<duration>`` texts may use in arithmetic
        (``strafe_leg_crouch+30``, as FIIT's files do; ``motions.expressions``).
    joint_order: Webots column order (wire names); None = canonical order of the joints used.
    header_comments: XML comments before ``<robot>`` (how the file was made, DESIGN.md); Webots files have
        no comments.
    source: file layout details for exact re-writing; not part of equality.
    """

    name: str
    keyframes: list[Keyframe]
    source_format: str | None = None
    first_phase: str | None = None
    constants: dict[str, float] = field(default_factory=dict)
    joint_order: tuple[str, ...] | None = None
    header_comments: tuple[str, ...] = ()
    source: MotionSource | None = field(default=None, compare=False, repr=False)

    # ----------------------------------------------------------------------------------------- time axis
    @property
    def duration_s(self) -> float:
        """Total time of the keyframes in list order (for Webots: the last pose's time), seconds."""
        times = self.keyframe_times_s()
        return times[-1] if times else 0.0

    def keyframe_times_s(self) -> list[float]:
        """Absolute end time of each keyframe in list order, seconds (Webots: the pose times)."""
        times, total = [], 0.0
        for keyframe in self.keyframes:
            total += keyframe.duration_s
            times.append(total)
        return times

    def joints(self) -> list[str]:
        """Wire names of ``joint_order`` and of every joint any keyframe lists (those in canonical order)."""
        used = {name for k in self.keyframes for name in k.targets}
        ordered = list(dict.fromkeys(self.joint_order or ()))
        return ordered + [j for j in canonical_sorted(used) if j not in ordered]

    def pose_at(self, t_s: float, *, start_pose: Mapping[str, float] | None = None,
                hold_unlisted: bool | None = None) -> dict[str, float | None]:
        """Joint targets at time ``t_s`` by linear interpolation between keyframes, as Webots plays them.

        Keyframes are taken in list order (for XML: file order, not the ``next`` chain; see ``play_order``).
        Before the first keyframe its values apply, after the last its values stay. A joint that is None at
        either end of the current interval is None (not commanded), as Webots does for ``*``.

        Args:
            t_s: time since the motion started, seconds.
            start_pose: wire name -> angle (rad) at t = 0; if given, the first interval moves from it to the
                first keyframe, as an XML phase moves from the robot's current pose.
            hold_unlisted: whether a joint a keyframe does not command keeps its previous target. Default:
                True for XML (an unlisted joint gets velocity 0), False otherwise (Webots ``*``).

        Returns:
            wire name -> SimSpark-signed angle in radians or None, for every joint of ``joints()``.
            ``computed`` targets contribute their fallback ``angle_rad``.
        """
        if not self.keyframes:
            return {}
        hold = self.source_format == XML if hold_unlisted is None else hold_unlisted
        names = self.joints()
        rows = self._resolved_rows(names, start_pose, hold)
        times = self.keyframe_times_s()
        # As Webots' motion.c: from the last pose's time on, its values; at an inner pose's exact time, the
        # interval that ends there (so a '*' before it still leaves the joint uncommanded).
        if t_s >= times[-1]:
            return dict(rows[-1])
        index = bisect.bisect_left(times, t_s)
        end_row = rows[index]
        if index == 0:
            if start_pose is None:
                return dict(end_row)
            start_row: Mapping[str, float | None] = {n: start_pose.get(n) for n in names}
            start_t, end_t = 0.0, times[0]
        else:
            start_row, start_t, end_t = rows[index - 1], times[index - 1], times[index]
        if end_t <= start_t:
            return dict(end_row)
        fraction = min(max((t_s - start_t) / (end_t - start_t), 0.0), 1.0)
        pose: dict[str, float | None] = {}
        for name in names:
            a, b = start_row[name], end_row[name]
            pose[name] = None if a is None or b is None else (b if fraction == 1.0 else a + fraction * (b - a))
        return pose

    def _resolved_rows(self, names: list[str], start_pose: Mapping[str, float] | None,
                       hold: bool) -> list[dict[str, float | None]]:
        """Per keyframe, the angle of every joint; with ``hold``, unlisted joints carry the previous value."""
        rows: list[dict[str, float | None]] = []
        previous: dict[str, float | None] = {n: (start_pose or {}).get(n) for n in names}
        for keyframe in self.keyframes:
            row = {}
            for name in names:
                value = keyframe.angle_rad(name)
                row[name] = previous[name] if value is None and hold else value
            rows.append(row)
            previous = row
        return rows

    # ----------------------------------------------------------------------------------- XML phase graph
    def find_phase(self, name: str | None) -> Keyframe | None:
        """The keyframe called ``name`` (the first one if names repeat), None if there is none."""
        if name is None:
            return None
        for keyframe in self.keyframes:
            if keyframe.name == name:
                return keyframe
        return None

    def phase(self, name: str) -> Keyframe:
        """The keyframe called ``name``.

        Raises:
            MotionFormatError: no keyframe has that name (the message lists the names there are).
        """
        found = self.find_phase(name)
        if found is None:
            known = ", ".join(repr(k.name) for k in self.keyframes)
            raise MotionFormatError(f"motion {self.name!r} has no phase {name!r}; phases: {known}",
                                    path=self.source.path if self.source else None, field="phase")
        return found

    def start_phase(self) -> Keyframe:
        """The phase playback starts with: ``first_phase``, or the first keyframe when that is None."""
        if self.first_phase is None:
            if not self.keyframes:
                raise MotionFormatError(f"motion {self.name!r} has no keyframes", field="keyframes")
            return self.keyframes[0]
        return self.phase(self.first_phase)

    def successor(self, phase: str | Keyframe, requested_same_motion: bool) -> Keyframe | None:
        """The phase that follows ``phase``, or None when the motion ends after it (REFERENCE §6a).

        While the same motion is still requested, ``next`` is followed (cycles allowed). If a different
        motion is requested and the phase has ``finalize``, that phase follows instead, and a ``finalize``
        naming the phase itself ends the motion here; without ``finalize``, ``next`` is followed. A name
        that matches no phase ends the motion (the reader has warned about it).
        """
        current = self.phase(phase) if isinstance(phase, str) else phase
        if not requested_same_motion and current.finalize is not None:
            if current.finalize == current.name:
                return None
            return self.find_phase(current.finalize)
        return self.find_phase(current.next)

    def play_order(self) -> list[Keyframe]:
        """Phases in the order they play while the motion stays requested: the ``next`` chain from the start
        phase, each phase once (a cycle is listed once and then stops)."""
        order: list[Keyframe] = []
        seen: set[int] = set()
        current: Keyframe | None = self.start_phase()
        while current is not None and id(current) not in seen:
            order.append(current)
            seen.add(id(current))
            current = self.successor(current, requested_same_motion=True)
        return order

    # ------------------------------------------------------------------------------------- transforms
    def mirrored(self) -> Motion:
        """The left/right mirror image (see ``motions.mirror``): mirroring twice gives the motion back."""
        from motions.mirror import mirrored_motion

        return mirrored_motion(self)

    def time_scaled(self, factor: float) -> Motion:
        """A copy with every duration multiplied by ``factor`` (> 0), e.g. 1.35 for the walk slowdown (§7.2)."""
        if not (math.isfinite(factor) and factor > 0.0):
            raise ValueError(f"time scale factor must be a finite number > 0, got {factor!r}")
        frames = [dataclasses.replace(k, duration_s=k.duration_s * factor, source=None) for k in self.keyframes]
        return dataclasses.replace(self, keyframes=frames)

    def validate(self, robot_type: int = 0) -> None:
        """Check joint names, finite angles within the joint limits, durations and phase names.

        Raises:
            MotionFormatError: the first problem found, with the file, line and field when known.
        """
        from motions.validation import validate_motion

        validate_motion(self, robot_type)
