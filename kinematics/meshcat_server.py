"""Meshcat's server as a child process that binds loopback only and ends with its parent.

meshcat 0.3.2's own ``Visualizer()`` starts ``meshcat.servers.zmqserver`` in a new session (so Ctrl-C does not
reach it), binds its web port on every interface (``app.listen(port)``: 0.0.0.0 and [::]) and kills it only at
a clean interpreter exit: a killed parent leaves it running. Here the same bridge runs with both its ZMQ and
its web port on 127.0.0.1, in the parent's process group, watching its parent.

``python -m kinematics.meshcat_server --parent-pid PID`` is the child; ``loopback_visualizer()`` the parent side.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import os
import re
import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager

import meshcat

HOST = "127.0.0.1"
#: Seconds to wait for the child to print its URLs before giving up.
START_TIMEOUT_S = 60.0


class LoopbackVisualizer(meshcat.Visualizer):
    """A meshcat ``Visualizer`` connected to a loopback server child; ``close()`` ends the child."""

    def __init__(self, process: subprocess.Popen, zmq_url: str) -> None:
        with contextlib.redirect_stdout(io.StringIO()):  # meshcat prints the URL; the CLI decides what to print
            super().__init__(zmq_url=zmq_url)
        self.server_process = process

    def close(self) -> None:
        """End the server child (idempotent)."""
        process = self.server_process
        if process.poll() is None:
            process.terminate()
            try:
                process.wait(timeout=5.0)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()
        if process.stdout is not None:
            process.stdout.close()


def start_server() -> tuple[subprocess.Popen, str, str]:
    """Start the child; returns (process, zmq URL, web URL).

    Raises:
        RuntimeError: the child ended or printed no URL (its output is in the message).
    """
    command = [sys.executable, "-u", "-m", "kinematics.meshcat_server", "--parent-pid", str(os.getpid())]
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    urls: dict[str, str] = {}
    seen: list[str] = []
    while len(urls) < 2:
        line = process.stdout.readline()
        if not line:
            process.wait()
            raise RuntimeError(f"meshcat server ended (exit {process.returncode}): {' | '.join(seen)[-500:]}")
        seen.append(line.strip())
        match = re.match(r"(zmq_url|web_url)=(\S+)", line.strip())
        if match:
            urls[match.group(1)] = match.group(2)
    return process, urls["zmq_url"], urls["web_url"]


def loopback_visualizer() -> LoopbackVisualizer:
    """A meshcat visualizer whose server listens on 127.0.0.1 only and dies with this process; call close()."""
    process, zmq_url, _ = start_server()
    try:
        return LoopbackVisualizer(process, zmq_url)
    except BaseException:
        process.kill()
        process.wait()
        raise


@contextmanager
def visualizer() -> Iterator[LoopbackVisualizer]:
    """``with visualizer() as vis:`` for scenes written to a file: the server ends with the block."""
    vis = loopback_visualizer()
    try:
        yield vis
    finally:
        vis.close()


def _run_child(parent_pid: int) -> None:
    # Imported here: the parent side needs none of tornado's machinery.
    from meshcat.servers.zmqserver import ZMQWebSocketBridge

    from kinematics.child_process import end_with_parent

    class LoopbackBridge(ZMQWebSocketBridge):
        """meshcat's bridge with its web port bound to ``HOST`` (its ZMQ port already uses ``host``)."""

        def make_app(self):  # noqa: ANN202 - tornado Application
            app = super().make_app()
            listen = app.listen
            app.listen = lambda port, **kwargs: listen(port, address=HOST, **kwargs)
            return app

    end_with_parent(parent_pid, death_signal=True)
    bridge = LoopbackBridge(host=HOST)
    print(f"zmq_url={bridge.zmq_url}", flush=True)
    print(f"web_url={bridge.web_url}", flush=True)
    try:
        bridge.run()
    except KeyboardInterrupt:
        pass


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--parent-pid", type=int, required=True)
    _run_child(parser.parse_args().parent_pid)
