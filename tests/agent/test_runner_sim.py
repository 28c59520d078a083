"""End to end over real sockets: the runner (and ``python -m agent``) against our TCP server."""

from __future__ import annotations

import math
import subprocess
import sys
import threading
import time

from agent import Agent, AgentConfig
from agent.errors import ServerUnreachable
from agent.formation import beam_spot
from agent.runner import ConnectionPolicy, run
from sim.engine import FrozenReferee, SimEngine
from sim.tcp_server import SimServer

FAST = ConnectionPolicy(connect_attempts=2, backoff_s=0.05, backoff_max_s=0.1, read_timeout_s=5.0, max_reconnects=0)


def test_runner_joins_beams_localizes_then_reports_the_lost_server():
    engine = SimEngine(seed=5, referee=FrozenReferee())
    server = SimServer(engine, agent_port=0, sync=True).start()
    agents: list[Agent] = []

    def make(config):
        agents.append(Agent(config))
        return agents[-1]

    outcome = {}

    def play():
        try:
            run(AgentConfig("Ours", 4), "127.0.0.1", server.agent_port, FAST, make_agent=make)
        except ServerUnreachable as error:
            outcome["error"] = error

    thread = threading.Thread(target=play, daemon=True)
    thread.start()
    deadline = time.monotonic() + 30.0
    while time.monotonic() < deadline and (not agents or agents[0].world.game.cycles < 120):
        time.sleep(0.05)
    world = agents[0].world
    spot = beam_spot(4)
    robot = engine.world.robot_of("left", 4)
    x, y, _ = engine.world.torso_position(robot.key)
    assert math.hypot(x - spot.x_m, y - spot.y_m) < 0.1  # beam noise is +-0.05 m per axis
    pose = world.pose
    assert pose is not None and math.hypot(pose.x_m - x, pose.y_m - y) < 0.05
    server.stop()
    thread.join(10.0)
    assert not thread.is_alive()
    assert "lost" in str(outcome["error"])


def test_cli_plays_against_our_server_and_exits_2_when_it_goes_away():
    engine = SimEngine(seed=6, referee=FrozenReferee())
    server = SimServer(engine, agent_port=0, sync=True).start()
    process = subprocess.Popen([sys.executable, "-m", "agent", "--port", str(server.agent_port), "--team", "Cli",
                                "--unum", "3", "--attempts", "2", "--log-level", "WARNING"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        def joined():
            return any(link.team == "Cli" and link.unum == 3 for link in list(engine.agents.values()))

        deadline = time.monotonic() + 60.0
        while time.monotonic() < deadline and not joined():  # a sync server free-runs until an agent comes
            time.sleep(0.05)
        assert joined(), process.stderr.read() if process.poll() is not None else "the agent never joined"
        start = engine.cycle
        while time.monotonic() < deadline and engine.cycle < start + 100:
            time.sleep(0.05)
        assert engine.cycle >= start + 100  # the agent answers every cycle with (syn)
        server.stop()
        _, stderr = process.communicate(timeout=30)
    finally:
        if process.poll() is None:
            process.kill()
    assert process.returncode == 2
    assert "no server answered" in stderr
