"""The solver trace of a run as JSON lines: one record per evaluated candidate and per finished iteration.

Why JSON lines: each finished rollout is one appended, flushed line, so a run killed with kill -9 keeps
every one it finished (a line cut short by the kill is dropped on resume), and plots and tables are drawn
from the records alone.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np


def _plain(value: Any) -> Any:
    """JSON-ready copy (NumPy scalars and arrays to Python, non-finite floats to strings JSON can hold)."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, (np.bool_,)):
        return bool(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, (float, np.floating)):
        value = float(value)
        return value if math.isfinite(value) else repr(value)
    return value


def read_trace(path: Path) -> list[dict[str, Any]]:
    """Every complete record of a trace file (a last line cut short by a kill is left out)."""
    if not path.is_file():
        return []
    records = []
    for line in path.read_text(encoding="utf-8").splitlines():
        try:
            records.append(json.loads(line))
        except json.JSONDecodeError:
            break
    return records


class TraceWriter:
    """Appends records to a trace file, one flushed and synced line each."""

    def __init__(self, path: Path, keep: Iterable[dict[str, Any]] | None = None) -> None:
        """Open ``path``; with ``keep`` the file is first rewritten to those records (a resume drops what
        the checkpoint does not cover)."""
        path.parent.mkdir(parents=True, exist_ok=True)
        if keep is not None:
            tmp = path.with_suffix(".tmp")
            tmp.write_text("".join(json.dumps(_plain(r)) + "\n" for r in keep), encoding="utf-8")
            tmp.replace(path)
        self.path = path
        self._file = path.open("a", encoding="utf-8")

    def write(self, record: dict[str, Any]) -> None:
        self._file.write(json.dumps(_plain(record)) + "\n")
        self._file.flush()
        os.fsync(self._file.fileno())

    def close(self) -> None:
        self._file.close()


__all__ = ["TraceWriter", "read_trace"]
