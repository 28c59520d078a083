"""Two field players that each believe the other plays the ball (issue 15): nobody may stand for ever.

Found on the real rcssserver3d 0.7.3 (3 v 3 against robots that only stand, 120 s, seed 72 at b2a64a5): after our
goal the opponents' kick-off ran out, the ball lay on the centre spot in PlayOn, and our two field players stood
at (-2.5, 1.4) and (-2.5, -1.5), 2.9 m from it, for the last 58 s of the match. Their on-ball costs differ by about
0.1 m and the believed holder gets a 1 m bonus (REFERENCE §7.10's hysteresis), so once each player held the other
as the holder, neither one's choice could change while nobody moved. The scenario below crosses the two beliefs
on purpose at the start of PlayOn: before ``roles.HolderWatch`` nobody touched the ball in 25 s (seeds 0-3); with it
the first touch came 5.8-10.7 s after PlayOn (seeds 0-3; 4.8 s when the beliefs were not crossed).
"""

from __future__ import annotations

from tests.standing_opponents import our_team_against_standing


def test_crossed_holder_beliefs_do_not_leave_the_ball_lying():
    engine, host, keys = our_team_against_standing(seed=0)
    referee, world = engine.referee, engine.world
    referee.kick_off("Right")   # robots that only stand never take it: PlayOn after its 15 s
    while referee.play_mode != "PlayOn":
        host.run(1)
    world.place_robot(keys["Left", 2], -2.5, 1.4, -30.0)
    world.place_robot(keys["Left", 3], -2.5, -1.4, 30.0)
    host.run(10)
    behaviors = {unum: host.agents[keys["Left", unum]].behavior for unum in (2, 3)}
    behaviors[2].holder, behaviors[3].holder = 3, 2
    touched_after_s = _seconds_to_our_touch(engine, host, limit_s=25.0)
    assert touched_after_s is not None and touched_after_s < 15.0


def test_at_the_opponents_kick_off_both_field_players_name_the_same_receiver():
    """Crossed beliefs at the start of the opponents' kick-off: within the kick-off both players name unum 2 (the
    lowest field unum, ``roles.kick_off_receiver``), which waits behind the ball and plays it after PlayOn."""
    engine, host, keys = our_team_against_standing(seed=1)
    referee, world = engine.referee, engine.world
    referee.kick_off("Right")
    world.place_robot(keys["Left", 2], -2.5, 1.3, -30.0)   # where the kick-off beam leaves them: symmetric
    world.place_robot(keys["Left", 3], -2.5, -1.3, 30.0)
    host.run(2)
    behaviors = {unum: host.agents[keys["Left", unum]].behavior for unum in (2, 3)}
    for _ in range(150):   # crossed for 3 s, until both hear each other where they stand
        behaviors[2].holder, behaviors[3].holder = 3, 2
        host.run(1)
    host.run(5)
    assert behaviors[2].holder == behaviors[3].holder == 2
    while referee.play_mode != "PlayOn":
        host.run(1)
    touched_after_s = _seconds_to_our_touch(engine, host, limit_s=20.0)
    assert touched_after_s is not None and touched_after_s < 8.0
    assert ("left", 2) in world.ball_touchers()


def _seconds_to_our_touch(engine, host, limit_s: float) -> float | None:
    """Game seconds until a left player touches the ball (None within ``limit_s``)."""
    start_s = engine.referee.game_time_s
    while engine.referee.game_time_s < start_s + limit_s:
        host.run(1)
        if any(t[0] == "left" for t in engine.world.ball_touchers()):
            return engine.referee.game_time_s - start_s
    return None
