"""The disk edge of the editor: read a motion file with a fingerprint, write one atomically with conflict check.

Two tabs (or a tab and another program) may edit one file. Each session remembers the fingerprint of the
bytes it last read or wrote; a save compares it with the file on disk, writes anyway (last save wins) and
returns a warning when someone else changed the file in between. Writes go to a temporary file in the same
folder and are moved over the target with ``os.replace``, so no reader ever sees half a file.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import tempfile
from dataclasses import dataclass
from pathlib import Path

from motions import Motion, MotionFormatError, dumps, loads
from motions.io import format_for_path

from motion_studio.editor.errors import EditorError


@dataclass(frozen=True)
class Fingerprint:
    """What a file held when we last saw it: SHA-256 of its bytes, and its mtime (ns) for messages."""

    sha256: str
    mtime_ns: int


@dataclass(frozen=True)
class SaveOutcome:
    """A finished save: the new fingerprint, and a warning when the file had changed on disk (else None)."""

    fingerprint: Fingerprint
    warning: str | None


def fingerprint_of(path: Path) -> Fingerprint | None:
    """The file's fingerprint, None if it does not exist."""
    try:
        data = path.read_bytes()
        mtime_ns = path.stat().st_mtime_ns
    except FileNotFoundError:
        return None
    return Fingerprint(hashlib.sha256(data).hexdigest(), mtime_ns)


def format_of(path: Path, fallback: str | None = None) -> str:
    """``"xml"`` / ``"webots"`` from the extension (``.xml`` / ``.motion``), else ``fallback``.

    Raises:
        EditorError: unknown extension and no fallback.
    """
    found = format_for_path(path) or fallback
    if found is None:
        raise EditorError(f"{path}: unknown motion file extension {path.suffix!r}; use .xml (XML phase) or "
                          ".motion (Webots)", field="path")
    return found


def read_motion(path: Path) -> tuple[Motion, Fingerprint]:
    """Load a motion file and the fingerprint of the very bytes it was parsed from.

    Raises:
        MotionFormatError: the file is not UTF-8 or breaks its format (path, line, field).
        OSError: it cannot be read (FileNotFoundError when it does not exist).
    """
    data = path.read_bytes()
    fingerprint = Fingerprint(hashlib.sha256(data).hexdigest(), path.stat().st_mtime_ns)
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as error:
        line = data[: error.start].count(b"\n") + 1
        raise MotionFormatError(f"not UTF-8 text (byte {error.start})", path=str(path), line=line) from None
    return loads(text, format_for_path(path), path=str(path)), fingerprint


def write_motion(motion: Motion, path: Path, format: str, expected: Fingerprint | None,
                 **convert_options: object) -> SaveOutcome:
    """Write ``motion`` to ``path`` in ``format``; warn if the file is not what ``expected`` says.

    Args:
        motion: the motion to write (converted first when its format differs).
        path: target file.
        format: ``"xml"`` or ``"webots"``.
        expected: the fingerprint the caller last saw, None if the file did not exist then.
        convert_options: ``unroll_cycle``, ``drop_dynamic``, ``drop_unreachable``, ``round_durations``...

    Returns:
        The new fingerprint and a warning if the file had been changed, created or deleted by someone else.

    Raises:
        MotionFormatError / ConversionError: the motion cannot be written (the file is left untouched).
        OSError: the folder is not writable.
    """
    text = dumps(motion, format, **convert_options)  # fails before the file is touched
    current = fingerprint_of(path)
    warning = None
    if expected is None and current is not None:
        warning = f"{path} was created by someone else after this tab opened it; your save replaced it"
    elif expected is not None and current is None:
        warning = f"{path} was deleted by someone else after this tab loaded it; your save wrote it again"
    elif expected is not None and current is not None and current.sha256 != expected.sha256:
        warning = (f"{path} was changed on disk (another tab or program) after this tab loaded or saved it; "
                   "your save replaced that version (last save wins)")
    directory = path.parent if str(path.parent) else Path(".")
    handle, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=directory)
    try:
        with os.fdopen(handle, "wb") as stream:
            stream.write(text.encode("utf-8"))
            stream.flush()
            os.fsync(stream.fileno())
        if current is not None:
            shutil.copymode(path, temporary)
        os.replace(temporary, path)
    except BaseException:
        if os.path.exists(temporary):
            os.unlink(temporary)
        raise
    data = text.encode("utf-8")
    return SaveOutcome(Fingerprint(hashlib.sha256(data).hexdigest(), path.stat().st_mtime_ns), warning)
