"""Load and save motion files of either format: pick the format, convert when the target format differs.

The file edge of the room: ``load``/``save`` touch the disk, ``loads``/``dumps`` work on text. Files are
UTF-8 and are read without newline translation, so CRLF files are written back as CRLF.
"""

from __future__ import annotations

import os
from pathlib import Path

from motions.convert import convert
from motions.errors import MotionFormatError
from motions.model import FORMATS, WEBOTS, XML, Motion
from motions.webots import MAGIC, dumps_webots, loads_webots
from motions.xml_phase import dumps_xml, loads_xml

EXTENSIONS: dict[str, str] = {".xml": XML, ".motion": WEBOTS}


def format_for_path(path: str | os.PathLike[str]) -> str | None:
    """``"xml"`` for ``.xml``, ``"webots"`` for ``.motion`` (any case), None for another extension."""
    return EXTENSIONS.get(Path(path).suffix.lower())


def detect_format(text: str, path: str = "<string>") -> str:
    """The format of ``text`` by content: a Webots header or an XML document.

    Raises:
        MotionFormatError: the text is neither (line 1, field ``format``).
    """
    start = text.lstrip("\ufeff \t\r\n")
    if start.startswith(MAGIC):
        return WEBOTS
    if start.startswith("<"):
        return XML
    raise MotionFormatError(f"cannot tell the motion format: expected '{MAGIC}' (Webots) or '<' (XML phase), "
                            f"got {start[:20]!r}", path=path, line=1, field="format")


def _check_format(format: str) -> str:
    if format not in FORMATS:
        raise MotionFormatError(f"unknown motion format {format!r}; known: {', '.join(FORMATS)}", field="format")
    return format


def loads(text: str, format: str | None = None, *, path: str = "<string>", name: str | None = None) -> Motion:
    """Read a motion from text.

    Args:
        text: the whole file.
        format: ``"xml"``, ``"webots"`` or None to tell by content.
        path: file name for error messages.
        name: Webots only: the motion name (default: the stem of ``path``); XML files name themselves.

    Raises:
        MotionFormatError: the text breaks its format (with path, line and field).
    """
    # Editors on Windows start UTF-8 files with a byte-order mark; it is no part of either format.
    text = text.removeprefix("\ufeff")
    chosen = _check_format(format) if format is not None else detect_format(text, path)
    if chosen == XML:
        return loads_xml(text, path)
    return loads_webots(text, path, name)


def dumps(motion: Motion, format: str | None = None, **convert_options: object) -> str:
    """Write a motion as text, converting it first (``motions.convert``) when ``format`` differs from its own.

    Args:
        motion: the motion.
        format: target format; default ``motion.source_format``.
        convert_options: options of ``to_webots`` / ``to_xml`` (``unroll_cycle``, ``round_durations``, ...).

    Raises:
        MotionFormatError: no format given for a code-built motion; ConversionError: the motion cannot be
            written in that format.
    """
    chosen = format if format is not None else motion.source_format
    if chosen is None:
        raise MotionFormatError(f"motion {motion.name!r} has no source format: pass format='xml' or 'webots'",
                                field="format")
    _check_format(chosen)
    if motion.source_format != chosen:
        motion = convert(motion, chosen, **convert_options)
    return dumps_xml(motion) if chosen == XML else dumps_webots(motion)


def load(path: str | os.PathLike[str], format: str | None = None) -> Motion:
    """Read a motion file; the format comes from ``format``, else the extension, else the content.

    Raises:
        MotionFormatError: the file is not UTF-8 or breaks its format (path, line, field).
        OSError: the file cannot be read.
    """
    raw = Path(path).read_bytes()
    name = os.fspath(path)
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as error:
        line = raw[: error.start].count(b"\n") + 1
        raise MotionFormatError(f"not UTF-8 text (byte {error.start})", path=name, line=line) from None
    return loads(text, format or format_for_path(path), path=name)


def save(motion: Motion, path: str | os.PathLike[str], format: str | None = None, **convert_options: object) -> None:
    """Write ``motion`` to ``path``; the format comes from ``format``, else the extension, else the motion.

    The text is produced completely before the file is opened, so a motion that cannot be written leaves
    an existing file untouched.

    Raises:
        MotionFormatError / ConversionError: as ``dumps``. OSError: the file cannot be written.
    """
    text = dumps(motion, format or format_for_path(path) or motion.source_format, **convert_options)
    Path(path).write_bytes(text.encode("utf-8"))
