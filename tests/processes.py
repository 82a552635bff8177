"""Watching the processes a test starts, through /proc: their children, what they have loaded, and
whether they have exited."""

from __future__ import annotations

import signal
import time
from pathlib import Path


def sigint_as_in_a_terminal() -> None:
    """A ``preexec_fn`` for a process a test sends Ctrl-C to: SIGINT's default action, as a terminal's
    command has it, whatever the test process inherited (a background job, ``nohup make test &``,
    ignores SIGINT, and its children would too)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def children(pid: int) -> list[int]:
    """The processes ``pid`` started, of every one of its threads."""
    found = []
    for task in Path(f"/proc/{pid}/task").iterdir():
        try:
            found += [int(c) for c in (task / "children").read_text().split()]
        except FileNotFoundError:  # a thread that ended meanwhile
            continue
    return found


def spawned_workers(pid: int) -> list[int]:
    """The worker processes ``pid`` spawned (not multiprocessing's resource tracker)."""
    found = []
    for child in children(pid):
        try:
            if b"spawn_main" in Path(f"/proc/{child}/cmdline").read_bytes():
                found.append(child)
        except FileNotFoundError:
            continue
    return found


def workers_started(pid: int) -> bool:
    """Whether one of the process's spawned workers has started."""
    return bool(spawned_workers(pid))


def loads_numpy(pid: int) -> bool:
    """Whether the process is loading its modules (NumPy's compiled core is mapped)."""
    try:
        return "_multiarray_umath" in Path(f"/proc/{pid}/maps").read_text()
    except FileNotFoundError:  # it has ended
        return False


def gone(pid: int) -> bool:
    """Whether ``pid`` has exited."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except FileNotFoundError:
        return True
    return "State:\tZ" in status  # a zombie has exited (nobody reaps it in some containers)


def living_in_group(group: int) -> list[int]:
    """Processes of a process group that have not exited (zombies have)."""
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
            except (FileNotFoundError, ProcessLookupError):
                continue
            if int(fields[2]) == group and fields[0] != "Z":
                found.append(int(entry.name))
    return found


def left_in_group(group: int, wait_s: float = 10.0) -> list[int]:
    """The processes of a process group still alive after waiting up to ``wait_s`` (s) for them to end."""
    deadline = time.monotonic() + wait_s
    while time.monotonic() < deadline and living_in_group(group):
        time.sleep(0.1)
    return living_in_group(group)
