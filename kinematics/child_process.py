"""Children that end with their parent: every process the toolkit starts calls ``end_with_parent`` first.

Why: a server or pool worker whose parent was killed (SIGKILL, a crashed test, a closed terminal) would
otherwise live on, holding ports and cores. Two mechanisms, because each misses a case: Linux's
``PR_SET_PDEATHSIG`` signals at once but fires when the *thread* that forked exits, which a pool worker
forked from a short-lived thread would not survive; so it is used only where the caller says the parent
process is the forking thread's, and a daemon watchdog thread, polling the parent id, covers the rest.
Toolkit-wide (like ``ToolkitError``), kept in the base room that every other room may import.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import os
import signal
import sys
import threading

#: Seconds between two looks at the parent id; a child outlives a killed parent by at most this.
WATCHDOG_PERIOD_S = 0.25
#: prctl option that asks the kernel for a signal when the parent dies (linux/prctl.h).
PR_SET_PDEATHSIG = 1


def _load_libc() -> ctypes.CDLL | None:
    if not sys.platform.startswith("linux"):
        return None
    try:
        return ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
    except OSError:
        return None


#: libc, loaded once at import: ``set_parent_death_signal`` may run as a ``preexec_fn`` between fork and exec,
#: where loading a library (locks, allocation) could deadlock a threaded parent.
_LIBC = _load_libc()


def set_parent_death_signal(signal_number: int = signal.SIGTERM) -> bool:
    """Ask Linux to send ``signal_number`` here when the forking thread ends; False where not available.

    Usable as ``subprocess.Popen(..., preexec_fn=set_parent_death_signal)`` for children that are not Python.
    """
    return _LIBC is not None and _LIBC.prctl(PR_SET_PDEATHSIG, int(signal_number), 0, 0, 0) == 0


def _watch(parent_pid: int, period_s: float) -> None:
    event = threading.Event()
    while not event.wait(period_s):
        if os.getppid() != parent_pid:
            os._exit(0)  # parent gone: no cleanup can reach anyone any more, leave at once


def end_with_parent(parent_pid: int | None = None, death_signal: bool = False,
                    period_s: float = WATCHDOG_PERIOD_S) -> None:
    """Make this process end when its parent does (call it first thing in a child, or as a pool initializer).

    Args:
        parent_pid: the parent to outlive no longer; default the current parent. A child started by
            ``subprocess`` passes the pid its parent wrote on the command line, so a parent that died while
            the child started up is noticed too.
        death_signal: also ask the kernel for SIGTERM on the parent's death (immediate); only right when the
            thread that started this child lives as long as its process.
        period_s: watchdog period, s.
    """
    parent = os.getppid() if parent_pid is None else parent_pid
    if death_signal:
        set_parent_death_signal(signal.SIGTERM)
    if os.getppid() != parent:
        os._exit(0)
    threading.Thread(target=_watch, args=(parent, period_s), name="end-with-parent", daemon=True).start()
