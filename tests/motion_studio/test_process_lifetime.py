"""Servers bind loopback only and their children end with them, however they are stopped (issue 16 item 1).

Real processes and real sockets: ``motion-studio view`` (meshcat's web and ZMQ ports, in a child process),
``motion-studio serve`` (agent and monitor ports) and a ``match`` batch's pool workers, each stopped by Ctrl-C
(SIGINT to the process group, as a terminal sends it), SIGTERM or SIGKILL to the parent alone.
"""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import time
import uuid

import pytest

from tests.process_audit import (TAG_VARIABLE, as_foreground_child, is_loopback, listening_addresses,
                                 tagged_processes, wait_for_line, wait_until_gone)

CLI = [sys.executable, "-m", "motion_studio"]
#: Seconds a child may take to notice its parent is gone (its watchdog looks four times a second).
END_TIMEOUT_S = 5.0


def start(args: list[str], tag: str) -> subprocess.Popen:
    env = dict(os.environ, **{TAG_VARIABLE: tag})
    # its own session, so a SIGINT to its group is what a terminal's Ctrl-C would be, and reaches no test
    return subprocess.Popen(CLI + args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env,
                            start_new_session=True, preexec_fn=as_foreground_child)  # gone if pytest is killed


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def stop(process: subprocess.Popen, how: str) -> None:
    if how == "SIGINT":
        os.killpg(process.pid, signal.SIGINT)
    else:
        process.send_signal(getattr(signal, how))
    process.wait(timeout=30)


def cleanup(tag: str) -> None:
    for pid in tagged_processes(tag):  # only after a failure: ours, found by the tag this test set
        os.kill(pid, signal.SIGKILL)


@pytest.mark.parametrize("how", ["SIGINT", "SIGTERM", "SIGKILL"])
def test_view_serves_meshcat_on_loopback_and_its_server_ends_with_it(how):
    tag = f"view-{uuid.uuid4().hex}"
    process = start(["view", "-j", "llj3=20"], tag)
    try:
        wait_for_line(process, r"meshcat viewer: http://127\.0\.0\.1:\d+")
        processes = tagged_processes(tag)
        assert len(processes) == 2, processes  # view and meshcat's server
        listening = listening_addresses(set(processes))
        assert len(listening) >= 2, listening  # web and ZMQ
        assert all(is_loopback(address) for _, address, _ in listening), listening
        stop(process, how)
        assert wait_until_gone(tag, END_TIMEOUT_S) == {}
    finally:
        cleanup(tag)


def test_serve_listens_on_loopback_only_and_stops_on_sigterm():
    tag = f"serve-{uuid.uuid4().hex}"
    process = start(["serve", "--port", "0", "--monitor-port", str(free_port())], tag)
    try:
        match = wait_for_line(process, r"agent port (\d+), monitor/trainer port (\d+)")
        listening = listening_addresses(set(tagged_processes(tag)))
        ports = {port for _, _, port in listening}
        assert {int(match.group(1)), int(match.group(2))} <= ports
        assert all(is_loopback(address) for _, address, _ in listening), listening
        stop(process, "SIGTERM")
        assert wait_until_gone(tag, END_TIMEOUT_S) == {}
    finally:
        cleanup(tag)


def test_match_pool_workers_end_when_the_parent_is_killed(tmp_path):
    tag = f"match-{uuid.uuid4().hex}"
    process = start(["match", "--players", "1", "--duration", "60", "--matches", "2", "--workers", "2",
                     "--no-log", "--out", str(tmp_path)], tag)
    try:
        deadline = time.monotonic() + 60
        while len(tagged_processes(tag)) < 3 and time.monotonic() < deadline:  # the parent and two workers
            assert process.poll() is None, process.stdout.read()
            time.sleep(0.2)
        assert len(tagged_processes(tag)) >= 3
        stop(process, "SIGKILL")
        assert wait_until_gone(tag, END_TIMEOUT_S) == {}
    finally:
        cleanup(tag)


@pytest.mark.parametrize("how", ["SIGINT", "SIGKILL"])
def test_match_agent_workers_end_with_the_match_process(tmp_path, how):
    # a single match runs its agents in two worker processes by default (sim.agent_processes)
    tag = f"match-agents-{uuid.uuid4().hex}"
    process = start(["match", "--players", "2", "--duration", "60", "--no-log", "--out", str(tmp_path)], tag)
    try:
        deadline = time.monotonic() + 60
        while len(tagged_processes(tag)) < 3 and time.monotonic() < deadline:  # the match and two workers
            assert process.poll() is None, process.stdout.read()
            time.sleep(0.2)
        assert len(tagged_processes(tag)) >= 3
        stop(process, how)
        assert wait_until_gone(tag, END_TIMEOUT_S) == {}
    finally:
        cleanup(tag)
