"""``motion-studio transfer``: every shipped skill on the real rcssserver3d 0.7.3 and on ours, side by side
(or, without the real server, the recorded real runs replayed on ours); a table of ours/real ratios, PNG plots
and JSON in --out."""

from __future__ import annotations

import json
import logging
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Annotated, Optional

import typer

from motion_studio.cli import app

DEFAULT_FIXTURES = Path(__file__).resolve().parents[2] / "tests" / "sim" / "fixtures"


def _fail(message: str) -> None:
    typer.echo(f"transfer: {message}", err=True)
    raise typer.Exit(2)


@app.command()
def transfer(
    starts: Annotated[int, typer.Option(min=1, max=1000, help="seeded lying starts per stand-up side (start 0 = the case as "
                                              "shipped; the others vary the fall script and the settle time)")] = 10,
    seed: Annotated[int, typer.Option(help="seed of the lying start variations")] = 0,
    out: Annotated[Path, typer.Option(help="folder for transfer.json, the PNG plots and the servers' logs")] =
        Path("out/transfer"),
    record: Annotated[Optional[Path], typer.Option(
        help="write the real runs into this folder as fixtures (real_0.7.3_skill_<run>.jsonl.gz); needs the "
             "real server")] = None,
    fixtures: Annotated[Path, typer.Option(help="recorded real runs replayed without the real server")] =
        DEFAULT_FIXTURES,
    case: Annotated[Optional[list[str]], typer.Option(
        "--case", help="run only this case (repeatable; default all)")] = None,
    motions: Annotated[str, typer.Option(
        help="git revision of the motions played live (default HEAD: the committed motions); 'worktree' = the "
             "files as they are now")] = "HEAD",
    robot_type: Annotated[int, typer.Option("--type", min=0, max=4, help="robot type (0-4) that plays every case, "
                                           "with its own motions (fixtures named <case>_type<N>)")] = 0,
    replay_only: Annotated[bool, typer.Option("--replay", help="replay the fixtures even if the real server is "
                                                               "built")] = False,
    real_server_dir: Annotated[Optional[Path], typer.Option(
        help="folder of the real-server scripts (server.sh, netns.sh); default $NAO3D_REAL_SERVER_DIR, else "
             "<project>/../shared/real-server")] = None,
) -> None:
    """Sim-to-real transfer of the shipped skills: walk speeds, turn per motion, kick distance, stand-up
    success and time over N lying starts, falls on a 20 m walk; real against ours with ratios. Live when the
    real server is built (it runs in a private network namespace), else from the recorded fixtures."""
    from motion_studio.realserver import paths, process, transfer as transfer_room, transfer_report
    from motion_studio.realserver.errors import RealServerError
    from motion_studio.realserver.git_export import code_state

    if starts < 1:
        _fail(f"--starts must be at least 1, got {starts}")
    unknown = [name for name in case or [] if name not in transfer_room.known_cases()]
    if unknown:
        _fail(f"unknown case {', '.join(unknown)}; known: {', '.join(transfer_room.known_cases())}")
    live = paths.installed() and not replay_only
    scripts = None
    if live:
        try:
            scripts = paths.checked_scripts_dir(real_server_dir)
        except RealServerError as error:
            _fail(str(error))
        process.reexec_in_netns(scripts, [sys.executable, "-m", "motion_studio", *sys.argv[1:]])
    elif record is not None:
        _fail("--record needs the real server (" + ("--replay given" if replay_only else paths.build_hint()) + ")")
    if not live and not fixtures.is_dir():
        _fail(f"no fixture folder {fixtures}")
    cases = transfer_room.plan(starts, seed, case, robot_type)
    out.mkdir(parents=True, exist_ok=True)
    logging.getLogger("sim").setLevel(logging.WARNING)  # each run's play-mode changes would bury the progress

    def progress(done: int, total: int, name: str) -> None:
        typer.echo(f"  [{done + 1}/{total}] {name}", err=True)

    started = time.perf_counter()
    code = code_state()
    with tempfile.TemporaryDirectory(prefix="transfer_") as scratch:
        try:
            result = transfer_room.measure("live" if live else "replay", cases, motions_revision=motions,
                                           fixtures=fixtures, scratch=Path(scratch), scripts=scripts,
                                           workdir=out / "logs", record=record, seed=seed, starts=starts,
                                           progress=progress)
        except subprocess.CalledProcessError:
            _fail(f"unknown git revision {motions!r} (--motions)")
        except RealServerError as error:
            _fail(str(error))
    wall_s = time.perf_counter() - started
    for error in result.errors:
        typer.echo(f"transfer: {error}", err=True)
    rows = transfer_report.rows(result.pairs, result.figures, starts, "not run" if live else "no fixture",
                                selected=case or None)
    what = ("live: rcssserver3d 0.7.3 and ours side by side" if live else
            "replay: recorded real runs, their commands replayed open loop on ours")
    typer.echo(transfer_report.table(rows, f"transfer ({what}; robot type {robot_type}; code {code}; motions "
                                           f"{result.motions})"))
    for note in result.notes:
        typer.echo(f"note: {note}")
    plots = transfer_report.plot(result.pairs, rows, out)
    summary = transfer_report.summary(result, rows, code=code, starts=starts, seed=seed, wall_s=wall_s, plots=plots,
                                      robot_type=robot_type)
    (out / "transfer.json").write_text(json.dumps(summary, indent=1) + "\n")
    typer.echo(f"{len(result.pairs)} runs in {wall_s:.0f} s; figures {out / 'transfer.json'}, plots in {out}")
    if not live:
        typer.echo(paths.build_hint(real_server_dir) if not paths.installed() else
                   "replayed on request (--replay); without it the real server runs")
