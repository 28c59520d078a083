"""Our team's robot types: legal for every team size under the server's own roster rules, the default of
matches and of the agent's --type auto."""

import pytest

from agent.runner import build_parser
from agent.team.composition import TEAM_TYPES, robot_type_for
from sim.match import MatchConfig
from sim.rules.params import RefereeConfig
from sim.rules.roster import Roster


@pytest.mark.parametrize("players", range(1, 12))
def test_every_team_size_is_accepted_by_the_roster_rules(players):
    roster = Roster(RefereeConfig())
    for unum in range(1, players + 1):
        assert roster.assign("Mine", unum, robot_type_for(unum)) is not None, f"unum {unum} refused"
    # The rules also hold against a twelfth request of any type: the team is full.
    assert roster.assign("Mine", 12, 0) is None


def test_the_types_cycle_from_the_goalkeeper_and_unum_zero_asks_for_type_0():
    assert [robot_type_for(u) for u in range(1, 12)] == [0, 2, 4, 0, 2, 4, 0, 2, 4, 0, 2]
    assert robot_type_for(0) == 0


def test_matches_and_the_agent_command_default_to_our_composition():
    assert MatchConfig().robot_types == TEAM_TYPES  # sim/ keeps its own copy: this test ties them
    parser = build_parser()
    assert parser.parse_args([]).robot_type == "auto"
    assert parser.parse_args(["--type", "3"]).robot_type == 3
    with pytest.raises(SystemExit):
        parser.parse_args(["--type", "7"])
