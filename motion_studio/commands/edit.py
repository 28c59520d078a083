"""``motion-studio edit``: the motion editor in the browser; ``motion-studio bench editor``: its view latency."""

from __future__ import annotations

import json
import time
import webbrowser
from pathlib import Path
from typing import Annotated, Optional

import typer

from motion_studio.cli import app, bench_app
from motion_studio.commands.options import RobotType

#: Seconds within which a second Ctrl-C quits although tabs hold unsaved changes.
CONFIRM_QUIT_S = 10.0


@app.command()
def edit(
    file: Annotated[Path, typer.Argument(help="motion file: XML phase (.xml) or Webots (.motion); created on the "
                                              "first save if it does not exist")],
    port: Annotated[int, typer.Option(min=0, max=65535, help="port on 127.0.0.1; 0 = a free one")] = 0,
    no_browser: Annotated[bool, typer.Option("--no-browser", help="only print the URL")] = False,
    robot_type: RobotType = 0,
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
    moves: Annotated[int, typer.Option(min=1, max=10000, help="slider steps timed in the browser")] = 40,
    screenshot: Annotated[Optional[Path], typer.Option(help="save a PNG of the editor here")] = None,
    browser: Annotated[bool, typer.Option("--browser/--no-browser-part",
                                          help="also time slider -> 3D view in headless Chromium")] = True,
    as_json: Annotated[bool, typer.Option("--json", help="print one JSON object only")] = False,
) -> None:
    """Time the editor: requests inside the server, and slider move -> updated 3D view in headless Chromium
    (Debian's; never downloaded). Figures only."""
    import tempfile

    from motion_studio.editor.benchmark import bench_requests, write_bench_motion
    from motion_studio.editor.browser import bench_slider_latency, browser_unavailable_reason

    with tempfile.TemporaryDirectory() as folder:
        path = motion if motion is not None else write_bench_motion(Path(folder))
        figures: dict = {"requests": bench_requests(path)}
        reason = browser_unavailable_reason() if browser else "not asked for"
        if reason is None:
            figures["browser"] = bench_slider_latency(path, joint=joint, moves=moves, screenshot=screenshot)
        else:
            figures["browser"] = {"skipped": reason}
    if as_json:
        typer.echo(json.dumps(figures))
        return
    requests = figures["requests"]
    typer.echo("inside the editor (median per request, scene commands included):")
    for key in ("set_joint_ms", "scrub_ms", "ik_ms", "scene_bytes_per_edit", "preview_wall_s",
                "preview_realtime_factor"):
        typer.echo(f"{key:>24}: {requests[key]}")
    latency = figures["browser"]
    if "skipped" in latency:
        typer.echo(f"browser part skipped: {latency['skipped']}", err=True)
        return
    typer.echo(f"slider -> updated 3D view, {latency['moves']} moves of {latency['joint']} in {latency['browser']}:")
    for key in ("median_ms", "p90_ms", "min_ms", "max_ms", "reply_median_ms", "server_median_ms"):
        typer.echo(f"{key:>24}: {latency[key]}")
    typer.echo(f"{'webgl':>24}: {latency['webgl']}")
    typer.echo("(input event -> frame with the new pose drawn and the GPU done; reply = the new pose reached the "
               "page; server = the editor's own work)")
