"""``motion-studio bench kinematics``: FK/IK speed and cross-library agreement."""

from __future__ import annotations

import json
from typing import Annotated

import typer

from motion_studio.cli import bench_app

TARGETS = {"fk_us": 20.0, "ik_ms": 1.0, "max_com_diff_m": 1e-6, "max_frame_diff_m": 1e-6}


@bench_app.command("kinematics")
def bench_kinematics(
    as_json: Annotated[bool, typer.Option("--json", help="print one JSON object only")] = False,
    poses: Annotated[int, typer.Option(min=1, max=100000, help="random poses per robot type for the agreement check")] = 100,
) -> None:
    """FK camera-height time, IK keyframe time, MuJoCo-Pinocchio disagreement (figures, not pass/fail)."""
    from kinematics.benchmark import run

    figures = run(poses)
    if as_json:
        typer.echo(json.dumps(figures))
        return
    for key, value in figures.items():
        target = TARGETS.get(key)
        ratio = f"  ({value / target:.3g} x target {target:g})" if target else ""
        typer.echo(f"{key:>18}: {value:.6g}{ratio}")
