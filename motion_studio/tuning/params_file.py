"""The one writer of tuned values into ``motions/params/*.toml``, with provenance (command, date, revision).

Why one: every tuner used to carry its own section rewriter. Here a tuner renders its section(s) in its
file's format and this module does the rest the same way for all: the other sections and the header
comments stay byte for byte, the file is replaced atomically, the room's own loader must read the new file
back (else the old file is restored and the error names file and section), and the provenance line says
which command made the values, when, and at which git revision.
"""

from __future__ import annotations

import datetime
import re
import shlex
import subprocess
import sys
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from motion_studio.tuning.errors import TuningError
from motions.authoring.toml_text import toml_value as authored_toml_value

#: The project's root (the git work tree the revision is read from).
PROJECT_ROOT = Path(__file__).resolve().parents[2]


def git_revision(root: Path = PROJECT_ROOT) -> str:
    """Short hash of HEAD, ``+dirty`` when the work tree has changes; "unknown" outside a git checkout."""
    try:
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=root, capture_output=True, text=True,
                              timeout=10, check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=root,
                               capture_output=True, text=True, timeout=10).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    return head + ("+dirty" if dirty else "")


def _program(argv0: str) -> str:
    """``motion-studio``, or ``python -m package.module`` for a module of the project run with -m."""
    path = Path(argv0)
    if path.name == "motion-studio" or path.suffix != ".py":
        return path.name
    try:
        module = path.resolve().relative_to(PROJECT_ROOT).with_suffix("")
    except ValueError:
        return f"python {path.name}"
    return "python -m " + ".".join(module.parts).removesuffix(".__main__")


@dataclass(frozen=True)
class Provenance:
    """How tuned values were made: the command line, the date (UTC) and the git revision."""

    command: str
    date: str
    revision: str

    @classmethod
    def now(cls, command: str | Sequence[str] | None = None) -> Provenance:
        """The running command (default ``sys.argv``), today and HEAD."""
        if command is None:
            command = [_program(sys.argv[0]), *sys.argv[1:]]
        text = command if isinstance(command, str) else " ".join(shlex.quote(part) for part in command)
        return cls(text, datetime.datetime.now(datetime.timezone.utc).date().isoformat(), git_revision())

    def text(self, note: str = "") -> str:
        """One line for a ``provenance`` key: the note (figures), then command, date and revision."""
        made = f"{self.command} on {self.date} at {self.revision}"
        return f"{note}; {made}" if note else made


def toml_value(value: object) -> str:
    """A TOML literal of a number, bool, string, list or inline table (``motions.authoring.toml_text``).

    Raises:
        TuningError: a value TOML cannot hold.
    """
    try:
        return authored_toml_value(value)
    except TypeError as error:
        raise TuningError(str(error)) from None


def section_text(name: str, values: Mapping[str, object], comments: Mapping[str, str] | None = None) -> str:
    """``[name]`` with ``key = value`` lines in order; ``comments[key]`` goes on a ``#`` line above its key."""
    lines = [f"[{name}]"]
    for key, value in values.items():
        if comments and key in comments:
            lines.append(f"# {comments[key]}")
        lines.append(f"{key} = {toml_value(value)}")
    return "\n".join(lines) + "\n"


def _span(text: str, name: str) -> tuple[int, int] | None:
    """Where section ``[name]`` and its sub-tables (``[name.x]``, ``[[name.x]]``) are in ``text``."""
    header = re.compile(r"^\[\[?\s*([^\]]+?)\s*\]\]?\s*$", re.M)
    start = end = None
    for match in header.finditer(text):
        table = match.group(1)
        ours = table == name or table.startswith(name + ".")
        if start is None and table == name and not match.group(0).startswith("[["):
            start = match.start()
        elif start is not None and not ours:
            end = match.start()
            break
    if start is None:
        return None
    return start, len(text) if end is None else end


def replace_sections(text: str, sections: Mapping[str, str]) -> str:
    """``text`` with each ``[name]`` (and its sub-tables) replaced by ``sections[name]``, appended if absent;
    everything else (header comments, other sections) kept byte for byte."""
    for name, body in sections.items():
        body = body.rstrip("\n") + "\n"
        span = _span(text, name)
        if span is None:
            text = text.rstrip("\n") + "\n\n" + body
        else:
            tail = text[span[1]:]
            text = text[:span[0]] + body + ("\n" if tail else "") + tail
    return text


def write_file(path: Path, text: str, check: Callable[[Path], object]) -> Path:
    """Replace ``path`` with ``text`` atomically; ``check(path)`` (the room's loader) must accept it.

    Raises:
        TuningError: ``check`` refused the new text (the old file is put back; the message says why).
    """
    path = Path(path)
    old = path.read_text(encoding="utf-8") if path.is_file() else None
    tmp = path.with_suffix(path.suffix + ".tmp")
    tmp.write_text(text, encoding="utf-8")
    tmp.replace(path)
    try:
        check(path)
    except (ValueError, KeyError, TypeError) as error:
        if old is None:
            path.unlink()
        else:
            path.write_text(old, encoding="utf-8")
        raise TuningError(f"{path}: the rewritten file does not load ({str(error).splitlines()[0]}); "
                          f"left unchanged") from error
    return path


def write_sections(path: Path, sections: Mapping[str, str], check: Callable[[Path], object]) -> Path:
    """Rewrite ``sections`` (name -> section text, as :func:`section_text` or a room's own dumper makes it)
    of the parameter file ``path``; see :func:`write_file`."""
    path = Path(path)
    return write_file(path, replace_sections(path.read_text(encoding="utf-8"), sections), check)


__all__ = ["PROJECT_ROOT", "Provenance", "git_revision", "replace_sections", "section_text", "toml_value",
           "write_file", "write_sections"]
