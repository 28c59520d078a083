"""Every ``motion-studio`` error as one line on stderr and exit code 2: no usage box, no traceback.

Why one place: Typer draws a multi-line box for a bad option and lets any error of the toolkit out as a
36-85-line traceback. Here the app runs in click's non-standalone mode and the edge turns each kind of user
error into ``motion-studio <command>: <what was wrong, the argument, the expected values>``. Errors that are
no user's fault (bugs) keep their traceback.
"""

from __future__ import annotations

import sys

import typer

from kinematics.errors import ToolkitError

#: Exit code of every usage or input error (click's, and the toolkit's).
USAGE_EXIT_CODE = 2


def one_line(text: str) -> str:
    """``text`` with its line breaks and runs of spaces folded, so the message stays on one line."""
    return " ".join(str(text).split())


def _command_path(error: typer.TyperException) -> str:
    ctx = getattr(error, "ctx", None)
    return ctx.command_path if ctx is not None else "motion-studio"


def _expected(error: typer.TyperException) -> str:
    """' (expected 1 to 22)' for an option with a range, so the message gives both bounds, not the one crossed."""
    param = getattr(error, "param", None)
    low, high = getattr(param, "min", None), getattr(param, "max", None)
    if low is None and high is None:
        return ""
    if high is None:
        return f"; expected at least {low}"
    return f"; expected at most {high}" if low is None else f"; expected {low} to {high}"


def run_app(app: typer.Typer, args: list[str] | None = None) -> int:
    """Run ``app`` on ``args`` (default ``sys.argv[1:]``); returns the exit code, never raises a user error."""
    words = sys.argv[1:] if args is None else args
    command = _invoked("motion-studio", words)
    try:
        result = app(args=args, prog_name="motion-studio", standalone_mode=False)
        return result if isinstance(result, int) else 0
    except typer.TyperException as error:  # bad option value, unknown option, missing argument, BadParameter
        if type(error).__name__ == "NoArgsIsHelpError":  # a group called bare: its help, as Typer shows it
            typer.echo(error.ctx.get_help())
            return USAGE_EXIT_CODE
        typer.echo(f"{_command_path(error)}: error: {one_line(error.format_message())}{_expected(error)} "
                   f"(see {_command_path(error)} --help)", err=True)
        return error.exit_code
    except typer.Abort:
        typer.echo(f"{command}: aborted", err=True)
        return 130
    except ToolkitError as error:  # bad input found inside a room: the message names what and where
        typer.echo(f"{command}: error: {one_line(error)}", err=True)
        return USAGE_EXIT_CODE
    except OSError as error:  # a file that is not there, a port in use
        what = f"{error.filename}: {error.strerror}" if error.filename and error.strerror else str(error)
        typer.echo(f"{command}: error: {one_line(what)}", err=True)
        return USAGE_EXIT_CODE
    except KeyboardInterrupt:
        return 130


def _invoked(program: str, args: list[str]) -> str:
    """'motion-studio bench sim' from the command line: the first words before an option or a path."""
    words = []
    for word in args[:2]:
        if word.startswith("-") or "/" in word or "." in word:
            break
        words.append(word)
    return " ".join([program, *words])


__all__ = ["USAGE_EXIT_CODE", "one_line", "run_app"]
