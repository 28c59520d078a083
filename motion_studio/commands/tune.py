"""``motion-studio tune TARGET [OPTIONS]``: the tuners of the shipped motions and curves, on our simulator.

Each tuner is its own module with its own options (``motion-studio tune gait --help``); this command only
gives them one entry point. They checkpoint as they go, so an interrupted run resumes where it stopped.
"""

from __future__ import annotations

import importlib
from typing import Annotated

import typer

from motion_studio.cli import app

#: Tuning target -> (module with ``main(argv)``, what it tunes).
TUNERS: dict[str, tuple[str, str]] = {
    "gait": ("motion_studio.tune_gait", "walk gait parameters (motions/params/gait.toml), CMA-ES on walk rollouts"),
    "lean": ("motion_studio.tune_lean", "walk-lean offsets ([walk_lean] of dynamic_elements.toml)"),
    "turn": ("motion_studio.tune_turn", "turn-gain curve ([turn_gain] of dynamic_elements.toml), fitted"),
    "kick": ("motion_studio.tune_kick", "kick parameters (motions/params/kick.toml), CMA-ES on kick rollouts"),
    "standup": ("motion_studio.tune_standup", "stand-up parameters (motions/params/standup.toml), CMA-ES"),
}


@app.command(context_settings={"allow_extra_args": True, "ignore_unknown_options": True,
                               "help_option_names": []})
def tune(
    ctx: typer.Context,
    target: Annotated[str, typer.Argument(help="; ".join(f"{name}: {text}" for name, (_, text) in TUNERS.items()))],
) -> None:
    """Tune a motion or a dynamic-element curve on our simulator; options after TARGET go to its tuner
    (``motion-studio tune gait --help``)."""
    if target not in TUNERS:
        raise typer.BadParameter(f"unknown target {target!r}; choose from {', '.join(TUNERS)}", param_hint="TARGET")
    module = importlib.import_module(TUNERS[target][0])
    code = module.main(list(ctx.args))
    if code:
        raise typer.Exit(int(code))
