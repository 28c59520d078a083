"""``motion-studio calibrate``: fit our world's contact parameters to recorded real-server traces."""

from __future__ import annotations

import logging
import shlex
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from motion_studio.cli import app

if TYPE_CHECKING:
    from motion_studio.realserver.fixtures import Fixture
    from sim.physics_params import PhysicsParams

PROJECT = Path(__file__).resolve().parents[2]


@app.command()
def calibrate(
    traces: Annotated[Path, typer.Option(help="folder of recorded real traces (real_*.jsonl.gz)")] =
        PROJECT / "tests" / "sim" / "fixtures",
    generations: Annotated[int, typer.Option(min=0, max=500, help="CMA-ES generations (0: only report the "
                                                                  "agreement of the current parameters)")] = 0,
    popsize: Annotated[int, typer.Option(min=4, max=64, help="candidates per generation")] = 10,
    seed: Annotated[int, typer.Option(min=0, help="seed of the optimiser")] = 0,
    out: Annotated[Path, typer.Option(help="run folder: checkpoint, evaluations.jsonl, agreement.png")] =
        Path("out/calibrate"),
    write: Annotated[bool, typer.Option(help="write the fitted values into sim/physics_calibrated.toml")] = False,
    parameters: Annotated[str, typer.Option(help="what to fit: contact (robot contacts), ball, slip (the "
                                               "feet's force-dependent slip, from a physics file that sets it), or "
                                               "all (contact and ball)")] = "contact",
    details: Annotated[bool, typer.Option(help="print every measure of every trace (real / ours, error)")] = False,
    only: Annotated[list[str] | None, typer.Option(help="use only traces whose name contains this (repeatable); "
                                                        "'ball_roll' is the real ball-roll figure")] = None,
    divergence: Annotated[bool, typer.Option(help="with --only: where each replay leaves its real recording (the "
                                                  "first joints past --threshold-deg, feet touching on one side "
                                                  "only, the torso), with a plot per trace in --out")] = False,
    threshold_deg: Annotated[float, typer.Option(min=0.01, help="--divergence: a joint has left the real one when "
                                                              "it is this far off [deg]")] = 1.0,
    cycles: Annotated[str | None, typer.Option(help="--divergence: also print these seconds after the skill's start "
                                                    "cycle by cycle, 'FROM:TO' (torso height, feet forces, joints)")]
        = None,
    joints: Annotated[str | None, typer.Option(help="--cycles: the joints to print, comma-separated HJ names "
                                                    "(default: the three earliest-diverging)")] = None,
    spread: Annotated[int, typer.Option(min=0, max=100, help="replay each skill trace this many times more with its "
                                                            "joint commands perturbed by the wire format's last digit "
                                                            "(1e-4 rad/s) and print the share ending as the real run "
                                                            "(holds / marginal / differs)")] = 0,
    workers: Annotated[int, typer.Option(min=1, max=64, help="--spread: processes replaying traces (each finished "
                                                            "trace goes to --out/spread.jsonl; a rerun resumes)")] = 1,
) -> None:
    """Replay every real trace on our simulator, print the agreement per trace, and with --generations fit the
    contact parameters (friction, impratio, solimp, solref) to them; a killed fit resumes from --out."""
    from motion_studio.calibration.errors import CalibrationError
    from motion_studio.calibration.fit import PARAMETER_SETS, evaluate, fit
    from motion_studio.calibration.report import (agreement_table, measure_table, plot_agreement,
                                                  write_physics_file)
    from motion_studio.realserver.errors import FixtureError
    from motion_studio.realserver.fixtures import find_fixture_files, read_fixture
    from sim.physics_params import CALIBRATED_FILE, default_physics_params

    if parameters not in PARAMETER_SETS:
        typer.echo(f"error: --parameters {parameters!r}: choose from {', '.join(PARAMETER_SETS)}", err=True)
        raise typer.Exit(2)
    if divergence and not only:
        typer.echo("error: --divergence needs --only NAME (one plot and table per trace)", err=True)
        raise typer.Exit(2)
    if divergence and generations:
        typer.echo("error: --divergence reports the current parameters; run it without --generations", err=True)
        raise typer.Exit(2)
    if (cycles is not None or joints is not None) and not divergence:
        typer.echo("error: --cycles and --joints print a --divergence report's cycles; add --divergence", err=True)
        raise typer.Exit(2)
    window = _window(cycles) if cycles is not None else None
    if spread and (divergence or generations):
        typer.echo("error: --spread reports the current parameters on its own; run it without --divergence and "
                   "--generations", err=True)
        raise typer.Exit(2)
    paths = [p for p in find_fixture_files(traces) if not only or any(o in p.name for o in only)]
    if not paths:
        typer.echo(f"error: --traces {traces}: no real_*.jsonl.gz trace files there", err=True)
        raise typer.Exit(2)
    loaded = []
    for path in paths:
        try:
            loaded.append(read_fixture(path, require_meta=False))
        except FixtureError as error:
            typer.echo(f"skipped: {error}", err=True)
    if not loaded:
        raise typer.Exit(2)
    logging.getLogger("sim").setLevel(logging.ERROR)   # blow-ups are counted in the objective
    base = default_physics_params()
    if divergence:
        chosen = tuple(j.strip() for j in joints.split(",") if j.strip()) if joints else ()
        _report_divergence(loaded, base, threshold_deg, out, window, chosen)
        return
    if spread:
        _report_spread(loaded, base, spread, seed, workers, out)
        return
    ball_roll = not only or "ball_roll" in only
    before = evaluate(loaded, base, ball_roll=ball_roll)
    after = None
    if generations:
        from tqdm import tqdm

        bar = tqdm(total=generations * popsize, desc="calibrate", unit="replay set")
        best = [before.objective]

        def progress(generation: int, result) -> None:  # noqa: ANN001 - fit.Evaluation
            if generation >= 0:
                best[0] = min(best[0], result.objective)
                bar.set_postfix(best=f"{best[0]:.3f}")
                bar.update(1)

        try:
            after = fit(loaded, base, PARAMETER_SETS[parameters], out, generations, popsize, seed=seed,
                        on_evaluation=progress, ball_roll=ball_roll)
        except CalibrationError as error:
            bar.close()
            typer.echo(f"error: {error}", err=True)
            raise typer.Exit(2) from None
        bar.close()
    typer.echo(agreement_table(before, after))
    if details:
        typer.echo(measure_table(after or before))
    png = plot_agreement(before, after, out / "agreement.png")
    typer.echo(f"plot: {png}")
    if after is not None:
        typer.echo(f"fitted: {after.values}")
        if write and after.objective < before.objective:
            command = "motion-studio " + " ".join(shlex.quote(a) for a in sys.argv[1:])
            write_physics_file(CALIBRATED_FILE, after, before, command, [t.name for t in loaded])
            typer.echo(f"written: {CALIBRATED_FILE}")
        elif write:
            typer.echo("not written: the fit found nothing better than the current parameters")


def _spread_one(job: tuple[Fixture, PhysicsParams, int, int]):  # noqa: ANN202 - OutcomeSpread | None
    """One trace's `outcome_spread` (a top-level function, so that a process pool can run it)."""
    from motion_studio.calibration.sensitivity import outcome_spread

    trace, physics, replays, seed = job
    logging.getLogger("sim").setLevel(logging.ERROR)
    return outcome_spread(trace, physics, replays, seed=seed)


def _report_spread(loaded: list[Fixture], physics: PhysicsParams, replays: int, seed: int, workers: int,
                   out: Path) -> None:
    """``--spread``: each skill trace replayed as recorded and ``replays`` times perturbed, as a table and a plot;
    each finished trace is a line of ``out/spread.jsonl`` at once, and a rerun replays only the missing ones."""
    from concurrent.futures import ProcessPoolExecutor
    from contextlib import ExitStack

    from tqdm import tqdm

    from motion_studio.calibration.sensitivity import (plot_spread, spread_from_row, spread_key, spread_row,
                                                       spread_table)
    from sim.match_batch import append_result, read_results

    skills = [trace for trace in loaded if trace.truth]
    if not skills:
        typer.echo("error: --spread needs skill traces (real poses); the selected ones are scripted", err=True)
        raise typer.Exit(2)
    checkpoint = out / "spread.jsonl"
    out.mkdir(parents=True, exist_ok=True)
    keys = {trace.name: spread_key(trace.name, physics, replays, seed) for trace in skills}
    done = {row["key"]: spread_from_row(row) for row in read_results(checkpoint)
            if isinstance(row, dict) and row.get("key") in keys.values()}
    jobs = [(trace, physics, replays, seed) for trace in skills if keys[trace.name] not in done]
    with tqdm(total=len(skills), initial=len(skills) - len(jobs), desc="spread", unit="trace") as bar, \
            ExitStack() as stack:
        mapper = map if workers == 1 or len(jobs) < 2 else \
            stack.enter_context(ProcessPoolExecutor(max_workers=workers)).map
        for result in mapper(_spread_one, jobs):
            if result is not None:
                append_result(checkpoint, spread_row(result, keys[result.trace]))
                done[keys[result.trace]] = result
            bar.update(1)
    spreads = [done[keys[trace.name]] for trace in skills if keys[trace.name] in done]
    typer.echo(spread_table(spreads))
    typer.echo(f"plot: {plot_spread(spreads, out / 'spread.png')}")


def _window(text: str) -> tuple[float, float]:
    """``--cycles 'FROM:TO'`` -> (from, to) [s after the skill's start]; a one-line exit on anything else."""
    parts = text.split(":")
    try:
        if len(parts) != 2:
            raise ValueError
        first, last = float(parts[0]), float(parts[1])
    except ValueError:
        typer.echo(f"error: --cycles {text!r}: give FROM:TO in seconds after the skill's start, e.g. 2.2:2.6",
                   err=True)
        raise typer.Exit(2) from None
    if last < first or first < 0.0:
        typer.echo(f"error: --cycles {text!r}: FROM must be at least 0 and TO not before FROM", err=True)
        raise typer.Exit(2)
    return first, last


def _report_divergence(loaded: list[Fixture], physics: PhysicsParams, threshold_deg: float, out: Path,
                       window: tuple[float, float] | None = None, joints: tuple[str, ...] = ()) -> None:
    """``--divergence``: replay each skill trace and print where it leaves the real recording, plot it, and with
    ``window`` print those seconds cycle by cycle."""
    from motion_studio.calibration.agreement import Replay
    from motion_studio.calibration.divergence import cycle_table, divergence, divergence_table, plot_divergence
    from motion_studio.realserver.replay import replay_states

    for trace in loaded:
        if not trace.truth:
            typer.echo(f"{trace.name}: a scripted trace (no real pose): skipped")
            continue
        replay = Replay(trace, replay_states(trace, physics))
        found = divergence(replay, threshold_deg)
        typer.echo(divergence_table(found))
        if window is not None:
            try:
                typer.echo(cycle_table(found, replay, *window, joints=joints))
            except ValueError as error:
                typer.echo(f"error: {error}", err=True)
                raise typer.Exit(2) from None
        typer.echo(f"plot: {plot_divergence(found, replay, out / f'divergence_{trace.name}.png')}")
