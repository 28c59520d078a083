"""The motions an agent can play, by name, with how each is played (Webots timing, turn-gain base).

Motion files live in ``motions/files/`` (type 0) and ``motions/files/type<N>/`` (a robot type's own versions,
which replace type 0's file of the same motion name). XML phase files are named by their ``low_skill``,
Webots files by their file stem. Loading happens here, at construction, never in the agent's step.
"""

from __future__ import annotations

import pickle
import tomllib
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

import motions
from motions import Motion
from motions.errors import MotionFormatError

#: The motion files shipped with the toolkit.
DEFAULT_MOTION_DIR = Path(motions.__file__).resolve().parent / "files"
#: How robot types other than 0 play the shared files of a motion folder (`_apply_type_settings`).
TYPES_FILE = "robot_types.toml"


@dataclass(frozen=True)
class WebotsTiming:
    """How a Webots motion is played (REFERENCE §6b, thesis playback).

    duration_cycles: cycles per pose (seed default 2 = 40 ms); pose_step: poses advanced per step (1 plays
    every pose, 2 every other one); use_file_times: take each pose's duration from the file's time column
    instead of ``duration_cycles``.
    """

    duration_cycles: int = 2
    pose_step: int = 1
    use_file_times: bool = False

    def __post_init__(self) -> None:
        if self.duration_cycles < 1 or self.pose_step < 1:
            raise ValueError(f"duration_cycles and pose_step must be >= 1, got {self.duration_cycles}, {self.pose_step}")


class MotionLibrary:
    """Name -> motion, plus per-motion playback settings.

    Args:
        motions: initial motions (name -> Motion).
    """

    def __init__(self, motions: Mapping[str, Motion] | None = None) -> None:
        self._motions: dict[str, Motion] = dict(motions or {})
        self.webots_timing: dict[str, WebotsTiming] = {}
        """Motion name -> Webots timing (default ``WebotsTiming()``)."""
        self.gain_bases: dict[str, str] = {}
        """Motion name -> name of the motion a gain scales from (same keyframe count); without one the gain
        scales the deviation from the motion's first keyframe."""

    def add(self, motion: Motion, name: str | None = None) -> str:
        """Add (or replace) a motion; returns the name it is known by."""
        key = name or motion.name
        self._motions[key] = motion
        return key

    def get(self, name: str) -> Motion:
        """The motion called ``name``.

        Raises:
            KeyError: no such motion (the message lists the known names).
        """
        try:
            return self._motions[name]
        except KeyError:
            raise KeyError(f"unknown motion {name!r}; known: {', '.join(sorted(self._motions)) or 'none'}") from None

    def remove(self, name: str) -> None:
        """Drop the motion called ``name`` and its playback settings (nothing if there is none)."""
        self._motions.pop(name, None)
        self.webots_timing.pop(name, None)
        self.gain_bases.pop(name, None)

    def __contains__(self, name: object) -> bool:
        return name in self._motions

    @property
    def names(self) -> list[str]:
        return sorted(self._motions)

    def timing(self, name: str) -> WebotsTiming:
        return self.webots_timing.get(name, WebotsTiming())

    def load_folder(self, folder: str | Path, pattern: Iterable[str] = ("*.xml", "*.motion")) -> list[str]:
        """Load every motion file of ``folder`` (not its subfolders); returns the names added.

        Raises:
            MotionFormatError: a malformed file (path, line, field).
        """
        added = []
        for glob in pattern:
            for path in sorted(Path(folder).glob(glob)):
                motion = _load(path)
                added.append(self.add(motion, motion.name if motion.source_format == motions.XML else path.stem))
        return added


#: Motion files read in this process: (path, mtime ns, size) -> the pickled Motion. A match builds 22 agents
#: with the same ~20 files each; a fresh copy from the pickle is ~3x cheaper than parsing the file again.
_LOADED: dict[tuple[str, int, int], bytes] = {}
_LOADED_KEPT = 512


def _load(path: Path) -> Motion:
    """``motions.load(path)``, as a fresh object each time, from the file's pickle if this process read it
    before unchanged (same modification time and size)."""
    try:
        stat = path.stat()
    except OSError:
        return motions.load(path)   # raises as it would
    key = (str(path.resolve()), stat.st_mtime_ns, stat.st_size)
    blob = _LOADED.get(key)
    if blob is not None:
        return pickle.loads(blob)
    motion = motions.load(path)
    if len(_LOADED) >= _LOADED_KEPT:
        _LOADED.clear()
    _LOADED[key] = pickle.dumps(motion, pickle.HIGHEST_PROTOCOL)
    return motion


def default_library(robot_type: int = 0, folder: str | Path | None = None, *,
                    include_withheld: bool = False) -> MotionLibrary:
    """The shipped motions for a robot type: ``motions/files`` then ``motions/files/type<N>`` on top, with the
    turn motions' gain bases and Webots timings of ``motions/files/playback.toml`` if present, and the robot
    type's constant offsets and withheld motions of ``robot_types.toml`` (shared files that type falls with are
    left out unless ``include_withheld``, to measure them).

    Raises:
        MotionFormatError: a malformed motion file, or a bad ``playback.toml`` or ``robot_types.toml`` entry.
    """
    root = Path(folder) if folder is not None else DEFAULT_MOTION_DIR
    library = MotionLibrary()
    if root.is_dir():
        library.load_folder(root)
        typed = root / f"type{robot_type}"
        if typed.is_dir():
            library.load_folder(typed)
    settings_path = root / "playback.toml"
    if settings_path.is_file():
        _apply_playback_settings(library, settings_path)
    types_path = root / TYPES_FILE
    if types_path.is_file():
        _apply_type_settings(library, robot_type, types_path, include_withheld)
    return library


def _line_of(lines: list[str], section: str, key: str | None = None) -> int | None:
    """1-based line of ``[section]`` in a TOML file's ``lines``, or of ``key`` inside it if written there."""
    line = next((i for i, row in enumerate(lines, 1) if row.strip() == f"[{section}]"), None)
    if key is not None and line is not None:
        for i, row in enumerate(lines[line:], line + 1):
            if row.lstrip().startswith("["):
                break
            if row.split("=")[0].strip() == key:
                return i
    return line


def _apply_playback_settings(library: MotionLibrary, path: Path) -> None:
    """``playback.toml``: the turn motions' gain bases and the Webots motions' timings.

    Raises:
        MotionFormatError: not TOML, or a timing entry that is no table of WebotsTiming fields (file, line, motion).
    """
    text = path.read_text(encoding="utf-8")
    try:
        settings = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise MotionFormatError(f"not valid TOML: {error}", path=str(path)) from None
    library.gain_bases.update(settings.get("gain_bases", {}))
    for name, table in settings.get("webots_timing", {}).items():
        try:
            if not isinstance(table, Mapping):
                raise ValueError(f"expected a table of WebotsTiming fields, got {table!r}")
            library.webots_timing[name] = WebotsTiming(**table)
        except (TypeError, ValueError) as error:
            raise MotionFormatError(f"[webots_timing] {name}: {error}", path=str(path),
                                    line=_line_of(text.splitlines(), "webots_timing", name), field=name) from None


def _apply_type_settings(library: MotionLibrary, robot_type: int, path: Path, include_withheld: bool) -> None:
    """``[type<N>]`` of ``TYPES_FILE``: add its ``constant_offsets`` (motion -> constant -> number) to the motions'
    XML constants, then drop its ``withheld`` motions (unless ``include_withheld``).

    Why: a robot type that plays type 0's file (no file of its own) meets the ball elsewhere with its own leg
    lengths, and may fall where type 0 stands; the spot a skill lines up for is the file's constant, and a skill
    plays a motion only if the library has it, so a type's shift and its exclusions live here instead of in
    copies of whole files.

    Raises:
        MotionFormatError: an unknown motion or constant, or a value of the wrong kind (file, line, field).
    """
    text = path.read_text(encoding="utf-8")
    lines = text.splitlines()
    try:
        settings = tomllib.loads(text).get(f"type{robot_type}", {})
    except tomllib.TOMLDecodeError as error:
        raise MotionFormatError(f"not valid TOML: {error}", path=str(path)) from None

    def error(section: str, detail: str, key: str | None = None) -> MotionFormatError:
        return MotionFormatError(f"[{section}]: {detail}", path=str(path), line=_line_of(lines, section, key),
                                 field=key)

    section = f"type{robot_type}"
    for name, offsets in settings.get("constant_offsets", {}).items():
        where = f"{section}.constant_offsets.{name}"
        if not isinstance(offsets, Mapping):
            raise error(where, f"expected a table of constant = offset, got {offsets!r}")
        if name not in library:
            raise error(where, f"no motion {name!r} for robot type {robot_type}")
        motion = library.get(name)
        constants = dict(motion.constants)
        for key, offset in offsets.items():
            if key not in constants:
                raise error(where, f"motion {name!r} has no constant {key!r} (it has "
                                   f"{', '.join(sorted(constants)) or 'none'})", key)
            if isinstance(offset, bool) or not isinstance(offset, (int, float)):
                raise error(where, f"expected a number, got {offset!r}", key)
            constants[key] += float(offset)
        motion.constants = constants   # (this library's own copy: `_load` hands out a fresh object per load)
    withheld = settings.get("withheld", [])
    if not isinstance(withheld, list) or not all(isinstance(name, str) for name in withheld):
        raise error(section, f"expected a list of motion names, got {withheld!r}", "withheld")
    for name in withheld:
        if name not in library:
            raise error(section, f"no motion {name!r} to withhold", "withheld")
        if not include_withheld:
            library.remove(name)
