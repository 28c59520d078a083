"""``motion-studio tune TARGET [OPTIONS]``: the tuners of the shipped motions and curves, on our simulator.

Each target is a subcommand whose options are its tuner's (``motion-studio tune kick --help`` prints them,
with help and defaults); the tuner modules keep their ``main(argv)`` so ``python -m motion_studio.tune_kick``
(which the real-server backend re-runs inside its network namespace) takes the same options. Every run
prints where its plots, checkpoint and trace are (``motion_studio.tuning``).
"""

from __future__ import annotations

import importlib
from typing import Any

import typer
from typer.core import TyperGroup

from motion_studio.cli import app

#: Tuning target -> (module with ``main(argv)``, what it tunes).
TUNERS: dict[str, tuple[str, str]] = {
    "lean": ("motion_studio.tune_lean", "walk-lean curve (walk_lean section of dynamic_elements.toml): CasADi/IPOPT "
                                        "trust region (or CMA-ES) on walk rollouts"),
    "turn": ("motion_studio.tune_turn", "turn-gain curve (turn_gain section of dynamic_elements.toml): CasADi/IPOPT "
                                        "trust region (or CMA-ES, or a line fit) on turn rollouts"),
    "gait": ("motion_studio.tune_gait", "walk gait parameters (motions/params/gait.toml), CMA-ES on walk rollouts "
                                        "(ours, the real server, or both)"),
    "kick": ("motion_studio.tune_kick", "kick parameters (motions/params/kick.toml), CMA-ES on kick rollouts "
                                        "(ours, the real server, or both)"),
    "standup": ("motion_studio.tune_standup", "stand-up parameters (motions/params/standup.toml), CMA-ES on "
                                              "lying-start rollouts (ours, the real server, or both)"),
}


class TargetGroup(TyperGroup):
    """The ``tune`` group: an unknown target is a usage error that lists the known ones."""

    def resolve_command(self, ctx: Any, args: list[str]) -> Any:
        if args and args[0] not in self.commands and not args[0].startswith("-"):
            raise typer.BadParameter(f"unknown target {args[0]!r}; choose from {', '.join(TUNERS)}", ctx,
                                     param_hint="TARGET")
        return super().resolve_command(ctx, args)


tune_app = typer.Typer(cls=TargetGroup, no_args_is_help=True,
                       help="Tune a motion or a dynamic-element curve on our simulator (motion_studio.tuning: "
                            "run folder with checkpoint, trace and plots; a killed run resumes).")
app.add_typer(tune_app, name="tune")


def _register(target: str, module: str, text: str) -> None:
    @tune_app.command(target, help=f"{text}. Options: motion-studio tune {target} --help.",
                      context_settings={"allow_extra_args": True, "ignore_unknown_options": True,
                                        "help_option_names": []}, add_help_option=False)
    def tuner(ctx: typer.Context) -> None:
        code = importlib.import_module(module).main(list(ctx.args))
        if code:
            raise typer.Exit(int(code))


for _target, (_module, _text) in TUNERS.items():
    _register(_target, _module, _text)
