"""A recorded real session replayed open loop on our simulator: the recorded scene, answers and trainer
commands at their cycles, the full referee (as tests/sim/test_real_skill_traces.py replays them).

Open loop, so the replay compares physics alone: our robot gets the real agent's commands, not the commands
our agent would give on our simulator; joint errors add up over long closed-loop skills (walks).
"""

from __future__ import annotations

from dataclasses import dataclass

from agent.agent import Agent, AgentConfig
from motion_studio.realserver.cases import TEAM, UNUM, Case, MotionSource, behavior
from motion_studio.realserver.fixtures import Fixture
from motion_studio.realserver.skill_runs import Run, ScriptedAgent, record_completions
from motion_studio.scenarios import Truth
from sim.physics_params import PhysicsParams


@dataclass
class ReplayStates:
    """Our side of a replay: the state each sense message i reports (``ours[i]``), the sense messages our
    server sent, and how often the blow-up guard fired and the referee called a self-collision foul."""

    ours: dict[int, Truth]
    messages: list[bytes]
    blow_ups: int
    fouls: int


def replay_states(fixture: Fixture, physics: PhysicsParams | None = None) -> ReplayStates:
    """Replay ``fixture``'s commands on a fresh engine (the full referee: PlayOn rules and self-collision fouls,
    as the real server) with ``physics`` (the default parameters if None)."""
    from sim.engine import SimEngine
    from sim.inprocess import InProcessHost
    from sim.rules.trainer import apply_trainer_message

    agent = ScriptedAgent(fixture.replies)
    engine = SimEngine(seed=0, physics=physics)
    host = InProcessHost(engine)
    key = host.add(agent)
    world = engine.world
    move_cycle = fixture.meta.get("move_cycle")
    ours: dict[int, Truth] = {}
    blow_ups = world.divergences
    for _ in range(4 * len(fixture.received) + 100):   # a scene that never makes a robot must not hang
        if agent.received >= len(fixture.received):
            break
        count = agent.received
        host.run(1)
        if agent.received == count or key not in world.by_key:
            continue
        index = agent.received - 1
        # the engine delivers the message made at the end of the previous step, then steps: the world now
        # holds the state that message index + 1 will report
        rotation = world.torso_rotation(key)
        ours[index + 1] = Truth(world.time_s, tuple(world.torso_position(key).tolist()), float(rotation[2, 2]),
                                world.heading_deg(key), world.ball_position(), False)
        if index == move_cycle:
            # the trainer commands went out with the answer to this message: applied before the next step
            for command in fixture.meta["trainer"]:
                apply_trainer_message(command, engine.referee, world)
    return ReplayStates(ours, agent.messages, world.divergences - blow_ups, len(getattr(engine.referee, "fouls", [])))


def replay(fixture: Fixture, physics: PhysicsParams | None = None) -> tuple[Run, Run]:
    """The real run as recorded and ours replaying its commands, both indexed as ``skill_runs.Run`` (truth
    ``j`` = the state sense message ``skill_cycle + 1 + j`` reports). Completions are unknown (empty)."""
    states = replay_states(fixture, physics)
    first = fixture.skill_cycle + 1
    cycles = range(first, len(fixture.received) + 1)
    real = Run("real", [fixture.truth.get(i) for i in cycles])
    sim = Run("sim (replay)", [states.ours.get(i) for i in cycles])
    sim.blow_ups = states.blow_ups
    sim.fouls = states.fouls
    return real, sim


def agent_completions(fixture: Fixture, case: Case, motions: MotionSource) -> tuple[list[tuple[int, str]], float]:
    """The motions the recording agent completed, and when: our agent (``motions``, the fixture's revision) is
    fed the recorded sense messages again; it is deterministic, so it gives the recorded answers.

    Returns:
        (skill-phase cycle, motion name) per completed motion, as ``Run.completions``; the fraction of the
        recorded answers it gave again (1.0: the same agent and motions; vision is not in the fixture).
    """
    inner, fall_behavior = behavior(case, motions)
    agent = Agent(AgentConfig(TEAM, UNUM, case.robot_type, say=False), fall_behavior)
    agent.connect_message()
    rerun = Run("rerun", [])
    done: dict[str, int] = {}
    same = 0
    for index, payload in enumerate(fixture.received):
        if index == fixture.skill_cycle:
            inner.set_skill(case.make_skill())
            fall_behavior.start_cycle = fall_behavior.cycle + 1
        same += agent.step(payload) == fixture.replies.get(index)
        if index >= fixture.skill_cycle:
            record_completions(rerun, inner, done, index - fixture.skill_cycle)
        else:
            done = dict(inner.motion.completed)
    return rerun.completions, same / len(fixture.received)
