"""Files of a git revision of this project exported into a folder (``git archive`` piped into ``tar``).

Why: the measuring commands play the code or motions of a committed revision while the working tree may hold
someone's unfinished files.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

from motion_studio.realserver.paths import PROJECT_DIR


def short_revision(revision: str) -> str:
    """The abbreviated commit id of ``revision`` (raises CalledProcessError for an unknown one)."""
    return subprocess.run(["git", "-C", str(PROJECT_DIR), "rev-parse", "--short", revision], check=True,
                          capture_output=True, text=True).stdout.strip()


def export_revision(revision: str, into: Path, *paths: str) -> Path:
    """Write ``paths`` (default: the whole tree) of ``revision`` under ``into``; returns ``into``."""
    archive = subprocess.run(["git", "-C", str(PROJECT_DIR), "archive", revision, *paths], check=True,
                             capture_output=True).stdout
    into.mkdir(parents=True, exist_ok=True)
    subprocess.run(["tar", "-x", "-C", str(into)], input=archive, check=True)
    return into


def export_motions(revision: str, into: Path) -> Path:
    """The motion files and dynamic elements of a git revision, exported into ``into``. Returns the folder
    holding ``files/`` and ``params/``."""
    return export_revision(revision, into, "motions/files", "motions/params") / "motions"


def code_state() -> str:
    """HEAD's abbreviated commit, and the project's Python files that differ from it (uncommitted changes play
    too when code runs from the working tree)."""
    head = short_revision("HEAD")
    changed = subprocess.run(["git", "-C", str(PROJECT_DIR), "diff", "--name-only", "HEAD", "--", "*.py"],
                             check=True, capture_output=True, text=True).stdout.split()
    return f"{head} + uncommitted changes in {', '.join(changed)}" if changed else head
