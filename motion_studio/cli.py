"""The ``motion-studio`` command: one thin subcommand per job, each in its own module under commands/."""

from __future__ import annotations

import importlib
import logging
import sys
from typing import Annotated

import typer

app = typer.Typer(help="Motion authoring and skill-tuning toolkit for the simulated RoboCup 3D Nao.",
                  no_args_is_help=True, add_completion=False)


def _show_version(value: bool) -> None:
    if value:
        from importlib.metadata import version

        typer.echo(f"motion-studio (nao3d-toolkit) {version('nao3d-toolkit')}")
        raise typer.Exit()


@app.callback()
def _options(version: Annotated[bool, typer.Option("--version", callback=_show_version, is_eager=True,
                                                   help="print the version and exit")] = False) -> None:
    """Motion authoring and skill-tuning toolkit for the simulated RoboCup 3D Nao."""


bench_app = typer.Typer(help="Benchmarks: print figures as JSON/tables, never pass/fail.", no_args_is_help=True)
app.add_typer(bench_app, name="bench")

# Each module registers its subcommands on `app` / `bench_app` when imported.
COMMAND_MODULES = (
    "motion_studio.commands.view",
    "motion_studio.commands.demo",
    "motion_studio.commands.bench_kinematics",
    "motion_studio.commands.match",
    "motion_studio.commands.bench_sim",
    "motion_studio.commands.bench_gym",
    "motion_studio.commands.agent",
    "motion_studio.commands.serve",
    "motion_studio.commands.edit",
    "motion_studio.commands.bench_skills",
    "motion_studio.commands.play",
    "motion_studio.commands.tune",
    "motion_studio.commands.transfer",
    "motion_studio.commands.real",
    "motion_studio.commands.calibrate",
    "motion_studio.commands.bench_tuning",
    "motion_studio.commands.motion_files",
    "motion_studio.commands.keypose",
    "motion_studio.commands.strike",
)


def _register_commands() -> None:
    for name in COMMAND_MODULES:
        importlib.import_module(name)


def main() -> None:
    from motion_studio.cli_errors import run_app

    logging.basicConfig(level=logging.INFO, format="%(levelname)s %(name)s: %(message)s")
    _register_commands()
    sys.exit(run_app(app))
