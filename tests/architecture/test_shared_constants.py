"""The cycle length and the field are defined once, in agent.protocol.constants, which agent and sim import.

Read from the code (as the room-graph test reads imports): no module of agent/, sim/ or motion_studio/ assigns
its own CYCLE_S or field dimension, and every view of the field (the agent's lines and landmarks, sim's drawn
lines and colliders, the referee's rules) is built from the shared numbers.
"""

from __future__ import annotations

import ast
from pathlib import Path

import agent.world.field as agent_field
import sim.field as sim_field
from agent.protocol import constants
from sim.physics_params import PhysicsParams
from sim.rules.params import default_config

ROOT = Path(__file__).resolve().parents[2]
SHARED_NAMES = {"CYCLE_S", "FIELD_LENGTH_M", "FIELD_WIDTH_M", "HALF_LENGTH_M", "HALF_WIDTH_M", "GOAL_WIDTH_M",
                "GOAL_HALF_WIDTH_M", "GOAL_HEIGHT_M", "GOAL_DEPTH_M", "PENALTY_DEPTH_M", "PENALTY_HALF_WIDTH_M",
                "PENALTY_AREA_X_M", "CENTRE_CIRCLE_RADIUS_M", "BALL_MASS_KG", "AGENT_RADIUS_M"}


def own_definitions(path: Path) -> list[str]:
    """Names of SHARED_NAMES this module assigns a number to at its top level."""
    found = []
    for node in ast.parse(path.read_text()).body:
        targets = node.targets if isinstance(node, ast.Assign) else [node.target] if isinstance(node, ast.AnnAssign) \
            else []
        value = getattr(node, "value", None)
        for target in targets:
            if isinstance(target, ast.Name) and target.id in SHARED_NAMES and isinstance(value, ast.Constant):
                found.append(target.id)
    return found


def test_no_room_defines_its_own_cycle_length_or_field():
    offenders = []
    for room in ("agent", "sim", "motion_studio"):
        for path in sorted((ROOT / room).rglob("*.py")):
            relative = path.relative_to(ROOT).as_posix()
            if relative == "agent/protocol/constants.py":
                continue
            offenders += [f"{relative}: {name}" for name in own_definitions(path)]
    assert not offenders, "define these in agent/protocol/constants.py and import them:\n" + "\n".join(offenders)


def test_motions_cycle_length_matches_the_shared_one():
    """motions/ may not import agent/ (DESIGN.md), so its authoring tools keep a copy, held equal here."""
    import motions.authoring.gait as gait
    import motions.authoring.turn as turn

    assert gait.CYCLE_S == turn.CYCLE_S == constants.CYCLE_S


def test_agent_and_sim_see_the_same_field():
    assert agent_field.LANDMARKS == {name: constants.LANDMARKS[name] for name in agent_field.LANDMARKS}
    assert set(agent_field.LANDMARKS) == set(sim_field.LANDMARK_NAMES)

    def undirected(segments) -> set:
        return {frozenset((tuple(round(float(v), 9) for v in a[:2]), tuple(round(float(v), 9) for v in b[:2])))
                for a, b in segments}

    assert len(agent_field.FIELD_LINES) == len(sim_field.FIELD_LINES_M) == 21
    assert undirected(agent_field.FIELD_LINES) == undirected(sim_field.FIELD_LINES_M)


def test_rules_and_physics_use_the_shared_numbers():
    rules = default_config()
    assert rules.cycle_s == PhysicsParams().cycle_s == constants.CYCLE_S
    assert (rules.field_length_m, rules.field_width_m) == (constants.FIELD_LENGTH_M, constants.FIELD_WIDTH_M)
    assert (rules.goal_width_m, rules.goal_height_m, rules.goal_depth_m) == (
        constants.GOAL_WIDTH_M, constants.GOAL_HEIGHT_M, constants.GOAL_DEPTH_M)
    assert (rules.ball_radius_m, rules.ball_mass_kg, rules.agent_radius_m) == (
        constants.BALL_RADIUS_M, constants.BALL_MASS_KG, constants.AGENT_RADIUS_M)
