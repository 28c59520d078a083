"""The editing session: one motion, its undo/redo history and the selected keyframe, plus its file.

Everything here is plain Python on the motion model: the web edge (``server.py``) and the scene drawing
(``scene.py``) call these methods and show the results. Angles are SimSpark-signed radians keyed by wire
name (``llj3``); durations are seconds. Disk access goes through ``files.py`` (fingerprints, atomic writes).

Display semantics: the pose "at" a keyframe holds every joint the keyframe does not command at its previous
value, starting from ``START_POSE`` (all hinges 0: standing straight, arms forward, the pose the physics
preview robot starts in). Playback interpolates linearly between keyframes in list order, as
``Motion.pose_at`` does, from ``START_POSE`` at t = 0.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

from kinematics import SpecError, robot_spec
from motions import WEBOTS, XML, JointTarget, Keyframe, Motion

from motion_studio.editor import structure
from motion_studio.editor.errors import EditorError
from motion_studio.editor.files import Fingerprint, fingerprint_of, format_of, read_motion, write_motion

#: Undo steps kept per session (a long slider drag counts as one).
HISTORY_LIMIT = 200
#: Duration of a keyframe made by "add" [s].
NEW_KEYFRAME_DURATION_S = 0.5
#: Joint changes below this are no change (IK results, float noise) [rad].
ANGLE_EPSILON_RAD = 1e-6


def start_pose(joint_names: tuple[str, ...] | list[str]) -> dict[str, float]:
    """Every hinge at 0: the zero pose the editor and the physics preview start from (REFERENCE §1)."""
    return {name: 0.0 for name in joint_names}


def copy_motion(motion: Motion) -> Motion:
    """A copy that shares nothing mutable with ``motion`` (targets dicts, keyframe list, constants)."""
    keyframes = [dataclasses.replace(k, targets=dict(k.targets)) for k in motion.keyframes]
    return dataclasses.replace(motion, keyframes=keyframes, constants=dict(motion.constants))


def new_motion(name: str, format: str, joint_names: tuple[str, ...]) -> Motion:
    """A one-keyframe motion at the zero pose, for a file that does not exist yet.

    XML: one phase of 500 ms listing every joint at 0. Webots: one pose at time 0 (``be there from the
    start``) with a column per joint.
    """
    targets = {name: JointTarget(0.0) for name in joint_names}
    if format == XML:
        first = Keyframe("phase1", NEW_KEYFRAME_DURATION_S, targets)
        return Motion(name, [first], source_format=XML, first_phase="phase1")
    return Motion(name, [Keyframe("Pose1", 0.0, targets)], source_format=WEBOTS, joint_order=tuple(joint_names))


@dataclass(frozen=True)
class _Snapshot:
    motion: Motion
    selected: int
    version: int


class EditorSession:
    """One open motion: edits with undo/redo, the selected keyframe, and save/save-as with conflict check.

    Args:
        motion: the motion (the session keeps and edits it; ``copy_motion`` it first if you keep yours).
        path: its file (the session saves there), or None for a motion not tied to a file yet.
        robot_type: 0-4; sets the joints, their limits and the sliders.
        fingerprint: what the file held when it was read (None: it did not exist).
    """

    def __init__(self, motion: Motion, path: Path | None = None, robot_type: int = 0,
                 fingerprint: Fingerprint | None = None) -> None:
        if not motion.keyframes:
            raise EditorError(f"motion {motion.name!r} has no keyframes; the editor needs at least one",
                              field="keyframes")
        self.spec = robot_spec(robot_type)
        self.robot_type = robot_type
        self.joint_names: tuple[str, ...] = self.spec.joint_names
        self.motion = motion
        self.path = path
        self.format = motion.source_format or (format_of(path) if path is not None else XML)
        self.fingerprint = fingerprint
        self.selected = 0
        self.notice: str | None = None
        """A note about the last edit the user should read (e.g. a phase graph left as it was), else None."""
        self._undo: list[_Snapshot] = []
        self._redo: list[_Snapshot] = []
        self._last_merge_key: str | None = None
        self._version = 0
        self._next_version = 1
        self._saved_version = 0 if fingerprint is not None else -1  # a new file starts unsaved
        self.load_warnings: tuple[str, ...] = tuple(motion.source.warnings) if motion.source else ()
        foreign = [j for j in motion.joints() if j not in self.joint_names]
        if foreign:
            self.load_warnings += (f"joints {', '.join(foreign)} are not on robot type {robot_type}: kept in the "
                                   "file, not shown (open with --type 4 for the toes)",)

    # ------------------------------------------------------------------------------------------- files
    @classmethod
    def open(cls, path: Path, robot_type: int = 0) -> EditorSession:
        """Open a motion file, or start a new motion when the file does not exist (saved on the first save).

        Raises:
            MotionFormatError: the file does not parse (path, line, field): nothing is opened.
            EditorError: a new file with an extension that names no format, or in a folder that does not
                exist. OSError: unreadable file.
        """
        path = Path(path)
        if not path.exists():
            if not path.parent.is_dir():
                raise EditorError(f"{path}: folder {path.parent} does not exist", field="path")
            format = format_of(path)
            robot_spec(robot_type)  # a bad type fails before anything is made
            return cls(new_motion(path.stem, format, robot_spec(robot_type).joint_names), path, robot_type, None)
        motion, fingerprint = read_motion(path)
        return cls(motion, path, robot_type, fingerprint)

    def save(self, **convert_options: object) -> str | None:
        """Write the motion to its file in its format; returns a warning if the file changed on disk.

        Raises:
            EditorError: no file yet (use save_as). MotionFormatError/ConversionError: cannot be written.
        """
        if self.path is None:
            raise EditorError("this motion has no file yet: use save as", field="path")
        outcome = write_motion(self.motion, self.path, self.format, self.fingerprint, **convert_options)
        self.fingerprint = outcome.fingerprint
        self._saved_version = self._version
        return outcome.warning

    def save_as(self, path: Path, format: str | None = None, lossy: bool = False,
                overwrite: bool = False) -> str | None:
        """Write to ``path`` (format from ``format``, else the extension) and continue editing that file.

        When the format changes, the written file is read back, so the session shows exactly what the file
        holds; the undo history then starts afresh (its steps belong to the other format).

        Args:
            path: the new file. format: ``"xml"`` or ``"webots"``, None = by extension.
            lossy: allow a conversion that gives something up (unroll a ``next`` cycle, drop flags and
                computed values, drop phases off the chain, round durations to whole ms).
            overwrite: replace ``path`` if it exists and is not this session's own file.

        Returns:
            A warning if ``path`` existed with other content than this session last saw there, else None.

        Raises:
            EditorError: unknown extension and no format, or ``path`` exists and ``overwrite`` is False.
                ConversionError: the motion cannot be written in
                that format (the message names the option ``lossy`` turns on).
        """
        path = Path(path)
        target_format = format or format_of(path, None)
        if target_format not in (XML, WEBOTS):
            raise EditorError(f"unknown motion format {target_format!r}; use 'xml' or 'webots'", field="format")
        options = ({"unroll_cycle": True, "drop_dynamic": True, "drop_unreachable": True}
                   if lossy and target_format == WEBOTS else {})
        if lossy and target_format == XML:
            options = {"round_durations": True}
        own_file = self.path is not None and path.resolve() == self.path.resolve()
        expected = self.fingerprint if own_file else None
        if not own_file and path.exists():
            if not overwrite:
                raise EditorError(f"{path} exists: confirm to replace it", field="overwrite")
            expected = fingerprint_of(path)  # replacing a file the user chose: no surprise, no warning
        outcome = write_motion(self.motion, path, target_format, expected, **options)
        if target_format != self.format:
            motion, fingerprint = read_motion(path)
            self.motion, self.fingerprint = motion, fingerprint
            self.selected = min(self.selected, len(motion.keyframes) - 1)
            self._undo.clear()
            self._redo.clear()
            self._last_merge_key = None
            self.notice = f"converted to {target_format}: the undo history starts here"
        else:
            self.fingerprint = outcome.fingerprint
        self.path, self.format = path, target_format
        self._saved_version = self._version
        return outcome.warning

    # ----------------------------------------------------------------------------------------- queries
    @property
    def dirty(self) -> bool:
        """Whether there are changes not saved (undoing back to the saved state counts as clean)."""
        return self._version != self._saved_version

    @property
    def version(self) -> int:
        """Identifies the motion's content: changes with every edit, comes back with undo/redo."""
        return self._version

    @property
    def can_undo(self) -> bool:
        return bool(self._undo)

    @property
    def can_redo(self) -> bool:
        return bool(self._redo)

    def keyframe_times_s(self) -> list[float]:
        """End time of each keyframe in list order [s]."""
        return self.motion.keyframe_times_s()

    def keyframe_poses(self) -> list[dict[str, float]]:
        """Per keyframe, every robot joint's angle [rad] with unlisted joints held (display semantics)."""
        previous = start_pose(self.joint_names)
        poses = []
        for keyframe in self.motion.keyframes:
            row = dict(previous)
            for name, target in keyframe.targets.items():
                if name in row and target.angle_rad is not None:
                    row[name] = target.angle_rad
            poses.append(row)
            previous = row
        return poses

    def keyframe_pose(self, index: int) -> dict[str, float]:
        """Every robot joint's angle at the end of keyframe ``index`` [rad] (unlisted joints held)."""
        self._check_index(index)
        return self.keyframe_poses()[index]

    def listed_joints(self, index: int) -> dict[str, str | None]:
        """Joints keyframe ``index`` commands with a value -> their ``computed`` name (None if plain)."""
        self._check_index(index)
        return {name: t.computed for name, t in self.motion.keyframes[index].targets.items()
                if t.angle_rad is not None}

    def pose_at(self, t_s: float) -> dict[str, float]:
        """Every robot joint's angle at time ``t_s`` of playback [rad], from ``START_POSE`` at t = 0."""
        names = set(self.motion.joints()) | set(self.joint_names)
        pose = self.motion.pose_at(max(t_s, 0.0), start_pose=start_pose(sorted(names)), hold_unlisted=True)
        return {name: (pose.get(name) or 0.0) for name in self.joint_names}

    def quantize(self, angle_rad: float) -> float:
        """The angle as the file will hold it: 0.01° steps in XML (degrees), 1e-4 rad in Webots files."""
        if self.format == XML:
            return math.radians(round(math.degrees(angle_rad), 2))
        return round(angle_rad, 4)

    # ------------------------------------------------------------------------------------------- edits
    def select(self, index: int) -> None:
        """Select keyframe ``index`` (not an edit: no undo step)."""
        self._check_index(index)
        self.selected = index

    def set_joint(self, index: int, joint: str, angle_rad: float, merge_key: str | None = None) -> float:
        """Set one joint's target in keyframe ``index``; returns the stored (quantized) angle [rad].

        Args:
            joint: wire, effector or Nao name. angle_rad: SimSpark sign, within the joint's limits.
            merge_key: consecutive edits with the same key form one undo step (one slider drag).

        Raises:
            EditorError: bad index, unknown joint, non-finite or out-of-limits angle.
        """
        self._check_index(index)
        wire = self._wire(joint)
        value = self._checked_angle(wire, angle_rad)
        self._begin(merge_key)
        self._put(self.motion.keyframes[index], wire, value)
        self.selected = index
        self._commit()
        return value

    def set_pose(self, index: int, angles_rad: Mapping[str, float], merge_key: str | None = None,
                 min_change_rad: float = ANGLE_EPSILON_RAD) -> list[str]:
        """Set every joint whose angle differs from keyframe ``index``'s pose by more than ``min_change_rad``
        (IK results: solver noise on joints the user did not mean to move stays out of the file); returns them.

        Raises:
            EditorError: bad index, unknown joint, non-finite or out-of-limits angle (nothing changed).
        """
        self._check_index(index)
        current = self.keyframe_pose(index)
        changes = {}
        for joint, angle in angles_rad.items():
            wire = self._wire(joint)
            value = self._checked_angle(wire, angle)
            if abs(value - current[wire]) > max(min_change_rad, ANGLE_EPSILON_RAD):
                changes[wire] = value
        if not changes:
            return []
        self._begin(merge_key)
        keyframe = self.motion.keyframes[index]
        for wire, value in changes.items():
            self._put(keyframe, wire, value)
        self.selected = index
        self._commit()
        return list(changes)

    def clear_joint(self, index: int, joint: str) -> None:
        """Stop commanding a joint in keyframe ``index``: XML leaves it out (it holds), Webots writes ``*``.

        Raises:
            EditorError: bad index or joint, or the keyframe does not command it.
        """
        self._check_index(index)
        wire = self._wire(joint)
        keyframe = self.motion.keyframes[index]
        if keyframe.angle_rad(wire) is None:
            raise EditorError(f"keyframe {keyframe.name!r} does not command {wire}", field="joint")
        self._begin(None)
        if self.format == XML:
            del keyframe.targets[wire]
        else:
            keyframe.targets[wire] = JointTarget(None)
        self._commit()

    def set_duration(self, index: int, duration_s: float, merge_key: str | None = None) -> None:
        """Set how long keyframe ``index`` takes to reach its pose (whole ms; only a first Webots pose may be 0).

        Raises:
            EditorError: bad index, non-finite, negative or zero (where not allowed) duration.
        """
        self._check_index(index)
        if not math.isfinite(duration_s) or duration_s < 0:
            raise EditorError(f"duration must be a finite number of ms >= 0, got {duration_s!r} s",
                              field="duration_ms")
        milliseconds = round(duration_s * 1000.0)
        if milliseconds < 1 and (self.format == XML or index > 0):
            where = "an XML phase" if self.format == XML else "a Webots pose after the first"
            raise EditorError(f"{where} lasts at least 1 ms, got {duration_s * 1000.0:g} ms", field="duration_ms")
        self._begin(merge_key)
        self.motion.keyframes[index].duration_s = milliseconds / 1000.0
        self._commit()

    def rename(self, index: int, name: str) -> None:
        """Rename keyframe ``index``; XML ``next``/``finalize``/``firstPhase`` references follow the name.

        Raises:
            EditorError: bad index, empty name, characters the format cannot hold, or a name in use (XML).
        """
        self._check_index(index)
        name = name.strip()
        if not name or any(c in name for c in ",\n\r\t") or (self.format == XML and " " in name):
            raise EditorError(f"keyframe name {name!r} must be non-empty, without commas, tabs, line breaks "
                              "(and spaces in XML)", field="name")
        old = self.motion.keyframes[index].name
        if name == old:
            return
        if self.format == XML and any(k.name == name for k in self.motion.keyframes):
            raise EditorError(f"phase name {name!r} is already used", field="name")
        self._begin(None)
        structure.rename_keyframe(self.motion, index, name)
        self._commit()

    def set_links(self, index: int, next_phase: str | None, finalize: str | None) -> None:
        """XML only: set a phase's ``next`` and ``finalize`` (None or "" = none).

        Raises:
            EditorError: not an XML motion, bad index, or a name that is no phase.
        """
        self._check_index(index)
        if self.format != XML:
            raise EditorError("next/finalize exist only in XML phase motions", field="next")
        names = {k.name for k in self.motion.keyframes}
        values = []
        for field, value in (("next", next_phase), ("finalize", finalize)):
            value = value or None
            if value is not None and value not in names:
                raise EditorError(f"{field} {value!r} names no phase; phases: {', '.join(sorted(names))}", field=field)
            values.append(value)
        self._begin(None)
        keyframe = self.motion.keyframes[index]
        keyframe.next, keyframe.finalize = values
        self._commit()

    def add_keyframe(self, after: int | None = None) -> int:
        """Insert a keyframe holding the pose of keyframe ``after`` (default: the selected one) right after it.

        XML: an empty phase (every joint holds); Webots: a pose repeating every column as it is (``*`` stays
        ``*``). Returns its index.
        """
        after = self.selected if after is None else after
        self._check_index(after)
        source = self.motion.keyframes[after]
        targets: dict[str, JointTarget] = {} if self.format == XML else dict(source.targets)
        keyframe = Keyframe(structure.unique_name(self.motion, source.name), NEW_KEYFRAME_DURATION_S, targets)
        return self._insert(after + 1, keyframe)

    def duplicate_keyframe(self, index: int | None = None) -> int:
        """Insert a copy of keyframe ``index`` (default: selected) right after it, under a new name."""
        index = self.selected if index is None else index
        self._check_index(index)
        source = self.motion.keyframes[index]
        copy = dataclasses.replace(source, name=structure.unique_name(self.motion, source.name),
                                   targets=dict(source.targets), source=None, next=None, finalize=None)
        return self._insert(index + 1, copy)

    def delete_keyframe(self, index: int | None = None) -> None:
        """Remove keyframe ``index`` (default: selected); the last remaining keyframe cannot go.

        XML: a linear ``next`` chain is relinked; elsewhere, references to the phase move to its ``next``.
        """
        index = self.selected if index is None else index
        self._check_index(index)
        if len(self.motion.keyframes) == 1:
            raise EditorError("a motion needs at least one keyframe", field="index")
        self._begin(None)
        self.notice = structure.remove_keyframe(self.motion, index)
        self.selected = min(index, len(self.motion.keyframes) - 1)
        self._commit()

    def move_keyframe(self, index: int, to_index: int) -> None:
        """Move keyframe ``index`` to position ``to_index`` (durations travel with their keyframes).

        XML: a linear ``next`` chain is relinked to the new order; another graph is left as it was.
        """
        self._check_index(index)
        self._check_index(to_index)
        if index == to_index:
            return
        self._begin(None)
        self.notice = structure.move_keyframe(self.motion, index, to_index)
        self.selected = to_index
        self._commit()

    def mirror_keyframe(self, index: int | None = None) -> None:
        """Replace keyframe ``index`` (default: selected) by its left/right mirror image (``motions.mirror``)."""
        index = self.selected if index is None else index
        self._check_index(index)
        self._begin(None)
        structure.mirror_keyframe(self.motion, index)
        self._commit()

    def mirror_motion(self) -> None:
        """Replace every keyframe by its left/right mirror image."""
        mirrored = self.motion.mirrored()
        self._begin(None)
        self.motion = copy_motion(dataclasses.replace(mirrored, source=self.motion.source))
        self._commit()

    def undo(self) -> None:
        """Go back one edit (a slider drag counts as one). Raises EditorError when there is none."""
        if not self._undo:
            raise EditorError("nothing to undo", field="undo")
        self._redo.append(_Snapshot(self.motion, self.selected, self._version))
        self._restore(self._undo.pop())

    def redo(self) -> None:
        """Re-apply the last undone edit. Raises EditorError when there is none."""
        if not self._redo:
            raise EditorError("nothing to redo", field="redo")
        self._undo.append(_Snapshot(self.motion, self.selected, self._version))
        self._restore(self._redo.pop())

    # ----------------------------------------------------------------------------------------- helpers
    def _restore(self, snapshot: _Snapshot) -> None:
        self.motion = snapshot.motion
        self.selected = min(snapshot.selected, len(self.motion.keyframes) - 1)
        self._version = snapshot.version
        self._last_merge_key = None
        self.notice = None

    def _begin(self, merge_key: str | None) -> None:
        """Record the state before an edit, unless it continues the previous edit's gesture (same key)."""
        self.notice = None
        if merge_key is None or merge_key != self._last_merge_key or not self._undo:
            self._undo.append(_Snapshot(copy_motion(self.motion), self.selected, self._version))
            del self._undo[:-HISTORY_LIMIT]
        self._redo.clear()
        self._last_merge_key = merge_key

    def _commit(self) -> None:
        self._version = self._next_version
        self._next_version += 1

    def _check_index(self, index: int) -> None:
        count = len(self.motion.keyframes)
        if isinstance(index, bool) or not isinstance(index, int) or not 0 <= index < count:
            raise EditorError(f"keyframe index must be 0..{count - 1}, got {index!r}", field="index")

    def _wire(self, joint: str) -> str:
        try:
            wire = self.spec.joint(joint).perceptor
        except SpecError as error:
            raise EditorError(str(error), field="joint") from None
        return wire

    def _checked_angle(self, wire: str, angle_rad: float) -> float:
        if isinstance(angle_rad, bool) or not isinstance(angle_rad, (int, float)) or not math.isfinite(angle_rad):
            raise EditorError(f"{wire}: angle must be a finite number, got {angle_rad!r}", field="angle")
        spec = self.spec.joint(wire)
        tolerance = 1e-9
        if not spec.min_rad - tolerance <= angle_rad <= spec.max_rad + tolerance:
            raise EditorError(f"{wire} ({spec.nao_name}): {math.degrees(angle_rad):.2f} deg is outside its limits "
                              f"{spec.min_deg:g}..{spec.max_deg:g} deg", field="angle")
        return min(max(self.quantize(angle_rad), spec.min_rad), spec.max_rad)

    def _put(self, keyframe: Keyframe, wire: str, value: float) -> None:
        structure.put_target(self.motion, keyframe, wire, value)

    def _insert(self, position: int, keyframe: Keyframe) -> int:
        self._begin(None)
        self.notice = structure.insert_keyframe(self.motion, position, keyframe)
        self.selected = position
        self._commit()
        return position
