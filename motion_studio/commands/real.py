"""``motion-studio real ...``: measurements against the real rcssserver3d 0.7.3 (built by the real-server
scripts' build.sh; never in CI): ``skills`` (each skill case on both servers, every figure), ``match`` (our agents
in a small match on both servers), ``trace`` (a scripted session recorded as a fixture). The real server runs in
a private network namespace (netns.sh); these commands re-run themselves inside it."""

from __future__ import annotations

import json
import logging
import os
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Optional

import typer

from motion_studio.cli import app
from motion_studio.realserver.match_play import MatchSetup

if TYPE_CHECKING:
    from motion_studio.realserver.cases import MotionSource

real_app = typer.Typer(help="Measure against the real rcssserver3d 0.7.3 (needs it built; never in CI).",
                       no_args_is_help=True)
app.add_typer(real_app, name="real")

ServerDir = Annotated[Optional[Path], typer.Option(
    help="folder of the real-server scripts (server.sh, netns.sh); default $NAO3D_REAL_SERVER_DIR, else "
         "<project>/../shared/real-server")]


def _fail(command: str, message: str) -> None:
    typer.echo(f"real {command}: {message}", err=True)
    raise typer.Exit(2)


def _into_netns(command: str, real_server_dir: Path | None) -> Path:
    """The checked scripts folder; re-runs this command inside netns.sh unless already inside."""
    from motion_studio.realserver import paths, process
    from motion_studio.realserver.errors import RealServerError

    if not paths.installed():
        _fail(command, paths.build_hint(real_server_dir))
    try:
        scripts = paths.checked_scripts_dir(real_server_dir)
    except RealServerError as error:
        _fail(command, str(error))
    process.reexec_in_netns(scripts, [sys.executable, "-m", "motion_studio", *sys.argv[1:]])
    return scripts


def _motions(command: str, revision: str) -> "MotionSource":
    """The motions of git ``revision`` (``--motions``), exported to a scratch folder; an unknown revision is a
    one-line error."""
    from motion_studio.realserver.cases import motion_source

    try:
        return motion_source(revision, Path(tempfile.mkdtemp(prefix="motions_")))
    except subprocess.CalledProcessError:
        _fail(command, f"unknown git revision {revision!r} (--motions)")


@real_app.command("skills")
def skills(
    cases: Annotated[Optional[list[str]], typer.Argument(help="cases to run (default all; --list shows them)")] = None,
    list_cases: Annotated[bool, typer.Option("--list", help="list the cases and exit")] = False,
    fixture: Annotated[Optional[Path], typer.Option(
        help="write each real trace into this folder (real_0.7.3_skill_<case>.jsonl.gz)")] = None,
    out: Annotated[Path, typer.Option(help="server and monitor logs")] = Path("out/real_skill_check"),
    json_path: Annotated[Optional[Path], typer.Option("--json", help="also write the figures as JSON")] = None,
    replay_sim: Annotated[bool, typer.Option(
        help="send the answers our agent gave on our simulator to the real server (the same joint commands on "
             "both: physics alone compared)")] = False,
    motions: Annotated[str, typer.Option(
        help="git revision of motions/files and motions/params to play (default HEAD: the committed motions); "
             "'worktree' = the files as they are now")] = "HEAD",
    robot_type: Annotated[int, typer.Option("--type", min=0, max=4, help="robot type (0-4) that plays every case, "
                                            "with its own motions")] = 0,
    dribble: Annotated[Optional[list[str]], typer.Option(
        "--dribble", metavar="NAME=VALUE",
        help="a DribbleConfig field for the dribble cases, on both servers (repeatable), e.g. "
             "--dribble near_heading_deg=30 --dribble free_line_deg=40")] = None,
    real_server_dir: ServerDir = None,
) -> None:
    """Each skill case on the real server and on ours, measured by ground truth; a table per case."""
    from motion_studio.realserver.cases import CASES, parse_dribble_settings
    from motion_studio.realserver.skill_check import check_skills

    try:
        dribble_config = parse_dribble_settings(dribble or [])
    except ValueError as error:
        _fail("skills", f"--dribble {error}")

    if list_cases:
        typer.echo("\n".join(f"{name}: {case.cycles} cycles" for name, case in CASES.items()))
        return
    unknown = [name for name in cases or [] if name not in CASES]
    if unknown:
        _fail("skills", f"unknown case(s) {', '.join(unknown)}; known: {', '.join(CASES)}")
    scripts = _into_netns("skills", real_server_dir)
    source = _motions("skills", motions)
    typer.echo(f"motions: {source.revision}")
    if dribble_config:
        typer.echo(f"dribble settings: {', '.join(f'{k}={v:g}' for k, v in dribble_config.items())}")
    results = check_skills(cases or list(CASES), source, scripts, out, fixture, replay_sim,
                           report=lambda text: typer.echo(text), robot_type=robot_type,
                           dribble_config=dribble_config)
    if json_path is not None:
        json_path.write_text(json.dumps(results, indent=1))


@real_app.command("joint-slack")
def joint_slack(
    cases: Annotated[list[str], typer.Argument(help="skill cases to run on the real server (see real skills --list)")],
    bodies: Annotated[str, typer.Option(help="comma-separated SimSpark body names to measure")] = "rfoot,lfoot",
    out: Annotated[Path, typer.Option(help="server and monitor logs")] = Path("out/real_joint_slack"),
    json_path: Annotated[Optional[Path], typer.Option("--json", help="also write the figures as JSON")] = None,
    plot_path: Annotated[Optional[Path], typer.Option(
        "--plot", help="also plot the z residual over time (PNG)")] = None,
    motions: Annotated[str, typer.Option(
        help="git revision of the motions to play (default HEAD); 'worktree' = the files as they are now")] = "HEAD",
    robot_type: Annotated[int, typer.Option("--type", min=0, max=4, help="robot type (0-4)")] = 0,
    ours: Annotated[bool, typer.Option(
        "--ours", help="also play each case on our simulator and measure it the same way (its own table)")] = False,
    real_server_dir: ServerDir = None,
) -> None:
    """How far the real robot's bodies lie from where its joint angles put them (ODE's joints give under fast
    rotation; ours emulates it, sim.joint_slack): per case and body, our forward kinematics of the monitor's torso
    and the HJ angles minus the monitor's body [mm]."""
    from dataclasses import replace

    from motion_studio.realserver import joint_slack as slack
    from motion_studio.realserver.cases import CASES, UNUM
    from motion_studio.realserver.errors import RealServerError
    from motion_studio.realserver.skill_runs import run_real
    from sim.replay import read_log

    unknown = [name for name in cases if name not in CASES]
    if unknown:
        _fail("joint-slack", f"unknown case(s) {', '.join(unknown)}; known: {', '.join(CASES)}")
    names = [name.strip() for name in bodies.split(",") if name.strip()]
    scripts = _into_netns("joint-slack", real_server_dir)
    source = _motions("joint-slack", motions)
    out.mkdir(parents=True, exist_ok=True)
    results = {}
    for name in cases:
        case = replace(CASES[name], robot_type=robot_type)
        typer.echo(f"{name}: running on the real server ...")
        try:
            _, lines = run_real(case, source, scripts, out)
            angles = slack.hinge_angles_by_cycle(line["msg"] for line in lines if line["k"] == "recv")
            results[name] = slack.body_slack(read_log(out / f"monitor_{case.name}.log"), angles, robot_type, names,
                                             robot=f"left_{UNUM}")
        except (RealServerError, KeyError) as error:
            _fail("joint-slack", f"{name}: {error}")
    typer.echo(slack.table(results))
    ours_results = {}
    if ours:
        from motion_studio.realserver.skill_runs import run_sim

        for name in cases:
            case = replace(CASES[name], robot_type=robot_type)
            typer.echo(f"{name}: running on our simulator ...")
            run = run_sim(case, source, record=True)
            log = out / f"ours_monitor_{case.name}.log"
            log.write_text("\n".join(run.monitor) + "\n")
            ours_results[name] = slack.body_slack(read_log(log), slack.hinge_angles_by_cycle(run.senses),
                                                  robot_type, names, robot=f"left_{UNUM}")
        typer.echo(slack.table(ours_results, server="ours"))
    if json_path is not None:
        json_path.parent.mkdir(parents=True, exist_ok=True)

        def summaries(by_case: dict) -> dict:
            return {name: {s.body: s.summary() for s in slacks if len(s.rows)} for name, slacks in by_case.items()}

        figures = {"motions": source.revision, "cases": summaries(results)}
        if ours:
            figures["ours"] = summaries(ours_results)
        json_path.write_text(json.dumps(figures, indent=1))
    if plot_path is not None:
        slack.plot(results, plot_path, ours_results or None)
        typer.echo(f"plot: {plot_path}")


@real_app.command("match")
def match(
    players: Annotated[int, typer.Option(min=1, max=11, help="players per team, 1-11")] = 3,
    duration: Annotated[float, typer.Option(min=0.02, max=3600.0, help="game time to play [s]")] = 120.0,
    seed: Annotated[int, typer.Option(help="our simulator's seed")] = 0,
    code: Annotated[str, typer.Option(
        help="git revision whose agent, simulator and motions play (default HEAD; exported and run in a child "
             "process); 'worktree' = the files as they are now")] = "HEAD",
    kick_off: Annotated[str, typer.Option(
        help="side kicking off on the real server: Left, Right or same (the side our match's coin toss "
             "chose)")] = "same",
    types: Annotated[Optional[str], typer.Option(
        help="robot types by unum, cycled, e.g. 0 or 0,2,4 (default: --type auto's, agent.team.composition)")] = None,
    cli: Annotated[bool, typer.Option(
        help="real match with python -m agent processes (the command people use) instead of agents in this "
             "process; only the monitor's figures then")] = False,
    connect_gap: Annotated[int, typer.Option(min=0, max=1000,
        help="cycles each agent plays before the next connects (in-process real match)")] = 3,
    only: Annotated[Optional[str], typer.Option(help="play one of the two matches only: real or ours")] = None,
    left: Annotated[str, typer.Option(help="left team: ours, baseline, solo or standing")] = "ours",
    right: Annotated[str, typer.Option(help="right team: ours, baseline, solo or standing")] = "ours",
    out: Annotated[Path, typer.Option(help="logs")] = Path("out/real_match_check"),
    json_path: Annotated[Optional[Path], typer.Option("--json", help="also write the figures as JSON")] = None,
    decisions: Annotated[bool, typer.Option(
        help="log every change of each player's decision (role, skill, skill mode) to agents.log "
             "(in-process agents)")] = False,
    real_server_dir: ServerDir = None,
    code_label: Annotated[Optional[str], typer.Option(hidden=True)] = None,
) -> None:
    """Our full soccer agent in a small match on the real server and on ours; figures side by side (falls,
    kicks and their effect, localization error, fouls, play modes)."""
    if not 1 <= players <= 11:
        _fail("match", f"--players must be 1-11, got {players}")
    if kick_off not in ("Left", "Right", "same"):
        _fail("match", f"--kick-off must be Left, Right or same, got {kick_off!r}")
    if only not in (None, "real", "ours"):
        _fail("match", f"--only must be real or ours, got {only!r}")
    try:
        robot_types = tuple(int(t) for t in types.split(",")) if types else None
    except ValueError:
        _fail("match", f"--types must be robot types separated by commas, got {types!r}")
    scripts = _into_netns("match", real_server_dir) if only != "ours" else None
    from motion_studio.match_agents import TEAM_KINDS

    for kind in (left, right):
        if kind not in TEAM_KINDS:
            _fail("match", f"--left/--right must be one of {', '.join(TEAM_KINDS)}, got {kind!r}")
    if code != "worktree":
        _play_revision(code, players, duration, seed, kick_off, types, cli, connect_gap, only, out, json_path,
                       left, right, decisions)
        return
    setup = MatchSetup(players, duration, robot_types, connect_gap, left, right)
    _play(setup, seed, code_label or "worktree", kick_off, cli, only, scripts, out, json_path, decisions)


def _play_revision(code: str, players: int, duration: float, seed: int, kick_off: str, types: str | None, cli: bool,
                   connect_gap: int, only: str | None, out: Path, json_path: Path | None, left: str = "ours",
                   right: str = "ours", decisions: bool = False) -> None:
    """The match with the code of a git revision: exported into a temporary folder and run there by a child
    process (``python -m motion_studio real match --code worktree``)."""
    from motion_studio.realserver.git_export import export_revision, short_revision

    try:
        short = short_revision(code)
    except subprocess.CalledProcessError:
        _fail("match", f"unknown git revision {code!r} (--code)")
    folder = export_revision(short, Path(tempfile.mkdtemp(prefix=f"real_match_{short}_")))
    if not (folder / "motion_studio" / "realserver" / "match_play.py").is_file():
        _fail("match", f"{short} predates motion_studio/realserver/match_play.py; use a later revision or "
                       "--code worktree")
    argv = [sys.executable, "-m", "motion_studio", "real", "match", "--players", str(players), "--duration",
            str(duration), "--seed", str(seed), "--code", "worktree", "--code-label", short, "--kick-off", kick_off,
            "--connect-gap", str(connect_gap), "--out", str(out.resolve())]
    argv += ["--types", types] if types else []
    argv += ["--left", left, "--right", right] if (left, right) != ("ours", "ours") else []
    argv += ["--cli"] if cli else []
    argv += ["--only", only] if only else []
    argv += ["--json", str(json_path.resolve())] if json_path else []
    argv += ["--decisions"] if decisions else []
    # the exported tree first on the child's path (its cwd, as python -m puts it first), so its code plays
    env = dict(os.environ, PYTHONPATH=str(folder))
    raise typer.Exit(subprocess.run(argv, cwd=folder, env=env).returncode)


def _play(setup: MatchSetup, seed: int, label: str, kick_off: str, cli: bool, only: str | None,
          scripts: Path | None, out: Path, json_path: Path | None, decisions: bool = False) -> None:
    """Both matches (or one, ``only``) with the code of this process; prints the table, writes the JSON."""
    import agent
    from motion_studio.realserver.match_figures import figures, problems, table
    from motion_studio.realserver.match_play import lineup, run_ours, run_real, run_real_cli

    out.mkdir(parents=True, exist_ok=True)
    root = logging.getLogger()
    for handler in list(root.handlers):  # the agents' logging goes to a file, not the table
        root.removeHandler(handler)
    logging.basicConfig(level=logging.INFO, filename=str(out / "agents.log"), filemode="w",
                        format="%(asctime)s %(threadName)s %(levelname)s %(name)s: %(message)s")
    if decisions:
        from agent.team.soccer_behavior import decision_log

        decision_log.setLevel(logging.DEBUG)
    typer.echo(f"code: {label} ({Path(agent.__file__).parent.parent}); {setup.players} v {setup.players}, "
               f"{setup.duration_s:g} s")
    results = {"code": label, "players": setup.players, "duration_s": setup.duration_s, "seed": seed,
               "types": [t for _, _, t in lineup(setup)]}
    side = "Left" if kick_off == "same" else kick_off
    played = []
    if only != "real":
        ours = run_ours(setup, seed, out)
        played.append(ours)
        if kick_off == "same":
            side = ours.kick_off
        typer.echo(f"ours: played in {ours.wall_s:.0f} s")
    if only != "ours":
        real = run_real_cli(setup, side, scripts, out) if cli else run_real(setup, side, scripts, out)
        played.insert(0, real)
        typer.echo(f"real: played in {real.wall_s:.0f} s")
    figs = {p.where.split()[0]: figures(p) for p in played}
    for p in played:
        results[p.where.split()[0]] = {"what": p.where, "figures": figs[p.where.split()[0]], "notes": p.notes,
                                       "problems": problems(p)}
    typer.echo(table(figs.get("real", {}), figs.get("ours", {})))
    for p in played:
        typer.echo(f"{p.where} notes: {json.dumps(p.notes, default=str)}")
        for line in problems(p):
            typer.echo(line)
    if json_path is not None:
        json_path.parent.mkdir(parents=True, exist_ok=True)
        json_path.write_text(json.dumps(results, indent=1, default=str))


@real_app.command("trace")
def trace(
    scenario: Annotated[str, typer.Argument(help="stand, crouch or fall")],
    out: Annotated[Path, typer.Argument(help="the trace file (.jsonl, or .jsonl.gz for gzip)")],
    cycles: Annotated[int, typer.Option(min=1, max=1_000_000, help="sense messages to record")] = 250,
    host: Annotated[str, typer.Option(help="the running server's address")] = "127.0.0.1",
    port: Annotated[int, typer.Option(min=1, max=65535, help="its agent port")] = 3100,
) -> None:
    """Record a scripted session against a running server (ours, or the real one started inside netns.sh:
    ``netns.sh bash -c 'server.sh & sleep 3; motion-studio real trace crouch out.jsonl.gz'``)."""
    from motion_studio.realserver.trace_recording import SCENARIOS, record

    if scenario not in SCENARIOS:
        _fail("trace", f"unknown scenario {scenario!r}; known: {', '.join(SCENARIOS)}")
    try:
        typer.echo(f"recorded {record(scenario, out, cycles, host, port)}")
    except OSError as error:
        _fail("trace", f"no server on {host}:{port} ({error})")
