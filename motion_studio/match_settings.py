"""The settings a match folder's results were played with, so a rerun never passes old results off as new.

``motion-studio match`` resumes a folder by match id; without this, ``match --duration 10`` in the demo's
folder printed the demo's 600 s result without playing. Each folder keeps ``settings.json`` beside
``results.jsonl``; a resume with other settings is refused (one line naming the options that differ), because
starting over silently would throw away finished matches and their logs.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from kinematics.errors import ToolkitError

SETTINGS_FILE = "settings.json"
#: Settings field -> the command-line option that sets it (for the message).
OPTIONS = {"players_per_team": "--players", "duration_s": "--duration", "team_left": "--team-left",
           "team_right": "--team-right", "log": "--log/--no-log", "robot_types": "robot types",
           "kick_off_wait_s": "kick-off wait", "left": "--left", "right": "--right"}


class MatchFolderError(ToolkitError, ValueError):
    """A run folder holds results of other settings (or of unknown ones) and a resume was asked for."""


@dataclass(frozen=True)
class MatchSettings:
    """What changes a match's result (seeds and the number of matches do not: they name the matches)."""

    players_per_team: int
    duration_s: float
    team_left: str
    team_right: str
    log: bool
    robot_types: tuple[int, ...]
    kick_off_wait_s: float
    left: str = "ours"
    right: str = "ours"

    def as_json(self) -> dict[str, Any]:
        return {**asdict(self), "robot_types": list(self.robot_types)}


def _shown(settings: dict[str, Any]) -> str:
    return " ".join(f"{OPTIONS.get(k, k)} {v}" for k, v in settings.items() if k in OPTIONS)


def prepare_folder(out: Path, settings: MatchSettings, resume: bool) -> None:
    """Make ``out`` ready for a run with ``settings``: keep its results when they were played with the same
    settings, clear them when ``resume`` is off, refuse otherwise.

    Raises:
        MatchFolderError: results of other (or unrecorded) settings are there and ``resume`` is on.
    """
    out.mkdir(parents=True, exist_ok=True)
    checkpoint, recorded_file = out / "results.jsonl", out / SETTINGS_FILE
    wanted = settings.as_json()
    has_results = checkpoint.exists() and checkpoint.stat().st_size > 0
    if has_results and resume:
        if not recorded_file.exists():
            raise MatchFolderError(f"--out {out}: holds results of unrecorded settings (no {SETTINGS_FILE}); "
                                   "pass --no-resume to replace them or choose another --out")
        try:
            recorded = json.loads(recorded_file.read_text())
        except json.JSONDecodeError as error:
            raise MatchFolderError(f"--out {out}: {SETTINGS_FILE} line {error.lineno}: {error.msg}; pass "
                                   "--no-resume to replace the results or choose another --out") from None
        differ = {k: (recorded.get(k), v) for k, v in wanted.items() if recorded.get(k) != v}
        if differ:
            changes = ", ".join(f"{OPTIONS.get(k, k)} {old} -> {new}" for k, (old, new) in differ.items())
            raise MatchFolderError(f"--out {out}: holds results of other settings ({changes}); pass --no-resume "
                                   "to replace them or choose another --out")
    elif checkpoint.exists():
        checkpoint.unlink()  # --no-resume, or an empty file
    recorded_file.write_text(json.dumps(wanted, indent=1) + "\n")


__all__ = ["MatchFolderError", "MatchSettings", "SETTINGS_FILE", "prepare_folder"]
