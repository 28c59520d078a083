"""``motion-studio real skills --dribble NAME=VALUE``: a dribble setting tried on both servers before it goes into the
code (the real server is where the dribble's line-ups cost most). The real server never runs in tests: the settings'
parsing, the case they change (the same case object drives both harnesses) and the trace's meta."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from agent.skills.dribble import Dribble, DribbleConfig
from motion_studio.cli import _register_commands, app
from motion_studio.realserver.cases import CASES, DribbleSkill, MotionSource, parse_dribble_settings, with_dribble_config
from motion_studio.realserver.skill_runs import meta_line


def test_settings_parse_to_numeric_dribble_fields():
    assert parse_dribble_settings(["near_heading_deg=30", " free_line_deg = 40"]) == {"near_heading_deg": 30.0,
                                                                                      "free_line_deg": 40.0}
    assert parse_dribble_settings([]) == {}


@pytest.mark.parametrize("word, words", [("near_heading_deg", "NAME=VALUE"), ("near_heading=30", "near_heading_deg"),
                                         ("near_heading_deg=wide", "'wide' is not a number"),
                                         ("near_heading_deg=nan", "'nan' is not a number"),
                                         ("push_aim_left_m=0.1", "NAME=VALUE")])
def test_a_bad_setting_names_the_word_and_the_fields(word, words):
    with pytest.raises(ValueError) as caught:
        parse_dribble_settings([word])
    assert word in str(caught.value) and words in str(caught.value)


def test_the_setting_changes_only_the_dribble_cases_and_is_recorded_in_the_trace():
    case = with_dribble_config(CASES["dribble"], {"near_heading_deg": 30.0})
    sequence = case.make_skill()
    dribble = sequence.parts[1][0]
    assert isinstance(dribble, Dribble) and dribble.config == DribbleConfig(near_heading_deg=30.0)
    assert CASES["dribble"].make_skill.config == DribbleConfig()          # the shipped case is untouched
    assert with_dribble_config(CASES["kick"], {"near_heading_deg": 30.0}) is CASES["kick"]
    assert meta_line(case, MotionSource(), "ours", "test")["dribble_config"] == {"near_heading_deg": 30.0}
    assert "dribble_config" not in meta_line(CASES["dribble"], MotionSource(), "ours", "test")
    assert isinstance(CASES["dribble_turn_left"].make_skill, DribbleSkill)


def test_a_bad_setting_is_one_line_before_any_server_starts():
    _register_commands()
    result = CliRunner().invoke(app, ["real", "skills", "dribble", "--dribble", "near_heading=30"])
    assert result.exit_code != 0
    assert "near_heading" in result.output and "Traceback" not in result.output


def test_a_fixture_recorded_with_a_setting_replays_as_that_case():
    """``motion-studio transfer`` rebuilds a fixture's case from its meta line: with the recorded dribble settings
    (``case_of`` reads the fixture's meta line and skill cycle only)."""
    from types import SimpleNamespace

    from motion_studio.realserver.transfer import case_of

    case = with_dribble_config(CASES["dribble"], {"near_ball_m": 0.8})
    meta = meta_line(case, MotionSource(), "ours", "test")
    rebuilt = case_of(SimpleNamespace(meta=meta, skill_cycle=meta["skill_cycle"], path="f.jsonl.gz"))
    assert rebuilt.make_skill.config == DribbleConfig(near_ball_m=0.8)
    assert case_of(SimpleNamespace(meta=meta_line(CASES["dribble"], MotionSource(), "ours", "test"),
                                   skill_cycle=meta["skill_cycle"], path="f")).make_skill.config == DribbleConfig()
