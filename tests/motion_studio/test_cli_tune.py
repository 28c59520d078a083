"""``motion-studio tune``: one entry point for the tuners; options after the target reach the tuner."""

from __future__ import annotations

from typer.testing import CliRunner

from motion_studio.cli import _register_commands, app
from motion_studio.commands.tune import TUNERS


def _run(*args: str):
    _register_commands()
    return CliRunner().invoke(app, ["tune", *args])


def test_an_unknown_target_lists_the_known_ones():
    result = _run("fly")
    assert result.exit_code == 2
    assert "gait" in result.output and "standup" in result.output


def test_options_after_the_target_go_to_its_tuner():
    result = _run("turn", "--help")
    assert result.exit_code == 0
    assert "--write" in result.output and "--min-gain" in result.output


def test_every_target_has_a_tuner_with_main():
    import importlib

    for module, _ in TUNERS.values():
        assert callable(importlib.import_module(module).main)


def test_tune_help_lists_every_target():
    result = _run("--help")
    assert result.exit_code == 0
    assert all(name in result.output for name in TUNERS)


def test_every_target_prints_its_options_with_defaults():
    for target in TUNERS:
        result = _run(target, "--help")
        assert result.exit_code == 0, (target, result.output)
        assert "--checkpoint" in result.output or "--run-dir" in result.output or "--params" in result.output
        assert "(default:" in result.output, target


def test_bench_tuning_says_what_it_prints():
    _register_commands()
    result = CliRunner().invoke(app, ["bench", "tuning", "--help"])
    assert result.exit_code == 0 and "--quick" in result.output and "rollouts" in result.output


def test_an_unknown_parameter_is_one_line_naming_it(capsys):
    from motion_studio import tune_kick

    assert tune_kick.main(["kick", "--only", "ball_ahead_m,strike_speed_m_s"]) == 2
    error = capsys.readouterr().err.strip()
    assert error.startswith("motion-studio tune kick: error: --only: unknown parameter 'strike_speed_m_s'; known: ")
    assert "\n" not in error


def test_a_turn_tuning_run_on_the_simulator_prints_where_its_files_are(tmp_path):
    """A real (short) run: three candidates of the quick turn-gain problem through the trust region."""
    run_dir = tmp_path / "turn"
    result = _run("turn", "--quick", "--evaluations", "3", "--run-dir", str(run_dir))
    assert result.exit_code == 0, result.output
    for line in (f"plots: {run_dir / 'objective.png'}, {run_dir / 'curve.png'}", f"checkpoint: {run_dir / 'checkpoint.pkl'}",
                 f"trace: {run_dir / 'trace.jsonl'}"):
        assert line in result.output
    assert (run_dir / "curve.png").stat().st_size > 5000
    assert "TurnBy check" in result.output and "curve: gains" in result.output
