"""``motion-studio bench skills``: runs the chosen skill benchmarks, prints JSON, writes plots and keeps each
finished skill's figures in skills.json at once (an interrupted run loses no finished skill)."""

from __future__ import annotations

import json

from typer.testing import CliRunner

from motion_studio.cli import _register_commands, app


def _run(*args: str):
    _register_commands()
    return CliRunner().invoke(app, ["bench", "skills", *args])


def test_quick_turn_benchmark_prints_json_writes_a_plot_and_the_checkpoint(tmp_path):
    result = _run("--skill", "turn", "--quick", "--json", "--out", str(tmp_path))
    assert result.exit_code == 0, result.output
    figures = json.loads(result.output.strip().splitlines()[-1])["turn"]
    assert figures["falls"] == 0
    assert figures["rate_left_deg_s"] > 30.0  # the floor
    assert all(path.endswith(".png") for path in figures["plots"])
    assert all((tmp_path / path.rsplit("/", 1)[-1]).stat().st_size > 10_000 for path in figures["plots"])
    assert json.loads((tmp_path / "skills.json").read_text())["turn"]["rate_left_deg_s"] == figures["rate_left_deg_s"]


def test_an_unknown_skill_is_refused_with_the_known_ones():
    result = _run("--skill", "fly")
    assert result.exit_code == 2
    assert "walk" in result.output and "standup" in result.output
