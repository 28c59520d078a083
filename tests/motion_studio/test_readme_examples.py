"""Every ``motion-studio ...`` example of the README works as written (issue 16).

The examples are read from the README's bash blocks, so a new one cannot be left out: each must be listed
here with how it is checked, and a listed one that left the README fails too. Three ways, to keep the whole
file under a minute on 2 shared cores:

- RUN: run exactly as written, in a scratch folder that holds the project's ``motions`` and the README's
  ``pose.json``; must exit 0.
- SERVE: start exactly as written, wait for the line with its URL, then Ctrl-C; it must have got that far.
- PARSE: the command line is parsed by the CLI's own parser (command names, option names, value types and
  ranges) but not run, because it takes minutes (a 600 s match, the skill benchmarks, a tuner), needs the
  real rcssserver3d, a Ray cluster or headless Chromium, would bind a fixed port other jobs on this machine
  may hold (serve --port 3100), or would write into the project (calibrate --write).
"""

from __future__ import annotations

import json
import os
import re
import shlex
import signal
import subprocess
import sys
from pathlib import Path

import pytest
import typer

from tests.process_audit import as_foreground_child, wait_for_line

ROOT = Path(__file__).resolve().parents[2]
CLI = [sys.executable, "-m", "motion_studio"]
RUN, SERVE, PARSE = "run", "serve", "parse"
#: README example (without "motion-studio") -> how it is checked.
HOW = {
    "view -j llj3=30 -j llj4=-60 -j llj5=30": SERVE,
    "view --pose pose.json --html pose.html": RUN,
    "view --log out/match/match-0.log.gz": SERVE,  # after a 1 s match has written that log
    "edit motions/files/kick.xml": SERVE,
    "play motions/files/standup_back.xml --plot out/standup.png --html out/standup.html": RUN,
    "tune gait walk_forward --generations 20": PARSE,
    "tune gait walk_forward --backend both --lean --robust 8": PARSE,   # needs the real server
    "tune gait walk_fast --backend both --step-cycles 7 --lean --robust 6": PARSE,   # needs the real server
    "tune kick kick_strong --backend real --real-placements quick": PARSE,   # needs the real server
    "tune kick kick_strong --type 3 --backend both": PARSE,   # needs the real server
    "tune kick kick_strong --write-only --params out/kick_candidate.toml": PARSE,   # needs a run folder
    "motions list": RUN,
    "validate motions/files/kick.xml motions/files/turn_left.motion": RUN,
    "convert motions/files/turn_left.motion out/turn_left.xml": RUN,
    "serve --port 3100": PARSE,
    "kickoff --port 3200": PARSE,  # needs a running server on 3200
    "match --players 3 --duration 600 --matches 4 --workers 2 --out out/batch": PARSE,
    "match --matches 40 --ray auto --out out/batch": PARSE,
    "match --players 11 --duration 20 --agent-processes 2": PARSE,   # ~15-30 s
    "match --players 11 --right baseline --matches 10 --workers 2": PARSE,   # ten 600 s matches: ~1 h
    "bench skills --json": PARSE,
    "bench sim --robots 22 --json": RUN,
    "bench sim --robots 1 --cycles 1000 --repeat 5": RUN,
    "bench speed": PARSE,   # a 20 s 11 v 11 match: ~15-30 s
    "bench kinematics --json": RUN,
    "bench editor": PARSE,
    "transfer": PARSE,
    "transfer --record out/fix": PARSE,
    "transfer --case walk_20m --case walk_fast_20m": PARSE,   # needs the real server for its figures
    "transfer --type 3 --starts 5": PARSE,   # needs the real server (or type 3 fixtures) for its figures
    "real skills turn_left --json out/f.json": PARSE,
    "real skills walk_forward kick dribble --type 4": PARSE,
    "real skills kick_1m kick_2m kick_3m kick_4m": PARSE,
    "real skills kick_lineup_45cm kick_lineup_50cm kick_lineup_55cm": PARSE,
    "real skills dribble": PARSE,
    "real joint-slack walk_forward kick --ours --plot out/slack.png": PARSE,
    "real match --players 3 --duration 120": PARSE,
    "real trace crouch out/crouch.jsonl.gz": PARSE,
    "calibrate": PARSE,
    "calibrate --generations 20 --out out/cal": PARSE,
    "calibrate --generations 20 --write": PARSE,
    "calibrate --only skill_walk_forward --divergence": RUN,   # two replays, ~10 s
    "calibrate --only skill_walk_forward --divergence --cycles 2.2:2.6 --joints llj3,rlj3": RUN,
    "calibrate --spread 8 --workers 2": PARSE,   # 69 traces x 9 replays: ~10 min on 2 cores
    "calibrate --parameters slip --generations 10": PARSE,   # ~25 min (100 replay sets)
}
#: The line a served example prints once it is up.
SERVED_LINE = r"http://127\.0\.0\.1:\d+"


def readme_examples() -> list[list[str]]:
    """The arguments of every ``motion-studio`` line of the README's bash blocks (env assignments dropped)."""
    examples = []
    for block in re.findall(r"```bash\n(.*?)```", (ROOT / "README.md").read_text(), re.S):
        for line in block.splitlines():
            words = shlex.split(line, comments=True)
            while words and re.match(r"^[A-Z_][A-Z0-9_]*=", words[0]):
                words = words[1:]
            if words[:1] == ["motion-studio"]:
                examples.append(words[1:])
    return examples


EXAMPLES = readme_examples()


def test_every_readme_example_is_checked_here():
    written = {" ".join(words) for words in EXAMPLES}
    assert written == set(HOW), {"not listed here": written - set(HOW), "not in the README": set(HOW) - written}


@pytest.fixture(scope="module")
def scratch(tmp_path_factory) -> Path:
    """A folder like the project's for a user: motions/ (linked) and the README's pose.json."""
    folder = tmp_path_factory.mktemp("readme")
    (folder / "motions").symlink_to(ROOT / "motions")
    (folder / "pose.json").write_text(json.dumps({"llj3": 30, "llj4": -60, "llj5": 30}))
    return folder


def env() -> dict[str, str]:
    # BROWSER=true: `edit` opens a browser; here that is a no-op. The project importable from the scratch folder.
    return dict(os.environ, BROWSER="true", PYTHONPATH=str(ROOT))


def parse(args: list[str]) -> dict:
    """The parameters the CLI's parser makes of ``args``, resolving subcommands; raises on a bad line."""
    from motion_studio.cli import _register_commands, app

    _register_commands()
    command = typer.main.get_command(app)
    context = command.make_context("motion-studio", list(args))
    while hasattr(command, "resolve_command"):
        rest = [*getattr(context, "_protected_args", []), *context.args]
        name, command, rest = command.resolve_command(context, rest)
        context = command.make_context(name, rest, parent=context)
    return context.params


@pytest.mark.parametrize("args", EXAMPLES, ids=[" ".join(a) for a in EXAMPLES])
def test_readme_example_works_as_written(args, scratch):
    how = HOW[" ".join(args)]
    if how == PARSE:
        assert parse(args) is not None
        return
    if how == RUN:
        result = subprocess.run(CLI + args, cwd=scratch, env=env(), capture_output=True, text=True, timeout=120)
        assert result.returncode == 0, result.stderr[-2000:]
        for index, word in enumerate(args):  # every file the example names is written
            if args[index - 1] in ("--html", "--plot") or (args[0] == "convert" and index == 2):
                assert (scratch / word).stat().st_size > 0
        return
    if "--log" in args:
        played = subprocess.run(CLI + ["match", "--players", "1", "--duration", "1", "--out", "out/match"],
                                cwd=scratch, env=env(), capture_output=True, text=True, timeout=180)
        assert played.returncode == 0, played.stderr[-2000:]
    process = subprocess.Popen(CLI + args, cwd=scratch, env=env(), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                               text=True, start_new_session=True, preexec_fn=as_foreground_child)
    try:
        wait_for_line(process, SERVED_LINE)
        assert process.poll() is None
    finally:
        os.killpg(process.pid, signal.SIGINT)  # Ctrl-C, twice for the editor's unsaved-tab question
        try:
            process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGINT)
            process.wait(timeout=10)
