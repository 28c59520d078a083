"""``motion-studio keypose``: a stand-up's crouch solved with IPOPT on the symbolic Nao
(``motion_studio.standup_keypose``): the authored one and the one with the largest CoM margin, in SimSpark
degrees, for pasting into a keyframe or judging a stand-up's parameters."""

from __future__ import annotations

import json
from typing import Annotated

import typer

from motion_studio.cli import app


def _pair(text: str, name: str) -> tuple[float, float]:
    try:
        low, high = (float(v) for v in text.split(","))
    except ValueError:
        raise typer.BadParameter(f"{name}: expected LOW,HIGH (two numbers), got {text!r}") from None
    return low, high


@app.command("keypose")
def keypose(
    section: Annotated[str, typer.Argument(help="stand-up section of motions/params/standup.toml")] = "standup_front",
    pitch_deg: Annotated[str, typer.Option(help="torso lean bounds LOW,HIGH [deg]")] = "15,35",
    height_m: Annotated[str, typer.Option(help="torso centre above the sole site, bounds LOW,HIGH [m]")] = "0.26,0.31",
    robot_type: Annotated[int, typer.Option(min=0, max=4, help="robot type")] = 0,
    as_json: Annotated[bool, typer.Option("--json", help="print one JSON object only")] = False,
) -> None:
    """The crouch of a stand-up as authored and with the largest CoM margin inside the feet (IPOPT)."""
    from motion_studio.standup_keypose import section_keyposes

    try:
        authored, best = section_keyposes(section, _pair(pitch_deg, "--pitch-deg"), _pair(height_m, "--height-m"),
                                          robot_type)
    except ValueError as error:
        raise typer.BadParameter(str(error)) from None
    out = {}
    for name, pose in (("authored", authored), ("max_margin", best)):
        out[name] = {"pitch_deg": round(pose.pitch_deg, 3), "height_m": round(pose.height_m, 4),
                     "com_forward_m": round(pose.com_forward_m, 4), "margin_m": round(pose.margin_m, 4),
                     "angles_deg": {k: round(v, 3) for k, v in sorted(pose.angles_deg.items())}}
    if as_json:
        typer.echo(json.dumps(out))
        return
    for name, figures in out.items():
        typer.echo(f"{name}: lean {figures['pitch_deg']} deg, height {figures['height_m']} m, CoM "
                   f"{figures['com_forward_m']:+.4f} m ahead of the soles, margin {figures['margin_m']} m")
        typer.echo("  " + " ".join(f"{k}={v:g}" for k, v in figures["angles_deg"].items()))
