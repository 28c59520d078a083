"""Match batches on a Ray cluster: a ``concurrent.futures.Executor`` whose tasks are Ray tasks.

Why an adapter and not Ray's own pool: `sim.match_batch.run_batch` already takes any executor and keeps the
checkpoint on the driver (each result is appended as its future completes), so a batch on a cluster resumes
exactly like a local one. Ray's ``ObjectRef.future()`` gives a standard future, so the adapter is small.

Each match is one Ray task asking for one CPU (MuJoCo and our agents are single-threaded). The workers must
have this toolkit installed at the same version (same constraints.txt); the monitor logs a match writes land
on the machine that played it, at the configured path (results, which carry everything the report needs,
come back to the driver).

Usage: ``motion-studio match --matches 40 --ray auto`` on a node of a running cluster (``ray start --head``
then ``ray start --address=HEAD:6379`` on the others), or ``--ray local`` for a Ray instance on this machine.
"""

from __future__ import annotations

import logging
import socket
from collections.abc import Callable
from concurrent.futures import Executor, Future
from typing import Any

logger = logging.getLogger(__name__)

#: ``--ray`` value that starts a private Ray instance on this machine instead of joining a cluster.
#: Address a local Ray instance binds (its GCS, raylet and object-manager ports).
LOOPBACK = "127.0.0.1"
LOCAL = "local"


class RayUnavailable(RuntimeError):
    """Ray is missing or its cluster cannot be reached; the message says which and where."""


#: How long to wait for a cluster's port before giving up [s] (Ray itself retries for minutes).
REACH_TIMEOUT_S = 5.0


def check_reachable(address: str, timeout_s: float = REACH_TIMEOUT_S) -> None:
    """Fail fast on a ``HOST:PORT`` (or ``ray://HOST:PORT``) that nothing listens on.

    Raises:
        RayUnavailable: the port does not accept a TCP connection within ``timeout_s``.
    """
    hostport = address.split("://", 1)[-1]
    host, _, port = hostport.rpartition(":")
    if not host or not port.isdigit():
        return  # "auto" and other forms are Ray's to resolve (it fails fast on them)
    try:
        with socket.create_connection((host, int(port)), timeout=timeout_s):
            pass
    except OSError as error:
        raise RayUnavailable(f"cannot reach the Ray cluster at {address!r}: {error}") from error


class RayExecutor(Executor):
    """Runs submitted functions as Ray tasks (one CPU each).

    Args:
        address: a cluster address (``auto``, ``HOST:PORT``, ``ray://HOST:10001``) or ``local`` for a new
            Ray instance on this machine.
        num_cpus: with ``local``, the CPUs Ray may use (default: all of this machine's).

    Raises:
        RayUnavailable: Ray is not installed or the cluster cannot be reached (the message says which).
    """

    def __init__(self, address: str = LOCAL, num_cpus: int | None = None) -> None:
        try:
            import ray
        except ImportError as error:  # pragma: no cover - ray is in constraints.txt
            raise RayUnavailable("--ray needs the 'ray' package (pip install -c constraints.txt ray)") from error
        self._ray = ray
        self._started_here = not ray.is_initialized()
        if self._started_here:
            options: dict[str, Any] = {"include_dashboard": False, "log_to_driver": False,
                                       "logging_level": logging.WARNING}
            if address != LOCAL:
                check_reachable(address)
            try:
                if address == LOCAL:  # a Ray of our own serves this process only: loopback, as every server here
                    ray.init(num_cpus=num_cpus, _node_ip_address=LOOPBACK, **options)
                else:
                    ray.init(address=address, **options)
            except (ConnectionError, RuntimeError, ValueError) as error:
                raise RayUnavailable(f"cannot reach the Ray cluster at {address!r}: {error}") from error
        self._remote_cache: dict[Callable[..., Any], Any] = {}

    @property
    def cluster_cpus(self) -> int:
        """CPUs the cluster offers now (how many matches run at once)."""
        return int(self._ray.cluster_resources().get("CPU", 0))

    def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> Future:
        """Run ``fn(*args, **kwargs)`` as a Ray task; ``fn`` and its arguments must pickle (module-level)."""
        remote = self._remote_cache.get(fn)
        if remote is None:
            remote = self._ray.remote(num_cpus=1, max_retries=0)(fn)
            self._remote_cache[fn] = remote
        return remote.remote(*args, **kwargs).future()

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        """Leave the cluster (a Ray instance started here stops; a joined cluster keeps running)."""
        if self._started_here and self._ray.is_initialized():
            self._ray.shutdown()


__all__ = ["LOCAL", "RayExecutor", "RayUnavailable", "check_reachable"]
