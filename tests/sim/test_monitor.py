"""Monitor messages against the real server's recorded monitor frames, and the log writer."""

from __future__ import annotations

import io
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from agent.protocol.sexpr import parse_sexpr
from sim.monitor import GameView, MonitorLogWriter, MonitorStream, RobotView, SceneSnapshot, environment_predicates
from sim.monitor_scene import _spell, compact_number, robot_body_order, translation
from sim.rules.params import default_config

SAMPLE = Path(__file__).resolve().parents[3] / "shared" / "samples" / "rcssserver3d-0.7.3_monitor_first_frames.txt"
BALL_INDEX = 35  # 2 lights, field, sky, 2 goals, 4 walls, 4 flags, 21 line transforms


def sample_lines() -> list[str]:
    if not SAMPLE.exists():
        pytest.skip("the recorded monitor sample is not available")
    return [line for line in SAMPLE.read_text().split("\n") if line]


def slt(node: list) -> tuple[float, ...] | None:
    for item in node[1:]:
        if isinstance(item, list) and item and item[0] == "SLT":
            return tuple(float(v) for v in item[1:])
    return None


def node_children(node: list) -> list[list]:
    return [item for item in node[1:] if isinstance(item, list) and item and item[0] == "nd"]


def recorded_state(line: str, previous: dict[str, tuple[float, ...]]) -> dict[str, tuple[float, ...]]:
    """Body and ball transforms sent in one recorded message (unsent ones keep their previous value)."""
    scene = parse_sexpr(line)[2]
    state = dict(previous)
    ball = slt(scene[BALL_INDEX])
    if ball is not None:
        state["ball"] = ball
    robot = scene[BALL_INDEX + 1]
    for name, body in zip(robot_body_order(0), node_children(robot)):
        matrix = slt(body)
        if matrix is not None:
            state[name] = matrix
    return state


def snapshot(state: dict[str, tuple[float, ...]]) -> SceneSnapshot:
    game = GameView(time_s=0.0, half=1, score_left=0, score_right=0, play_mode_index=0, team_left="Capture")
    bodies = {name: state[name] for name in robot_body_order(0)}
    return SceneSnapshot(game, state["ball"], (RobotView("left", 1, 0, bodies),))


def test_environment_header_matches_the_server() -> None:
    line = sample_lines()[0]
    assert line.startswith("(" + environment_predicates(default_config()) + "(time 0)(team_left Capture)")


def test_full_state_and_two_diffs_match_the_real_server_byte_for_byte() -> None:
    lines = sample_lines()
    stream = MonitorStream()
    state: dict[str, tuple[float, ...]] = {}
    for index, line in enumerate(lines[:3]):
        state = recorded_state(line, state)
        ours = stream.message(snapshot(state))
        assert ours == line, f"line {index + 1} differs at {next(i for i, (a, b) in enumerate(zip(ours, line)) if a != b)}"


def test_game_state_list_sends_changes_only_and_fouls_once() -> None:
    stream = MonitorStream()
    base = GameView(team_left="A", team_right="B")
    stream.message(SceneSnapshot(base))
    later = GameView(time_s=41.22, score_left=1, play_mode_index=13, team_left="A", team_right="B",
                     fouls=((1, 4, 2, 7),))
    text = stream.message(SceneSnapshot(later))
    assert text.startswith("((time 41.22)(score_left 1)(play_mode 13)(foul 1 4 2 7))(RDS 0 1)(")
    again = stream.message(SceneSnapshot(later))
    assert again.startswith("((time 41.22))(RDS 0 1)")
    full = stream.message(SceneSnapshot(later), full=True)
    assert "(team_left A)(team_right B)(half 1)(score_left 1)(score_right 0)(play_mode 13))(RSG 0 1)" in full
    assert "(foul" not in full


def test_robot_materials_for_roboviz() -> None:
    stream = MonitorStream()
    text = stream.message(SceneSnapshot(GameView(), robots=(RobotView("right", 7, 4, {}),)))
    assert "(load models/naobody4.obj) (sSc 0.1 0.1 0.1)(resetMaterials matNum7 matRight matType4 naowhite)" in text
    assert text.count("models/lfoot.obj") == 2 and text.count("models/rfoot.obj") == 2  # feet and toes
    assert "models/rshank4.obj" in text


def test_new_robot_forces_full_state_and_small_moves_are_not_resent() -> None:
    stream = MonitorStream()
    game = GameView()
    stream.message(SceneSnapshot(game))
    assert "(RDS 0 1)" in stream.message(SceneSnapshot(game, translation(0, 0, 0.042)))
    assert "(RSG 0 1)" in stream.message(SceneSnapshot(game, robots=(RobotView("left", 2, 0, {}),)))
    nudged = stream.message(SceneSnapshot(game, translation(0.004, 0, 0.042), (RobotView("left", 2, 0, {}),)))
    assert "SLT" not in nudged
    moved = stream.message(SceneSnapshot(game, translation(0.5, 0, 0.042), (RobotView("left", 2, 0, {}),)))
    assert moved.count("(SLT") == 1 and "(SLT 1 0 0 0 0 1 0 0 0 0 1 0 0.5 0 0.042 1)" in moved


def test_log_writer_lines_full_states_and_period() -> None:
    out = io.StringIO()
    states = [SceneSnapshot(GameView(time_s=i * 0.02)) for i in range(400)]
    writer = MonitorLogWriter(out, lambda: states[current], step_cycles=2, full_state_every_s=3.0)
    for current in range(1, 400):
        writer.on_cycle(current)
    lines = out.getvalue().splitlines()
    assert len(lines) == 200  # first cycle, then every 2nd cycle
    kinds = ["RSG" if "(RSG 0 1)" in line else "RDS" for line in lines]
    assert kinds[0] == "RSG" and kinds.count("RSG") == 3  # at start, after 3 s and after 6 s
    assert all("\n" not in line and not line.startswith("\x00") for line in lines)


@settings(max_examples=300, deadline=None)
@given(st.lists(st.one_of(st.floats(allow_nan=False, allow_infinity=False, min_value=-1e4, max_value=1e4),
                          st.sampled_from([0.0, -0.0, 0.005, -0.005, 0.995, -0.0004999, 10.0, -10.0, 2.675])),
                min_size=16, max_size=16),
       st.sampled_from([(2, 3), (1, 1), (3, 2), (6, 6), (0, 3), (2, 0)]))
def test_a_transform_is_spelled_as_each_number_on_its_own(matrix, decimals):
    # the log's one-format spelling of a transform (sim.monitor_scene._spell) against compact_number per element
    expected = [compact_number(value, decimals[1] if 12 <= i <= 14 else decimals[0]) for i, value in enumerate(matrix)]
    assert _spell(tuple(matrix), decimals) == expected
