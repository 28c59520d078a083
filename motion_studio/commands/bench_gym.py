"""``motion-studio bench gym``: environment steps per second of the Nao3D Gymnasium environments."""

from __future__ import annotations

import json
from typing import Annotated

import typer

from motion_studio.cli import bench_app


@bench_app.command("gym")
def bench_gym(
    env_id: Annotated[str, typer.Option("--env", help="environment id: Nao3D-Stand-v0 or Nao3D-Walk-v0")] = "Nao3D-Stand-v0",
    steps: Annotated[int, typer.Option(min=10, max=1_000_000, help="timed steps of the single env")] = 2000,
    envs: Annotated[int, typer.Option(min=1, max=64, help="environments of the vectorised runs")] = 8,
    vector_steps: Annotated[int, typer.Option(min=1, max=100_000, help="timed steps of each vectorised run")] = 250,
    as_json: Annotated[bool, typer.Option("--json", help="one JSON object per run")] = False,
) -> None:
    """Time one env, then ``--envs`` envs in a SyncVectorEnv and an AsyncVectorEnv (one step = 20 ms)."""
    import logging

    from nao3d_gym import ENVIRONMENTS
    from nao3d_gym.bench import TARGET_STEPS_PER_S, run_single, run_vector

    if env_id not in ENVIRONMENTS:
        raise typer.BadParameter(f"expected one of {', '.join(ENVIRONMENTS)}, got {env_id!r}", param_hint="--env")
    logging.getLogger("sim").setLevel(logging.WARNING)   # every reset's play-mode line is noise here
    results = [run_single(env_id, steps)]
    results += [run_vector(env_id, envs, vector_steps, mode) for mode in ("sync", "async")]
    for result in results:
        figures = result.as_dict()
        if as_json:
            typer.echo(json.dumps(figures))
            continue
        per_cpu = f", {figures['steps_per_cpu_s']:.0f} per CPU second" if figures["steps_per_cpu_s"] else ""
        typer.echo(f"{figures['env_id']} {figures['mode']:>5} x{figures['num_envs']}: {figures['steps_per_s']:7.0f} "
                   f"env steps/s{per_cpu} ({figures['steps']} steps in {figures['wall_s']:.2f} s, "
                   f"{figures['episodes_ended']} episodes ended)")
    if not as_json:
        typer.echo(f"goal: {TARGET_STEPS_PER_S:.0f} env steps/s with one robot")
