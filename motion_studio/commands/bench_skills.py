"""``motion-studio bench skills``: the skill benchmarks (walk, turn, kick, stand-up, dribble) on our simulator.

Each skill's benchmark lives in ``motion_studio.skill_bench.<skill>`` with
``run(quick, seed, progress, robot_type=...)`` returning JSON-ready figures (with their ``robot_type``) and
``plot(result, out_dir)`` writing PNGs named per type (``walk_type1.png``). This command runs the chosen ones
for each chosen robot type (``--type``, default 0), shows progress, prints one JSON object (``--json``) or a
table, writes the plots, and keeps each finished skill's figures in ``<out>/skills.json`` at once, so an
interrupted run loses no finished skill. With one type the figures are keyed by skill (``{"walk": ...}``), with
several by type, then skill (``{"type1": {"walk": ...}, "type4": ...}``).
"""

from __future__ import annotations

import importlib
import json
import time
from pathlib import Path
from typing import Annotated, Any

import typer

from kinematics.spec import ROBOT_TYPES
from motion_studio.cli import bench_app

#: Benchmarked skills in the order they run (the module name under motion_studio.skill_bench).
SKILLS = ("walk", "turn", "kick", "standup", "dribble")


def _flatten(prefix: str, value: Any, rows: list[tuple[str, str]]) -> None:
    """Rows 'walk.speed_m_s  0.52' of nested figures, lists shortened (they are in the JSON)."""
    if isinstance(value, dict):
        for key, item in value.items():
            _flatten(f"{prefix}.{key}" if prefix else str(key), item, rows)
    elif isinstance(value, list):
        shown = value if len(value) <= 6 else value[:6] + ["..."]
        rows.append((prefix, json.dumps(shown) if len(value) <= 6 else str(shown)))
    elif isinstance(value, float):
        rows.append((prefix, f"{value:.4g}"))
    else:
        rows.append((prefix, str(value)))


def type_key(robot_type: int) -> str:
    """The key of a robot type's figures when several types run: ``type1``."""
    return f"type{robot_type}"


def parse_robot_types(values: list[str] | None) -> list[int]:
    """Robot types of ``--type`` values, each one type or a comma list (``1``, ``1,4``); default [0].

    Raises:
        typer.BadParameter: a value that is not a robot type (the message names it and the range).
    """
    types: list[int] = []
    for value in values or ["0"]:
        for word in value.split(","):
            try:
                robot_type = int(word)
            except ValueError:
                robot_type = -1
            if robot_type not in ROBOT_TYPES:
                raise typer.BadParameter(f"{word.strip()!r} is not a robot type; expected "
                                         f"{min(ROBOT_TYPES)} to {max(ROBOT_TYPES)}", param_hint="'--type'")
            if robot_type not in types:
                types.append(robot_type)
    return types


def run_skill_benchmarks(skills: list[str], quick: bool, seed: int, out_dir: Path,
                         show_progress: bool = True, robot_types: tuple[int, ...] = (0,)) -> dict[str, Any]:
    """Run the benchmarks of ``skills`` for each of ``robot_types``, type after type.

    Returns:
        {skill: figures} for one type, {"type<N>": {skill: figures}} for several; every figures dict holds
        its "robot_type", "plots" and "wall_s". The same object is written to ``out_dir/skills.json`` after
        each finished skill of each type.
    """
    from tqdm import tqdm

    out_dir.mkdir(parents=True, exist_ok=True)
    checkpoint = out_dir / "skills.json"
    several = len(robot_types) > 1
    results: dict[str, Any] = {}
    for robot_type in robot_types:
        per_skill: dict[str, Any] = results.setdefault(type_key(robot_type), {}) if several else results
        for skill in skills:
            module = importlib.import_module(f"motion_studio.skill_bench.{skill}")
            bar = tqdm(desc=f"bench {skill} type {robot_type}", unit="trial", disable=not show_progress,
                       leave=False)

            def progress(done: int, total: int, bar: Any = bar) -> None:
                bar.total = total
                bar.n = done
                bar.refresh()

            started = time.perf_counter()
            figures = module.run(quick=quick, seed=seed, progress=progress, robot_type=robot_type)
            bar.close()
            figures["robot_type"] = robot_type
            figures["wall_s"] = round(time.perf_counter() - started, 2)
            figures["plots"] = [str(path) for path in module.plot(figures, out_dir)]
            per_skill[skill] = figures
            checkpoint.write_text(json.dumps(results, indent=2) + "\n")
    return results


@bench_app.command("skills")
def bench_skills(
    skill: Annotated[list[str] | None, typer.Option(
        "--skill", help=f"skill to benchmark (repeatable): {', '.join(SKILLS)}; default all")] = None,
    quick: Annotated[bool, typer.Option(help="reduced trials (a smoke run, figures less certain)")] = False,
    seed: Annotated[int, typer.Option(min=0, help="random seed of the simulator and the trial variations")] = 0,
    out: Annotated[Path, typer.Option(help="folder for the PNG plots and skills.json")] = Path("out/skills"),
    as_json: Annotated[bool, typer.Option("--json", help="print one JSON object only")] = False,
    robot_type: Annotated[list[str] | None, typer.Option(
        "--type", metavar="N[,N]",
        help=f"robot type {min(ROBOT_TYPES)}-{max(ROBOT_TYPES)} to benchmark (repeatable, or a comma list: "
             "--type 1,4); default 0. With several, the figures are keyed by type")] = None,
) -> None:
    """Walk speed and falls (run challenge), turn rate and turn-gain error, kick distance and direction,
    stand-up success and time, dribble speed and ball control, on our simulator with the real agent, per
    robot type with that type's motions. Writes PNG plots."""
    robot_types = parse_robot_types(robot_type)
    chosen = skill or list(SKILLS)
    unknown = [name for name in chosen if name not in SKILLS]
    if unknown:
        raise typer.BadParameter(f"unknown skill {', '.join(unknown)}; choose from {', '.join(SKILLS)}",
                                 param_hint="--skill")
    results = run_skill_benchmarks(chosen, quick, seed, out, show_progress=not as_json,
                                   robot_types=tuple(robot_types))
    if as_json:
        typer.echo(json.dumps(results))
        return
    rows: list[tuple[str, str]] = []
    for name, figures in results.items():
        _flatten(name, figures, rows)
    width = max(len(key) for key, _ in rows)
    for key, value in rows:
        typer.echo(f"{key:<{width}}  {value}")
    typer.echo(f"figures: {out / 'skills.json'}")
