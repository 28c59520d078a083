"""`serve --kickoff auto|manual`, the printed line on how to start the game, and `motion-studio kickoff`."""

from __future__ import annotations

import socket
import subprocess
import sys
import threading

from agent.protocol.framing import FrameDecoder
from motion_studio.commands.serve import how_to_start
from sim.serve import ServeOptions, build_simulation_server

CLI = [sys.executable, "-m", "motion_studio"]


def test_serve_options_set_the_referees_kick_off_rule():
    for automatic, wait_s in ((True, 2.0), (False, None)):
        server, close = build_simulation_server(ServeOptions(agent_port=0, monitor_port=None, seed=1,
                                                             automatic_kick_off=automatic, kick_off_wait_s=wait_s))
        try:
            config = server.engine.referee.config
            assert config.automatic_kick_off is automatic
            assert config.wait_before_kick_off_s == (wait_s if wait_s is not None else 30.0)
        finally:
            server.stop()
            close()


def test_the_printed_lines_say_how_the_game_starts_and_how_to_watch():
    manual = "\n".join(how_to_start("127.0.0.1", 3201, automatic=False, wait_s=30.0))
    assert "motion-studio kickoff --port 3201" in manual and "--serverPort=3201" in manual
    assert "automatic, 5 s" in how_to_start("127.0.0.1", 3201, automatic=True, wait_s=5.0)[0]


def test_kickoff_sends_the_trainer_command_on_the_monitor_port():
    listener = socket.create_server(("127.0.0.1", 0))
    received: list[bytes] = []

    def accept() -> None:
        connection, _ = listener.accept()
        with connection:
            reader = FrameDecoder()
            while not received:
                data = connection.recv(4096)
                if not data:
                    break
                received.extend(reader.feed(data))

    thread = threading.Thread(target=accept, daemon=True)
    thread.start()
    port = listener.getsockname()[1]
    result = subprocess.run(CLI + ["kickoff", "--side", "Left", "--port", str(port)], capture_output=True, text=True,
                            timeout=120)
    thread.join(timeout=10)
    listener.close()
    assert result.returncode == 0, result.stderr
    assert received == [b"(kickOff Left)"]
    bad = subprocess.run(CLI + ["kickoff", "--side", "Middle", "--port", str(port)], capture_output=True, text=True,
                         timeout=120)
    assert bad.returncode == 2 and "--side" in bad.stderr and "Left, Right, None" in bad.stderr
    assert len(bad.stderr.strip().splitlines()) == 1
