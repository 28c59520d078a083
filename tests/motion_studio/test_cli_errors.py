"""Every motion-studio error is one line naming the argument and the expected values, exit 2, no traceback."""

from __future__ import annotations

import subprocess
import sys

import pytest

CLI = [sys.executable, "-m", "motion_studio"]

#: (arguments, words the one line must hold): a representative set, one per kind of check.
CASES = [
    (["bench", "sim", "--robots", "0"], ["'--robots'", "1 to 22"]),
    (["bench", "sim", "--robots", "-3"], ["'--robots'", "1 to 22"]),
    (["bench", "sim", "--robots", "23"], ["'--robots'", "1 to 22"]),
    (["bench", "sim", "--robotz", "3"], ["--robotz"]),
    (["view", "-j", "llj9=10", "--html", "x.html"], ["--joint", "unknown joint 'llj9'", "llj1"]),
    (["view", "-j", "llj3=abc", "--html", "x.html"], ["--joint", "not a number of degrees"]),
    (["view", "--type", "7", "--html", "x.html"], ["'--type'", "0 to 4"]),
    (["match", "--players", "12"], ["'--players'", "1 to 11"]),
    (["match", "--duration", "0"], ["'--duration'", "0.02 to 3600"]),
    (["match", "--players", "abc"], ["'--players'", "integer"]),
    (["match", "--matches", "2", "--agent-processes", "2"], ["--agent-processes", "single match"]),
    (["agent", "--unum", "12"], ["'--unum'", "0 to 11"]),
    (["agent", "--localization", "gps"], ["--localization", "ekf, seed"]),
    (["serve", "--port", "70000"], ["'--port'", "0 to 65535"]),
    (["serve", "--kickoff", "now"], ["--kickoff", "manual, auto"]),
    (["play", "no/such/file.xml"], ["MOTION_FILE", "No such file"]),
    (["play", "motions/files/kick.xml", "--start", "upside_down"], ["--start", "back, front"]),
    (["demo", "--players", "0"], ["'--players'", "1 to 11"]),
    (["real", "match", "--players", "0"], ["'--players'", "1 to 11"]),
    (["real", "joint-slack", "nosuch"], ["unknown case(s) nosuch", "walk_forward"]),
    (["calibrate", "--popsize", "1"], ["'--popsize'", "4 to 64"]),
    (["transfer", "--starts", "0"], ["'--starts'", "1 to 1000"]),
    (["bench", "skills", "--skill", "swim"], ["--skill", "walk, turn, kick, standup"]),
    (["nonsense"], ["No such command"]),
]


@pytest.mark.parametrize(("args", "words"), CASES, ids=[" ".join(a) for a, _ in CASES])
def test_error_is_one_line_with_exit_code_2(args, words, tmp_path):
    result = subprocess.run(CLI + args, capture_output=True, text=True, timeout=120, cwd=tmp_path.parent
                            if args[0] != "play" else None)
    assert result.returncode == 2, (result.stdout, result.stderr)
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1, result.stderr
    assert "Traceback" not in result.stderr
    for word in words:
        assert word in lines[0], lines[0]


@pytest.mark.parametrize(("args", "words"), [(["--type", "9"], ["--type", "0-4 or auto"]),
                                             (["--port", "99999"], ["--port", "1-65535"]),
                                             (["--localization", "gps"], ["--localization", "ekf"])])
def test_the_agent_command_errors_are_one_line_too(args, words):
    result = subprocess.run([sys.executable, "-m", "agent", *args], capture_output=True, text=True, timeout=120)
    assert result.returncode == 2
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and all(word in lines[0] for word in words), result.stderr
