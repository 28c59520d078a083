"""``motion-studio convert``, ``validate`` and ``motions list``: the motion files from the command line.

Thin edges over ``motions`` (its readers, writers, converter and validator); every message of a bad file is
the room's ``file:line: field ...: what`` on one line.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from motion_studio.cli import app
from motion_studio.commands.options import RobotType

motions_app = typer.Typer(help="The motion files: list them (motions list).", no_args_is_help=True)
app.add_typer(motions_app, name="motions")

#: Where the shipped motion files live, relative to the project.
FILES_DIR = Path(__file__).resolve().parents[2] / "motions" / "files"
#: Extensions of motion files: XML phase and Webots.
MOTION_SUFFIXES = (".xml", ".motion")
#: Exit code of ``validate`` when a file breaks its format (2 stays for files that cannot be read).
INVALID_EXIT_CODE = 1


@app.command()
def convert(
    source: Annotated[Path, typer.Argument(help="motion file to read: XML phase (.xml) or Webots (.motion)")],
    target: Annotated[Path, typer.Argument(help="file to write; its extension picks the format")],
    unroll_cycle: Annotated[bool, typer.Option(help="XML -> Webots: write one pass of a next cycle")] = False,
    drop_dynamic: Annotated[bool, typer.Option(help="XML -> Webots: ignore flags, use computed values' "
                                                    "'end' fallback")] = False,
    drop_unreachable: Annotated[bool, typer.Option(help="XML -> Webots: leave out phases off the next chain "
                                                        "(finalize sequences)")] = False,
    round_durations: Annotated[bool, typer.Option(help="Webots -> XML: round times to whole ms")] = False,
) -> None:
    """Convert a motion between the XML phase format and Webots .motion (the readers and writers of motions/).

    A feature the target cannot express (a cycle, a flag, a computed value) is an error naming the option that
    gives it up; nothing is written then.
    """
    import motions
    from motions.io import format_for_path

    target_format = format_for_path(target)
    if target_format is None:
        raise typer.BadParameter(f"{target}: unknown extension; expected .xml (XML phase) or .motion (Webots)",
                                 param_hint="TARGET")
    motion = motions.load(source)
    options = ({"unroll_cycle": unroll_cycle, "drop_dynamic": drop_dynamic, "drop_unreachable": drop_unreachable}
               if target_format == "webots" else {"round_durations": round_durations})
    target.parent.mkdir(parents=True, exist_ok=True)
    try:
        motions.save(motion, target, target_format, **options)
    except motions.ConversionError as error:  # the room names its keyword; the user knows the option
        text = str(error)
        for option in (*options, "round_durations"):
            text = text.replace(f"{option}=True", f"--{option.replace('_', '-')}")
        raise typer.BadParameter(f"{source}: {text}", param_hint="SOURCE") from None
    typer.echo(f"wrote {target} ({target_format}, {len(motions.load(target).keyframes)} keyframes, "
               f"{motion.duration_s:.3f} s)")


@app.command()
def validate(
    files: Annotated[list[Path], typer.Argument(help="motion files (.xml or .motion)")],
    robot_type: RobotType = 0,
) -> None:
    """Parse and check each motion file (joint names and limits of the robot type, durations, phase links).

    One line per file: ``FILE: ok ...`` or ``FILE:LINE: field ...: what is wrong``. Exit 1 if a file is
    invalid, 2 if one cannot be read.
    """
    import motions
    from motions.validation import validate_motion

    invalid = unreadable = 0
    for path in files:
        try:
            motion = motions.load(path)
            validate_motion(motion, robot_type)
        except motions.MotionFormatError as error:
            invalid += 1
            text = str(error) if str(error).startswith(str(path)) else f"{path}: {error}"
            typer.echo(" ".join(text.split()), err=True)
            continue
        except OSError as error:
            unreadable += 1
            typer.echo(f"{path}: cannot read: {error.strerror or error}", err=True)
            continue
        typer.echo(f"{path}: ok ({motion.source_format}, {len(motion.keyframes)} keyframes, "
                   f"{motion.duration_s:.3f} s)")
    if unreadable:
        raise typer.Exit(2)
    if invalid:
        raise typer.Exit(INVALID_EXIT_CODE)


def motion_files(folder: Path) -> list[Path]:
    """Every motion file under ``folder``, sorted by path."""
    return sorted(p for p in folder.rglob("*") if p.suffix in MOTION_SUFFIXES and p.is_file())


def made_by(header_comments: tuple[str, ...]) -> str:
    """The first line of a file's header comment (how it was made), shortened."""
    first = " ".join(header_comments[0].split()) if header_comments else ""
    return first if len(first) <= 70 else first[:67] + "..."


@motions_app.command("list")
def list_motions(
    folder: Annotated[Path, typer.Option(help="folder searched for .xml and .motion files")] = FILES_DIR,
) -> None:
    """The motion files: format, keyframes, length and how each was made (its header); subfolders type1/,
    type3/, type4/ hold the files of those robot types."""
    import motions

    if not folder.is_dir():
        raise typer.BadParameter(f"{folder} is not a folder", param_hint="--folder")
    paths = motion_files(folder)
    width = max((len(str(p.relative_to(folder))) for p in paths), default=4)
    typer.echo(f"{'file':<{width}}  format  keyframes  length_s  made by")
    for path in paths:
        shown = str(path.relative_to(folder))
        try:
            motion = motions.load(path)
        except motions.MotionFormatError as error:
            typer.echo(f"{shown:<{width}}  unreadable: {' '.join(str(error).split())}")
            continue
        typer.echo(f"{shown:<{width}}  {motion.source_format:<6}  {len(motion.keyframes):>9}  "
                   f"{motion.duration_s:>8.3f}  {made_by(motion.header_comments)}")
