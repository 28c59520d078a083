"""Recorded real-server sessions (tests/sim/fixtures/real_0.7.3_*.jsonl.gz) as typed traces.

A trace file is JSON lines, gzip or plain: ``send`` lines (the agent's message answering sense message
``i``; ``i = -1`` is the scene command), ``recv`` lines (the sense messages in order), and for skill traces a
``meta`` line (trainer commands and the cycle they went out with, the skill's first cycle) and ``truth``
lines (the monitor's torso pose and ball per cycle). Written by the real-server tools; read here for replays.
"""

from __future__ import annotations

import gzip
import json
from dataclasses import dataclass, field
from pathlib import Path

from motion_studio.calibration.errors import CalibrationError


@dataclass(frozen=True)
class Pose:
    """Torso pose of one cycle: centre [m] (field frame), up-axis z [-], heading [deg], ball centre [m]."""

    torso_m: tuple[float, float, float]
    up_z: float
    heading_deg: float
    ball_m: tuple[float, float, float]


@dataclass
class Trace:
    """One recorded session: what the agent sent and received, and the real truth where the monitor gave it."""

    name: str
    path: Path
    replies: dict[int, bytes]
    received: list[bytes]
    meta: dict = field(default_factory=dict)
    truth: dict[int, Pose] = field(default_factory=dict)

    @property
    def skill_cycle(self) -> int:
        """First cycle of the skill phase (0 for a scripted session without meta)."""
        return int(self.meta.get("skill_cycle", 0))

    @property
    def scene(self) -> bytes:
        return self.replies[-1]


def trace_name(path: Path) -> str:
    """``real_0.7.3_skill_walk_forward.jsonl.gz`` -> ``skill_walk_forward``."""
    name = path.name
    for suffix in (".gz", ".jsonl"):
        name = name.removesuffix(suffix)
    return name.removeprefix("real_0.7.3_")


def load_trace(path: Path | str) -> Trace:
    """Read a trace file.

    Raises:
        CalibrationError: the file is missing, not gzip/JSON, or a line lacks a field (file and line named).
    """
    path = Path(path)
    if not path.is_file():
        raise CalibrationError(path, 0, "no such trace file")
    opener = gzip.open if path.suffix == ".gz" else open
    replies: dict[int, bytes] = {}
    received: list[bytes] = []
    meta: dict = {}
    truth: dict[int, Pose] = {}
    line_number = 0
    try:
        with opener(path, "rt", encoding="utf-8") as stream:
            for line_number, line in enumerate(stream, start=1):
                if not line.strip():
                    continue
                row = json.loads(line)
                kind = row["k"]
                if kind == "send":
                    replies[int(row["i"])] = str(row["msg"]).encode()
                elif kind == "recv":
                    received.append(str(row["msg"]).encode())
                elif kind == "meta":
                    meta = row
                elif kind == "truth":
                    truth[int(row["i"])] = Pose(tuple(map(float, row["torso"])), float(row["up_z"]),
                                                float(row["heading_deg"]), tuple(map(float, row["ball"])))
    except (OSError, EOFError, UnicodeDecodeError) as error:
        raise CalibrationError(path, line_number + 1, f"unreadable ({error})") from None
    except json.JSONDecodeError as error:
        raise CalibrationError(path, line_number, f"not JSON ({error.msg})") from None
    except KeyError as error:
        raise CalibrationError(path, line_number, f"missing field {error}") from None
    except (TypeError, ValueError) as error:
        raise CalibrationError(path, line_number, f"bad value ({error})") from None
    if -1 not in replies:
        raise CalibrationError(path, 0, "no scene message (a 'send' line with i = -1)")
    if not received:
        raise CalibrationError(path, 0, "no sense messages ('recv' lines)")
    if meta and ("move_cycle" not in meta or "trainer" not in meta):
        raise CalibrationError(path, 0, "meta line lacks move_cycle/trainer")
    return Trace(trace_name(path), path, replies, received, meta, truth)


def find_traces(folder: Path | str) -> list[Path]:
    """The trace files of a folder, sorted."""
    folder = Path(folder)
    return sorted(p for p in folder.glob("real_*.jsonl*") if p.is_file())
