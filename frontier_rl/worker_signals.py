"""Keeping Ctrl-C from worker processes while they start, for every package that spawns them
(evaluate's worker pool, the ROS node's per-robot workers).

A terminal sends SIGINT to the whole process group, so a worker interrupted while it starts (its
interpreter still unpickling and importing) prints a traceback. A worker is therefore spawned with
SIGINT blocked, which it inherits, and ignores it before unblocking: only the process that started
it sees a Ctrl-C, and it ends its workers itself.
"""

from __future__ import annotations

import contextlib
import signal
import threading
from collections.abc import Iterator
from multiprocessing import resource_tracker


@contextlib.contextmanager
def interrupts_held() -> Iterator[None]:
    """Hold a Ctrl-C until the block ends, then hand it to the SIGINT handler that was there
    before (Python's raises KeyboardInterrupt; an ignored Ctrl-C stays ignored): a process half
    spawned, or half ended, would print a traceback or be left behind. Processes started inside
    inherit SIGINT blocked. In another thread, or where the handler was not set from Python, only
    those processes are kept from it (a Ctrl-C goes to the main thread meanwhile)."""
    handler = signal.getsignal(signal.SIGINT)
    # an ignored Ctrl-C (a background job's) has nothing to hold: its handler, which may be one set
    # outside Python (rclpy's), is left alone
    holding = threading.current_thread() is threading.main_thread() and handler not in (None, signal.SIG_IGN)
    held: list[int] = []
    previous = signal.signal(signal.SIGINT, lambda signum, frame: held.append(signum)) if holding else None
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})  # inherited by the processes started here
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)  # a Ctrl-C pending meanwhile lands in `held`
        if holding:
            signal.signal(signal.SIGINT, previous)
            if held:
                signal.raise_signal(signal.SIGINT)


@contextlib.contextmanager
def spawning_workers() -> Iterator[None]:
    """:func:`interrupts_held`, for spawning worker processes that call :func:`ignore_interrupts`
    first. Multiprocessing's resource tracker is started before: starting it unblocks SIGINT (it
    does so for its own spawn), and the first worker would start with it unblocked."""
    resource_tracker.ensure_running()
    with interrupts_held():
        yield


def ignore_interrupts() -> None:
    """In a worker spawned inside :func:`spawning_workers`: ignore SIGINT from now on, dropping a
    Ctrl-C held while it started."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
