"""The watched match of ``motion_studio.match_diagnose``: where each team's on-ball time goes."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from agent.skills.dribble import Dribble
from motion_studio.match_agents import SideAgents
from motion_studio.match_diagnose import ZONE_NAMES, ball_zone, diagnose, main, on_ball_activity
from sim.match import MatchConfig


@pytest.mark.parametrize("x_m, zone", [(-14.0, "own half"), (-0.01, "own half"), (0.0, "0-10 m"), (9.99, "0-10 m"),
                                       (10.0, "10-13 m"), (12.99, "10-13 m"), (13.0, "13 m-goal line"),
                                       (15.2, "13 m-goal line")])
def test_ball_zones_run_along_the_attack(x_m, zone):
    assert ball_zone(x_m) == zone
    assert zone in ZONE_NAMES


def test_the_activity_is_the_dribble_s_mode_else_the_skill_s_name_or_the_stand_up():
    dribble = Dribble(15.0, 0.0)
    dribble.mode = "push"
    assert on_ball_activity(SimpleNamespace(skills=SimpleNamespace(recovering=False, skill=dribble))) == "push"
    assert on_ball_activity(SimpleNamespace(skills=SimpleNamespace(recovering=True, skill=dribble))) == "StandUp"
    assert on_ball_activity(SimpleNamespace(skills=SimpleNamespace(recovering=False, skill=object()))) == "object"
    assert on_ball_activity(SimpleNamespace(skills=SimpleNamespace(recovering=False, skill=None))) == "-"
    assert on_ball_activity(object()) == "-"   # an agent that only stands has no skills


def test_a_watched_match_against_standing_robots_books_the_on_ball_time_of_our_side_only():
    config = MatchConfig(players_per_team=3, duration_s=20.0, seed=0)
    result = diagnose(config, SideAgents("ours", "standing", team_left=config.team_left))
    play_on = result.play_modes_s["PlayOn"]
    ours = result.on_ball_rows("left")
    # Our kick-off (the taker's line-up and kick) comes first; then one player dribbles on the whole time.
    assert result.play_modes_s["KickOff_Left"] > 1.0 and 5.0 < play_on < 19.0
    assert sum(s for _, _, s in ours) == pytest.approx(play_on, abs=0.1)
    assert result.on_ball_rows("right") == []          # robots that only stand never play the ball
    zones = {zone for zone, _, _ in ours}
    activities = {activity for _, activity, _ in ours}
    assert zones <= {"0-10 m"}                          # the kick-off ball lies 2-4 m out, then is pushed on
    assert "push" in activities and activities <= {"push", "approach", "avoid", "turn", "blocked"} | {
        a for a in activities if a.startswith("near:")}
    assert result.falls == [] and result.score == (0, 0)


def test_the_command_prints_the_on_ball_table(capsys):
    assert main(["--players", "2", "--duration", "12", "--seed", "1", "--right", "standing"]) == 0
    out = capsys.readouterr().out
    assert "left (ours) on-ball time in PlayOn" in out and "right (standing)" not in out
    assert "play modes [s]:" in out
