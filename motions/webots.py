"""Reader and writer of Webots ``.motion`` text files (REFERENCE §6b, Webots ``motion.c``).

Radians with real-Nao signs and conventional joint names (``LHipPitch``) in the file; SimSpark-signed radians
and wire names (``llj3``) inside, converted through ``kinematics`` (pitch joints are negated). Reading follows
``motion.c``: tokens split on ``,`` ``\\n`` ``\\r`` (empty fields collapse), header ``#WEBOTS_MOTION,V1.0,
<joints>``, times ``ms | s:ms | m:s:ms`` strictly increasing, exactly one value per column (``*`` =
undefined), lines of at most 4096 characters, the first line without tokens ends the file. An unknown joint
name is a warning and its column is ignored by playback but kept for writing back. The thesis-era header
(``#WEBOTS_MOTION,V1.0`` alone, joint names on line 2) is read too; the writer always writes the one-line
header. There are no comments: a ``#`` line after the header is an error, as in Webots.

The older ``V1.1`` layout (Kouretes' and TUC's 2012 agents shipped the NaoQi-era Webots motions in it:
``StandUpFromFront``, the kicks) is read too: ``#WEBOTS_MOTION,V1.1`` alone on line 1, the joint names on
line 2 separated by ``%``, then one line per pose ``<state>%<v1>%...%<vn>%<seconds>`` with no time column
and no pose name: the state word is ``play`` in every known file (another word is a warning, read as
``play``) and the last field is the pose's duration in seconds. Those files give 0 for most poses, which the
2012 players (they ignore the column) played in 2 cycles, so 0 reads as ``V11_ZERO_POSE_MS``, with one
warning per file; poses are named ``Pose1``, ``Pose2``, ... It is written back as ``V1.0``.

Canonical layout: the one-line header, then one line per pose ``mm:ss:mmm,<name>,<v1>,...`` (``00:00:400``),
values as the shortest decimal that reads back exactly (``1.5``, ``-0.35``; no exponent), ``*`` for
undefined, LF line endings, a final newline. Time and value texts of a file read elsewhere (``400``,
``1.50``) are written back unchanged while their values are unchanged, as are CRLF line endings.

Each pose becomes a Keyframe whose ``duration_s`` is the time since the previous pose; the first pose's
duration is its absolute time, so a first pose at ``00:00:000`` has duration 0 (Webots applies the first
pose's values before its time).
"""

from __future__ import annotations

import logging
import math
import re
from pathlib import PurePath

from kinematics import nao_rad_to_simspark_rad, simspark_rad_to_nao_rad

from motions.errors import ConversionError, MotionFormatError
from motions.joints import joint_by_nao_name, joint_by_wire
from motions.model import (SERVER_CYCLE_MS, WEBOTS, JointTarget, Keyframe, KeyframeSource, Motion, MotionSource,
                           UnknownColumn)
from motions.numbers import is_whole, parse_decimal, shortest_decimal

logger = logging.getLogger(__name__)

MAGIC = "#WEBOTS_MOTION"
VERSION = "V1.0"
#: The older layout read besides VERSION (module docstring).
VERSION_V11 = "V1.1"
#: A V1.1 pose with a duration of 0 lasts this long [ms]: the 2012 players' 2 cycles per pose (REFERENCE §6b).
V11_ZERO_POSE_MS = 2 * SERVER_CYCLE_MS
MAX_LINE_CHARS = 4096
UNDEFINED = "*"
_TOKEN_SEPARATORS = re.compile(r"[,\r]")
_TIME = re.compile(r"\d+(?::\d+){0,2}")
# Robot type whose hinge set the sign conversion consults: type 4 has every hinge (toes included).
_ALL_HINGES_TYPE = 4


def _tokens(line: str) -> list[str]:
    """Tokens as ``strtok(line, ",\\n\\r")`` gives them: empty fields collapse."""
    return [t for t in _TOKEN_SEPARATORS.split(line) if t]


def parse_time_ms(token: str) -> int | None:
    """``ms``, ``s:ms`` or ``m:s:ms`` (digits and colons only) -> m*60000 + s*1000 + ms; None if malformed."""
    if not _TIME.fullmatch(token):
        return None
    parts = [int(p) for p in token.split(":")]
    parts = [0] * (3 - len(parts)) + parts
    return parts[0] * 60000 + parts[1] * 1000 + parts[2]


def format_time_ms(time_ms: int) -> str:
    """``mm:ss:mmm`` as the Webots editor writes it (``400`` -> ``00:00:400``)."""
    minutes, rest = divmod(time_ms, 60000)
    seconds, milliseconds = divmod(rest, 1000)
    return f"{minutes:02d}:{seconds:02d}:{milliseconds:03d}"


# ---------------------------------------------------------------------------------------------- reading
class _Reader:
    def __init__(self, text: str, path: str) -> None:
        self.path = path
        self.lines = text.split("\n")
        self.warnings: list[str] = []
        self.v11 = False
        """The V1.1 layout (``header`` finds it)."""

    def error(self, line: int, detail: str, field: str | None, element: str | None = None) -> MotionFormatError:
        return MotionFormatError(detail, path=self.path, line=line, field=field, element=element)

    def line_tokens(self, number: int, separator: str = ",") -> list[str]:
        """Tokens of 1-based line ``number`` ([] past the end), after the line-length check; ``separator``
        ``%`` for the V1.1 layout."""
        if number > len(self.lines):
            return []
        line = self.lines[number - 1]
        if len(line.rstrip("\r")) > MAX_LINE_CHARS:
            raise self.error(number, f"line is {len(line.rstrip())} characters long; Webots reads at most "
                             f"{MAX_LINE_CHARS}", "line")
        return _tokens(line) if separator == "," else [t for t in re.split(r"[%\r]", line) if t]

    def v11_pose(self, number: int, tokens: list[str], columns: list[str], pose: str) -> tuple[list[str], int]:
        """Values and duration [ms] of a V1.1 pose line ``<state>%<values>%<seconds>`` (``pose``: its name, for
        the errors)."""
        if tokens[0].strip() != "play":
            self.warnings.append(f"{self.path}:{number}: pose state {tokens[0]!r} read as 'play'")
            logger.warning(self.warnings[-1])
        values = tokens[1:]
        if len(values) not in (len(columns), len(columns) + 1):
            raise self.error(number, f"expected the state word, {len(columns)} values and the pose's seconds, got "
                             f"{len(tokens)} fields", "values", f"pose {pose!r}")
        if len(values) == len(columns):
            return values, 0
        seconds = parse_decimal(values[-1].strip())
        if seconds is None or seconds < 0:
            raise self.error(number, f"expected the pose's duration in seconds (>= 0), got {values[-1]!r}",
                             "duration", f"pose {pose!r}")
        return values[:-1], round(seconds * 1000.0)

    def header(self) -> tuple[list[str], int]:
        """Column names and the number of header lines (1, or 2 for the thesis-era layout)."""
        tokens = self.line_tokens(1)
        if not tokens:
            raise self.error(1, f"empty first line; expected the header '{MAGIC},{VERSION},<joint names>'", "header")
        if tokens[0] != MAGIC:
            raise self.error(1, f"expected the header '{MAGIC},{VERSION},<joint names>', got {tokens[0]!r}",
                             "header")
        if len(tokens) < 2:
            raise self.error(1, f"missing version after {MAGIC}; expected {VERSION}", "version")
        if tokens[1] == VERSION_V11:
            if len(tokens) > 2:
                raise self.error(1, f"a {VERSION_V11} file has the header alone on line 1 and its joint names on "
                                 f"line 2 (separated by '%'); got {tokens[2]!r} after the version", "version")
            names = [name for name in self.line_tokens(2, "%") if name.strip()]
            if not names:
                raise self.error(2, "no joint names (a V1.1 file names them on line 2, separated by '%')", "header")
            self.v11 = True
            return [name.strip() for name in names], 2
        if tokens[1] != VERSION:
            raise self.error(1, f"unsupported version {tokens[1]!r}; {VERSION} and {VERSION_V11} are read",
                             "version")
        if len(tokens) > 2:
            return tokens[2:], 1
        names = self.line_tokens(2)
        if not names:
            raise self.error(2, "no joint names (header line 1 or, in the thesis-era layout, line 2)", "header")
        return names, 2

    def pose(self, number: int, tokens: list[str], columns: list[str], previous_ms: int) -> tuple[int, str]:
        """Check the time and name of a pose line; returns (time in ms, pose name)."""
        time_ms = parse_time_ms(tokens[0])
        if time_ms is None:
            hint = " (Webots motion files have no comments)" if tokens[0].startswith("#") else ""
            raise self.error(number, f"expected a time (ms, s:ms or m:s:ms), got {tokens[0]!r}{hint}", "time")
        if time_ms <= previous_ms:
            raise self.error(number, f"time {tokens[0]} ({time_ms} ms) is not after the previous pose "
                             f"({previous_ms} ms); times must strictly increase", "time")
        if len(tokens) < 2:
            raise self.error(number, "missing pose name after the time", "pose name")
        count = len(tokens) - 2
        if count < len(columns):
            raise self.error(number, f"expected {len(columns)} values, got {count}", columns[count],
                             f"pose {tokens[1]!r}")
        if count > len(columns):
            raise self.error(number, f"expected {len(columns)} values, got {count}: unexpected extra data "
                             f"{tokens[2 + len(columns)]!r}", "values", f"pose {tokens[1]!r}")
        return time_ms, tokens[1]

    def value(self, number: int, token: str, column: str, pose: str) -> float | None:
        if token == UNDEFINED:
            return None
        value = parse_decimal(token)
        if value is None:
            raise self.error(number, f"expected a number or '*', got {token!r}", column, f"pose {pose!r}")
        return value


def loads_webots(text: str, path: str = "<string>", name: str | None = None) -> Motion:
    """Read a Webots motion from ``text``.

    Args:
        text: the whole file.
        path: file name for error messages, kept in ``motion.source.path``.
        name: motion name; default the file stem of ``path`` (Webots files carry no name).

    Returns:
        The motion, ``source_format == "webots"``, ``joint_order`` = the known columns in file order, one
        Keyframe per pose with a target (None for ``*``) for every known column.

    Raises:
        MotionFormatError: bad header or version (V1.0 and the older V1.1 layout are read), duplicate joint
            column, bad or non-increasing time, a V1.1 pose line with other than the state word, a value per
            column and (optionally) its seconds,
            missing pose name, wrong number of values, a value that is neither a number nor ``*``, an
            over-long line, no joints or no poses; each with path, line and field.
    """
    reader = _Reader(text, path)
    columns, header_lines = reader.header()
    wires: list[str | None] = []
    for column in columns:
        spec = joint_by_nao_name(column)
        if spec is None:
            reader.warnings.append(f"{path}:{header_lines}: unknown joint {column!r}: column ignored")
            logger.warning(reader.warnings[-1])
        elif spec.perceptor in wires:
            raise reader.error(header_lines, f"joint {column!r} has two columns", column)
        wires.append(None if spec is None else spec.perceptor)
    keyframes: list[Keyframe] = []
    unknown_texts: dict[int, list[str]] = {i: [] for i, w in enumerate(wires) if w is None}
    v11 = reader.v11
    zero_poses = 0
    previous_ms = -1
    number = header_lines
    while True:
        number += 1
        tokens = reader.line_tokens(number, "%" if v11 else ",")
        if not tokens or (v11 and not "".join(tokens).strip()):
            break
        if v11:
            pose, time_text = f"Pose{len(keyframes) + 1}", None
            values, pose_ms = reader.v11_pose(number, tokens, columns, pose)
            if pose_ms == 0:
                zero_poses, pose_ms = zero_poses + 1, V11_ZERO_POSE_MS
            time_ms = max(previous_ms, 0) + pose_ms
        else:
            time_ms, pose = reader.pose(number, tokens, columns, previous_ms)
            values, time_text = tokens[2:], tokens[0]
        targets: dict[str, JointTarget] = {}
        texts: dict[str, str] = {}
        for index, (column, wire, token) in enumerate(zip(columns, wires, values)):
            token = token.strip() if v11 else token
            value = reader.value(number, token, column, pose)
            if wire is None:
                unknown_texts[index].append(token)
                continue
            angle = None if value is None else nao_rad_to_simspark_rad(wire, value, _ALL_HINGES_TYPE)
            targets[wire] = JointTarget(angle)
            if value is not None:
                texts[wire] = token
        duration_s = (time_ms - max(previous_ms, 0)) / 1000.0
        keyframes.append(Keyframe(pose, duration_s, targets,
                                  source=KeyframeSource(line=number, time_text=time_text, value_texts=texts)))
        previous_ms = time_ms
    if zero_poses:
        reader.warnings.append(f"{path}:3: {zero_poses} of {len(keyframes)} poses give 0 s: each played in "
                               f"{V11_ZERO_POSE_MS} ms (the 2012 players' 2 cycles per pose)")
        logger.warning(reader.warnings[-1])
    if not keyframes:
        raise reader.error(number, "no poses: a Webots motion needs at least one pose line", "time")
    if any(line.strip() for line in reader.lines[number:]):
        reader.warnings.append(f"{path}:{number}: empty line ends the motion; the lines after it are ignored")
        logger.warning(reader.warnings[-1])
    source = MotionSource(
        path=path, line_ending="\r\n" if "\r\n" in text else "\n", final_newline=text.endswith("\n"),
        unknown_columns=tuple(UnknownColumn(i, columns[i], tuple(t)) for i, t in unknown_texts.items()),
        warnings=tuple(reader.warnings))
    motion_name = name if name is not None else (PurePath(path).stem if path != "<string>" else "")
    return Motion(motion_name, keyframes, source_format=WEBOTS,
                  joint_order=tuple(w for w in wires if w is not None), source=source)


# ---------------------------------------------------------------------------------------------- writing
def _phase_feature(keyframe: Keyframe) -> str | None:
    """Name of the first XML-only feature a keyframe uses, None if it uses none."""
    for attribute, value in (("next", keyframe.next), ("finalize", keyframe.finalize),
                             ("isFinal", keyframe.is_final), ("skipIfFlag", keyframe.skip_if_flag),
                             ("setFlagTrue", keyframe.set_flag_true), ("setFlagFalse", keyframe.set_flag_false)):
        if value is not None:
            return attribute
    for wire, target in keyframe.targets.items():
        if target.computed is not None:
            return f"computed ({wire})"
    return None


def _times_ms(motion: Motion) -> list[int]:
    times, total = [], 0
    for index, keyframe in enumerate(motion.keyframes):
        milliseconds = keyframe.duration_s * 1000.0
        minimum = 0 if index == 0 else 1
        if not (math.isfinite(milliseconds) and is_whole(milliseconds) and round(milliseconds) >= minimum):
            raise ConversionError(f"Webots times are whole, strictly increasing milliseconds; this pose lasts "
                                  f"{milliseconds!r} ms", field="duration", element=f"pose {keyframe.name!r}")
        total += round(milliseconds)
        times.append(total)
    return times


def _value_text(keyframe: Keyframe, wire: str, angle_rad: float | None) -> str:
    if angle_rad is None:
        return UNDEFINED
    if not math.isfinite(angle_rad):
        raise ConversionError(f"angle must be finite, got {angle_rad!r}", field=wire, element=f"pose {keyframe.name!r}")
    nao_rad = simspark_rad_to_nao_rad(wire, angle_rad, _ALL_HINGES_TYPE)
    old = keyframe.source.value_texts.get(wire) if keyframe.source else None
    if old is not None and parse_decimal(old) == nao_rad:
        return old
    return shortest_decimal(nao_rad)


def _columns(motion: Motion) -> list[tuple[str, str | None, UnknownColumn | None]]:
    """(header name, wire name, kept unknown column) in the order to write; exactly one of the last two."""
    columns: list[tuple[str, str | None, UnknownColumn | None]] = []
    for wire in motion.joints():
        spec = joint_by_wire(wire)
        if spec is None:
            raise ConversionError(f"unknown joint {wire!r} (targets are keyed by wire names such as 'llj3')",
                                  field=wire)
        columns.append((spec.nao_name, wire, None))
    for unknown in sorted(motion.source.unknown_columns if motion.source else (), key=lambda c: c.index):
        if len(unknown.texts) != len(motion.keyframes):
            logger.warning("dropping unknown Webots column %r: the number of poses changed", unknown.name)
            continue
        columns.insert(min(unknown.index, len(columns)), (unknown.name, None, unknown))
    return columns


def dumps_webots(motion: Motion) -> str:
    """Write ``motion`` as a Webots motion file (one-line header, canonical or as-read layout).

    Columns: ``motion.joints()`` (``joint_order``, then other joints in canonical order); a keyframe that
    does not list a joint gets ``*``.

    Raises:
        ConversionError: XML-only features (next, finalize, isFinal, flags, computed values; convert with
            ``motions.convert.to_webots``), durations that are not whole ms or do not strictly increase the
            time, pose names that are empty or hold ``,``/line breaks, no keyframes or no joints.
    """
    if not motion.keyframes:
        raise ConversionError(f"motion {motion.name!r} has no poses", field="keyframes")
    for keyframe in motion.keyframes:
        feature = _phase_feature(keyframe)
        if feature is not None:
            raise ConversionError(f"Webots motions cannot express {feature}; convert with "
                                  "motions.convert.to_webots", field=feature.split(" ")[0],
                                  element=f"pose {keyframe.name!r}")
        if not keyframe.name or any(c in keyframe.name for c in ",\r\n"):
            raise ConversionError("a Webots pose name must be non-empty and hold no ',' or line break",
                                  field="pose name", element=f"pose {keyframe.name!r}")
    columns = _columns(motion)
    if not columns:
        raise ConversionError("a Webots motion needs at least one joint column", field="header")
    lines = [",".join([MAGIC, VERSION, *(name for name, _, _ in columns)])]
    for index, (keyframe, time_ms) in enumerate(zip(motion.keyframes, _times_ms(motion))):
        old_time = keyframe.source.time_text if keyframe.source else None
        fields = [old_time if old_time is not None and parse_time_ms(old_time) == time_ms else format_time_ms(time_ms),
                  keyframe.name]
        for _, wire, kept in columns:
            if kept is not None:
                fields.append(kept.texts[index])
            elif wire is not None:
                fields.append(_value_text(keyframe, wire, keyframe.angle_rad(wire)))
        lines.append(",".join(fields))
    for number, line in enumerate(lines, start=1):
        if len(line) > MAX_LINE_CHARS:
            raise ConversionError(f"line {number} would be {len(line)} characters; Webots reads at most "
                                  f"{MAX_LINE_CHARS}", field="line")
    source = motion.source or MotionSource()
    text = "\n".join(lines) + ("\n" if source.final_newline else "")
    return text.replace("\n", source.line_ending) if source.line_ending != "\n" else text
