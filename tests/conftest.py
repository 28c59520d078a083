"""Session-wide check: the test suite leaves no process and no non-loopback listener behind (issue 16).

Every process the suite starts inherits ``NAO3D_TEST_TAG``; at the end of the session, after a short grace
for children that watch their parent, any tagged process still alive, or any socket the suite's processes
listen on outside loopback, fails the session (exit status 1) with the list.
"""

from __future__ import annotations

import os
import uuid

from tests.process_audit import TAG_VARIABLE, is_loopback, listening_addresses, tagged_processes, wait_until_gone

#: Seconds a child of a finished test may take to notice and end.
GRACE_S = 5.0


def pytest_configure(config) -> None:  # noqa: ANN001 - pytest.Config
    os.environ.setdefault(TAG_VARIABLE, f"session-{uuid.uuid4().hex}")


def pytest_sessionfinish(session, exitstatus) -> None:  # noqa: ANN001 - pytest.Session
    if hasattr(session.config, "workerinput"):
        return  # an xdist worker; the controller checks
    tag = os.environ[TAG_VARIABLE]
    me = os.getpid()
    left = wait_until_gone(tag, GRACE_S, exclude={me})
    exposed = [(pid, address, port) for pid, address, port in listening_addresses({me, *left})
               if not is_loopback(address)]
    problems = [f"left running: pid {pid}: {command}" for pid, command in left.items()]
    problems += [f"listening outside loopback: pid {pid} on {address}:{port}" for pid, address, port in exposed]
    reporter = session.config.pluginmanager.get_plugin("terminalreporter")
    if problems:
        if reporter is not None:
            reporter.write_sep("=", "processes or listeners left behind (tests/conftest.py)", red=True)
            for line in problems:
                reporter.write_line(line)
        session.exitstatus = 1
    elif reporter is not None:
        reporter.write_line(f"process audit: no process left, no listener outside loopback ({tag})")
