"""Recorded real-server skill sessions as fixture files (tests/sim/fixtures/real_0.7.3_skill_<case>.jsonl.gz).

A fixture is gzip JSON lines: a ``meta`` line (case, motions revision, spot, trainer commands and the cycle they
went out with, the skill's first cycle, the fall side), ``send`` lines (the agent's answer to sense message
``i``; ``i = -1`` is the scene command), ``recv`` lines (the sense messages, vision left out) and a ``truth``
line per cycle with a known pose (torso position, up-axis z, heading, ball: the monitor's full state).
"""

from __future__ import annotations

import gzip
import json
import zlib
from dataclasses import dataclass
from pathlib import Path

from motion_studio.realserver.errors import FixtureError
from motion_studio.scenarios import Truth

PREFIX = "real_0.7.3_skill_"


def fixture_path(folder: Path, name: str) -> Path:
    """``folder/real_0.7.3_skill_<name>.jsonl.gz``."""
    return folder / f"{PREFIX}{name}.jsonl.gz"


def without_vision(message: str) -> str:
    """A sense message without its ``(See ...)`` (half of a fixture's bytes; the replays need joints, FRP,
    gyro and accelerometer)."""
    start = message.find("(See ")
    if start < 0:
        return message
    depth = 0
    for index in range(start, len(message)):
        depth += {"(": 1, ")": -1}.get(message[index], 0)
        if depth == 0:
            return message[:start] + message[index + 1:]
    return message


def write_fixture(lines: list[dict], path: Path) -> None:
    """The trace as gzip JSONL, vision left out of the sense messages (meta ``vision``: "omitted")."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with gzip.open(path, "wt") as handle:
        for line in lines:
            if line["k"] == "meta":
                line = {**line, "vision": "omitted"}
            elif line["k"] == "recv":
                line = {**line, "msg": without_vision(line["msg"])}
            handle.write(json.dumps(line, separators=(",", ":")) + "\n")


@dataclass
class Fixture:
    """One recorded session."""

    path: Path
    meta: dict
    replies: dict[int, bytes]
    """The agent's answer to sense message i (-1: the scene command)."""
    received: list[bytes]
    """The sense messages in order."""
    truth: dict[int, Truth]
    """The real state each sense message i reports, where the monitor gave it."""

    @property
    def skill_cycle(self) -> int:
        """First cycle of the skill phase (0 for a scripted session without a meta line)."""
        return int(self.meta.get("skill_cycle", 0))

    @property
    def name(self) -> str:
        """``real_0.7.3_skill_walk_forward.jsonl.gz`` -> ``skill_walk_forward``."""
        return self.path.name.removesuffix(".gz").removesuffix(".jsonl").removeprefix("real_0.7.3_")


def _truth(row: dict) -> Truth:
    return Truth(float(row["t"]), tuple(float(v) for v in row["torso"]), float(row["up_z"]),
                 float(row["heading_deg"]), tuple(float(v) for v in row["ball"]), False)


def find_fixture_files(folder: Path) -> list[Path]:
    """The recorded sessions of a folder (``real_*.jsonl.gz``: skill fixtures and scripted traces), sorted."""
    return sorted(p for p in Path(folder).glob("real_*.jsonl.gz") if p.is_file())


def read_fixture(path: Path, require_meta: bool = True) -> Fixture:
    """Read a skill fixture (or, with ``require_meta`` False, also a scripted trace: sends and sense messages
    without a meta line or truth, as ``motion-studio real trace`` records).

    Raises:
        FixtureError: the file is missing, not gzip JSON lines, a line lacks a field or has a bad value, or the
            file lacks its meta line, scene command or sense messages (file and line named; line 0 = the file).
    """
    path = Path(path)
    if not path.is_file():
        raise FixtureError(path, 0, "no such fixture file")
    meta: dict | None = None
    replies: dict[int, bytes] = {}
    received: list[bytes] = []
    truth: dict[int, Truth] = {}
    number = 0
    try:
        with gzip.open(path, "rt", encoding="utf-8") as stream:
            for number, text in enumerate(stream, start=1):
                if not text.strip():
                    continue
                row = json.loads(text)
                kind = row["k"]
                if kind == "meta":
                    meta = row
                    for key in ("move_cycle", "skill_cycle", "trainer", "case"):
                        row[key]  # noqa: B018 - a KeyError names the missing field
                    int(row["move_cycle"]), int(row["skill_cycle"])
                elif kind == "send":
                    replies[int(row["i"])] = str(row["msg"]).encode()
                elif kind == "recv":
                    received.append(str(row["msg"]).encode())
                elif kind == "truth":
                    truth[int(row["i"])] = _truth(row)
                else:
                    raise ValueError(f"unknown line kind {kind!r}")
    except (OSError, EOFError, UnicodeDecodeError, zlib.error) as error:
        raise FixtureError(path, number + 1, f"unreadable ({error})") from None
    except json.JSONDecodeError as error:
        raise FixtureError(path, number, f"not JSON ({error.msg})") from None
    except KeyError as error:
        raise FixtureError(path, number, f"missing field {error}") from None
    except (TypeError, ValueError, AttributeError) as error:
        raise FixtureError(path, number, f"bad value ({error})") from None
    if meta is None and require_meta:
        raise FixtureError(path, 0, "no meta line")
    if -1 not in replies:
        raise FixtureError(path, 0, "no scene command (a 'send' line with i = -1)")
    if not received:
        raise FixtureError(path, 0, "no sense messages ('recv' lines)")
    if meta is None:
        return Fixture(path, {}, replies, received, truth)
    if len(received) <= int(meta["skill_cycle"]):
        raise FixtureError(path, 0, f"{len(received)} sense messages, the skill starts at {meta['skill_cycle']}")
    return Fixture(path, meta, replies, received, truth)
