"""Export files of a git revision of this repository into a folder (``git archive`` piped into ``tar``).

Why: the measuring tools play the code or motions of a committed revision while the working tree may hold
someone's unfinished files. Imports nothing of the project, so a tool can call it before it puts the
exported code first on ``sys.path``.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def short_revision(revision: str) -> str:
    """The abbreviated commit id of ``revision`` (raises CalledProcessError for an unknown one)."""
    return subprocess.run(["git", "-C", str(REPO), "rev-parse", "--short", revision], check=True,
                          capture_output=True, text=True).stdout.strip()


def export_revision(revision: str, into: Path, *paths: str) -> Path:
    """Write ``paths`` (default: the whole tree) of ``revision`` under ``into``; returns ``into``."""
    archive = subprocess.run(["git", "-C", str(REPO), "archive", revision, *paths], check=True,
                             capture_output=True).stdout
    into.mkdir(parents=True, exist_ok=True)
    subprocess.run(["tar", "-x", "-C", str(into)], input=archive, check=True)
    return into
