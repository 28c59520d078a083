"""``motion-studio edit``: the motion editor in the browser; ``motion-studio bench editor``: its view latency."""

from __future__ import annotations

import json
import time
import webbrowser
from pathlib import Path
from typing import Annotated, Optional

import typer

from motion_studio.cli import app, bench_app

#: Seconds within which a second Ctrl-C quits although tabs hold unsaved changes.
CONFIRM_QUIT_S = 10.0


@app.command()
def edit(
    file: Annotated[Path, typer.Argument(help="motion file: XML phase (.xml) or Webots (.motion); created on the "
                                              "first save if it does not exist")],
    port: Annotated[int, typer.Option(help="port on 127.0.0.1; 0 = a free one")] = 0,
    no_browser: Annotated[bool, typer.Option("--no-browser", help="only print the URL")] = False,
    robot_type: Annotated[int, typer.Option("--type", help="robot type 0-4")] = 0,
) -> None:
    """Edit a motion in the browser: keyframes, joint sliders, IK handles, playback, physics preview, save.

    Serves on 127.0.0.1 only and prints the URL; Ctrl-C stops (twice if a tab has unsaved changes).
    """
    from kinematics import ToolkitError
    from motion_studio.editor.server import EditorServer
    from motion_studio.editor.session import EditorSession

    try:
        session = EditorSession.open(file, robot_type)  # a file that does not parse opens nothing
    except (ToolkitError, OSError) as error:
        typer.echo(f"error: {error}", err=True)
        raise typer.Exit(2) from None
    try:
        server = EditorServer(file, robot_type, port)
    except OSError as error:
        typer.echo(f"error: cannot listen on 127.0.0.1:{port}: {error.strerror or error}", err=True)
        raise typer.Exit(2) from None
    state = "new file, created on the first save" if session.fingerprint is None else \
        f"{len(session.motion.keyframes)} keyframes, {session.motion.duration_s:.3f} s"
    typer.echo(f"motion editor for {file} ({state}): {server.url}  (Ctrl-C to stop)")
    for warning in session.load_warnings:
        typer.echo(f"warning: {warning}", err=True)
    last_warning = [-CONFIRM_QUIT_S * 2]

    def on_interrupt(dirty_tabs: list) -> bool:
        now = time.monotonic()
        if not dirty_tabs or now - last_warning[0] < CONFIRM_QUIT_S:
            return True
        last_warning[0] = now
        typer.echo(f"\n{len(dirty_tabs)} tab(s) have unsaved changes to "
                   f"{', '.join(sorted({str(t.session.path) for t in dirty_tabs}))}: save them in the browser, "
                   f"or press Ctrl-C again within {CONFIRM_QUIT_S:.0f} s to quit and discard them", err=True)
        return False

    server.on_interrupt = on_interrupt
    if not no_browser:
        webbrowser.open(server.url, new=2)
    server.run()
    typer.echo("editor stopped")


@bench_app.command("editor")
def bench_editor(
    motion: Annotated[Optional[Path], typer.Option(help="motion file to open (a copy is edited); default: a "
                                                        "built-in two-phase crouch")] = None,
    joint: Annotated[str, typer.Option(help="slider moved (wire name)")] = "llj3",
    moves: Annotated[int, typer.Option(help="slider steps timed")] = 40,
    screenshot: Annotated[Optional[Path], typer.Option(help="save a PNG of the editor here")] = None,
    as_json: Annotated[bool, typer.Option("--json", help="print one JSON object only")] = False,
) -> None:
    """Time slider move -> updated 3D view in headless Chromium (Debian's; never downloaded). Figures only."""
    import tempfile

    from motion_studio.editor.browser import bench_slider_latency, browser_unavailable_reason

    reason = browser_unavailable_reason()
    if reason is not None:
        typer.echo(f"cannot run the editor benchmark: {reason}", err=True)
        raise typer.Exit(1)
    with tempfile.TemporaryDirectory() as folder:
        path = motion
        if path is None:
            path = Path(folder) / "bench_crouch.xml"
            path.write_text(BENCH_MOTION)
        figures = bench_slider_latency(path, joint=joint, moves=moves, screenshot=screenshot)
    if as_json:
        typer.echo(json.dumps(figures))
        return
    typer.echo(f"slider -> updated 3D view, {figures['moves']} moves of {figures['joint']} in {figures['browser']}:")
    for key in ("median_ms", "p90_ms", "min_ms", "max_ms", "server_median_ms"):
        typer.echo(f"{key:>18}: {figures[key]}")


BENCH_MOTION = """<?xml version="1.0" encoding="UTF-8"?>
<!-- motion-studio bench editor: a two-phase crouch written by hand for the benchmark -->
<robot>
\t<low_skills>
\t\t<low_skill name="bench_crouch" firstPhase="down" />
\t</low_skills>

\t<phases>
\t\t<phase name="down" next="up">
\t\t\t<effectors>
\t\t\t\t<lle3 end="30" />
\t\t\t\t<lle4 end="-60" />
\t\t\t\t<lle5 end="30" />
\t\t\t\t<rle3 end="30" />
\t\t\t\t<rle4 end="-60" />
\t\t\t\t<rle5 end="30" />
\t\t\t</effectors>
\t\t\t<duration>500</duration>
\t\t</phase>
\t\t<phase name="up">
\t\t\t<effectors>
\t\t\t\t<lle3 end="0" />
\t\t\t\t<lle4 end="0" />
\t\t\t\t<lle5 end="0" />
\t\t\t\t<rle3 end="0" />
\t\t\t\t<rle4 end="0" />
\t\t\t\t<rle5 end="0" />
\t\t\t</effectors>
\t\t\t<duration>500</duration>
\t\t</phase>
\t</phases>
</robot>
"""
