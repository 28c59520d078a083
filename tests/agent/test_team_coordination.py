"""Team decisions from heard messages: a silent or fallen teammate loses the ball within 1 s, the set-piece
taker keeps off the ball until someone else touched it, the baseline's nearest-player rule."""

from __future__ import annotations

from agent.communication.messages import TeamMessage, encode
from agent.protocol import parse_sense
from agent.team.baseline import nearest_to_ball
from agent.team.roles import Candidate, candidates, choose_on_ball
from agent.team.set_pieces import TAKER_WAIT_S, TakerMemory, own_set_piece
from agent.world_model import WorldModel

TEAM = "Mine"


def _hear(world: WorldModel, now_s: float, message: TeamMessage | None = None, mode: str = "PlayOn") -> None:
    hear = "" if message is None else f"(hear {TEAM} {now_s:.2f} -30 {encode(message, TEAM)})"
    world.update(parse_sense(f"(time (now {now_s:.2f}))(GS (sl 0) (sr 0) (t {now_s:.2f}) (pm {mode})){hear}"
                             .encode()))


def _on_ball(world: WorldModel, ball: tuple[float, float]) -> int | None:
    return choose_on_ball(candidates(world), ball, None)


def test_a_teammate_that_falls_silent_loses_the_ball_within_one_second():
    world = WorldModel(TEAM, 4)
    _hear(world, 10.0, TeamMessage("c", 2, position=(-0.3, 0.0), ball=(0.0, 0.0)))
    _hear(world, 10.02, TeamMessage("l", 3, position=(-3.0, 1.0)))
    assert _on_ball(world, (0.0, 0.0)) == 2
    # Unum 3 keeps talking; unum 2 says nothing more (taken off the field, crashed).
    now = 10.02
    while now < 11.0:
        now += 0.18
        _hear(world, now, TeamMessage("l", 3, position=(-3.0, 1.0)))
    assert _on_ball(world, (0.0, 0.0)) == 3


def test_a_teammate_that_says_it_fell_loses_the_ball_at_once():
    world = WorldModel(TEAM, 4)
    _hear(world, 10.0, TeamMessage("c", 2, position=(-0.3, 0.0), ball=(0.0, 0.0)))
    _hear(world, 10.02, TeamMessage("l", 3, position=(-3.0, 1.0)))
    _hear(world, 10.04, TeamMessage("x", 2))
    assert _on_ball(world, (0.0, 0.0)) == 3


def test_the_set_piece_taker_keeps_off_the_ball_until_someone_else_was_there():
    world = WorldModel(TEAM, 3)
    _hear(world, 10.0, mode="KickOff_Left")
    world.game.side = "left"
    memory = TakerMemory()
    memory.update(world, own_set_piece("KickOff_Left", "left"), 2)
    _hear(world, 10.5)  # the kick: PlayOn
    memory.update(world, own_set_piece("PlayOn", "left"), 2)
    ball = (2.3, 0.0)
    taker_near = [Candidate(2, 1.9, 0.0), Candidate(3, -1.0, 1.0)]
    assert memory.excluded(world, ball, taker_near) == 2
    assert choose_on_ball([p for p in taker_near if p.unum != 2], ball, None) == 3
    # Unum 3 reaches the ball: the taker may play again.
    assert memory.excluded(world, ball, [Candidate(2, 1.9, 0.0), Candidate(3, 2.1, 0.0)]) is None


def test_the_set_piece_taker_is_free_again_after_the_wait():
    world = WorldModel(TEAM, 3)
    _hear(world, 10.0, mode="KickIn_Left")
    memory = TakerMemory()
    memory.update(world, True, 2)
    _hear(world, 10.5)
    memory.update(world, None, 2)
    _hear(world, 10.6 + TAKER_WAIT_S)
    assert memory.excluded(world, (0.0, 0.0), [Candidate(2, -0.5, 0.0)]) is None


def test_opponent_set_pieces_and_play_on_are_told_apart():
    assert own_set_piece("corner_kick_right", "right") is True
    assert own_set_piece("corner_kick_right", "left") is False
    assert own_set_piece("PlayOn", "left") is None


def test_the_baseline_sends_the_nearest_field_player_whatever_its_angle():
    ball = (0.0, 0.0)
    # Unum 3 is nearer but in front of the ball: our cost rule sends 2, the baseline sends 3.
    players = [Candidate(1, -0.5, 0.0), Candidate(2, -1.5, 0.0), Candidate(3, 1.0, 0.0)]
    assert choose_on_ball(players, ball, None) == 2
    assert nearest_to_ball(players, ball) == 3
