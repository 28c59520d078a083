"""What a test run left behind: processes carrying a tag in their environment, and who listens where.

Processes are found by an environment variable the test session (or one test) sets, because a killed
parent's children are re-parented to init and no longer show up as anyone's descendants; listeners by the
socket inodes in /proc/<pid>/fd matched against /proc/net/tcp and tcp6 (LISTEN rows).
"""

from __future__ import annotations

import ipaddress
import os
import queue
import re
import signal
import subprocess
import threading
import time
from pathlib import Path

TAG_VARIABLE = "NAO3D_TEST_TAG"
#: /proc/net/tcp state code of a listening socket.
TCP_LISTEN = "0A"


def as_foreground_child() -> None:
    """``preexec_fn`` of a command a test stops with SIGINT (Ctrl-C): SIGINT at its default, as in a terminal's
    foreground job (pytest started in the background by a script inherits SIGINT ignored, and so would the
    command: it then never sees the test's Ctrl-C), and ended by the kernel if pytest dies."""
    from kinematics.child_process import set_parent_death_signal

    signal.signal(signal.SIGINT, signal.SIG_DFL)
    set_parent_death_signal()


def tagged_processes(tag: str, exclude: set[int] = frozenset()) -> dict[int, str]:
    """pid -> command line of every live process whose environment holds ``NAO3D_TEST_TAG=<tag>``."""
    needle = f"{TAG_VARIABLE}={tag}".encode()
    found = {}
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit() or int(entry.name) in exclude:
            continue
        try:
            if needle not in (entry / "environ").read_bytes().split(b"\0"):
                continue
            if (entry / "stat").read_text().rsplit(")", 1)[1].split()[0] == "Z":
                continue  # a zombie holds nothing; its parent has just not reaped it yet
            found[int(entry.name)] = (entry / "cmdline").read_bytes().replace(b"\0", b" ").decode().strip()
        except (FileNotFoundError, ProcessLookupError, PermissionError):
            continue
    return found


def wait_until_gone(tag: str, timeout_s: float, exclude: set[int] = frozenset()) -> dict[int, str]:
    """Tagged processes still alive after up to ``timeout_s`` (empty once they have all ended)."""
    deadline = time.monotonic() + timeout_s
    while True:
        left = tagged_processes(tag, exclude)
        if not left or time.monotonic() > deadline:
            return left
        time.sleep(0.1)


def _address(hex_address: str) -> ipaddress.IPv4Address | ipaddress.IPv6Address:
    raw = bytes.fromhex(hex_address)
    # the kernel prints each 32-bit word in host (little-endian) order
    words = b"".join(raw[i:i + 4][::-1] for i in range(0, len(raw), 4))
    return ipaddress.ip_address(words)


def listeners() -> dict[int, tuple[str, int]]:
    """Socket inode -> (address, port) of every listening TCP socket of this network namespace."""
    found = {}
    for table in ("/proc/net/tcp", "/proc/net/tcp6"):
        try:
            rows = Path(table).read_text().splitlines()[1:]
        except FileNotFoundError:
            continue
        for row in rows:
            fields = row.split()
            if fields[3] != TCP_LISTEN:
                continue
            address, port = fields[1].split(":")
            found[int(fields[9])] = (str(_address(address)), int(port, 16))
    return found


def socket_inodes(pid: int) -> set[int]:
    inodes = set()
    try:
        for fd in Path(f"/proc/{pid}/fd").iterdir():
            try:
                target = os.readlink(fd)
            except OSError:
                continue
            if target.startswith("socket:["):
                inodes.add(int(target[8:-1]))
    except (FileNotFoundError, PermissionError):
        pass
    return inodes


def is_loopback(address: str) -> bool:
    parsed = ipaddress.ip_address(address)
    if isinstance(parsed, ipaddress.IPv6Address) and parsed.ipv4_mapped is not None:
        parsed = parsed.ipv4_mapped
    return parsed.is_loopback


def listening_addresses(pids: set[int]) -> list[tuple[int, str, int]]:
    """(pid, address, port) of every socket the processes ``pids`` listen on."""
    table = listeners()
    return [(pid, *table[inode]) for pid in sorted(pids) for inode in socket_inodes(pid) if inode in table]


def wait_for_line(process: subprocess.Popen, pattern: str, timeout_s: float = 120.0) -> re.Match:
    """The first output line matching ``pattern``; fails after ``timeout_s`` or when the process ends."""
    lines: queue.Queue[str] = queue.Queue()
    threading.Thread(target=lambda: [lines.put(line) for line in iter(process.stdout.readline, "")],
                     daemon=True).start()
    deadline = time.monotonic() + timeout_s
    seen = []
    while time.monotonic() < deadline:
        try:
            line = lines.get(timeout=0.2)
        except queue.Empty:
            assert process.poll() is None, f"ended (exit {process.poll()}) before printing {pattern!r}: {seen}"
            continue
        seen.append(line.strip())
        match = re.search(pattern, line)
        if match:
            return match
    raise AssertionError(f"no line matching {pattern!r} within {timeout_s} s: {seen}")
