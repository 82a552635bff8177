"""A pool of spawned worker processes that Ctrl-C ends cleanly.

The standard library's ``ProcessPoolExecutor`` was not up to a Ctrl-C: the terminal sends SIGINT to
the whole process group, so workers interrupted while they started printed tracebacks, and about
one interrupt in five left the command hanging at exit, joining the pool's manager thread. Here
workers are spawned with SIGINT blocked and ignore it, so only this process sees a Ctrl-C; it ends
its workers itself, and there is no thread to join. A worker that dies (killed, out of memory)
fails only its own task: a fresh worker takes the next one.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import signal
import threading
import time
from collections import deque
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from multiprocessing import resource_tracker
from multiprocessing.connection import Connection, wait
from multiprocessing.process import BaseProcess
from typing import Any

from frontier_rl.errors import FrontierRLError

Task = tuple[Callable[..., Any], tuple[Any, ...]]
"""A function and its arguments; both are pickled to the worker."""

_STOP_WAIT_S = 5.0
"""How long a terminated worker may take to end before it is killed (s)."""


class WorkerDiedError(FrontierRLError):
    """A worker process ended while it ran a task (killed, or out of memory)."""


def exit_with_parent(parent: int) -> None:
    """End this worker when the process that started it is gone (killed with SIGKILL, it cannot
    end its workers), instead of finishing an episode no one will read."""

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(0.5)
        os._exit(1)

    threading.Thread(target=watch, daemon=True).start()


def _serve(conn: Connection, parent: int) -> None:
    """A worker's loop: run each task the pipe brings, send back its result or the exception it
    raised; end when the pipe closes."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # drops a Ctrl-C held while this process started
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
    exit_with_parent(parent)
    while True:
        try:
            function, args = conn.recv()
        except EOFError:
            return
        try:
            outcome = function(*args)
        except Exception as exc:  # handed back: the task failed, the worker goes on
            outcome = exc
        try:
            conn.send(outcome)
        except Exception as exc:  # the outcome cannot be pickled (nothing was sent yet)
            conn.send(RuntimeError(f"the task's outcome could not be sent back: {type(exc).__name__}: {exc}"))


@contextlib.contextmanager
def interrupts_held() -> Iterator[None]:
    """Hold a Ctrl-C until the block ends, then raise it: a process half spawned, or half ended,
    would print a traceback or be left behind. Processes started inside inherit SIGINT blocked.
    Only the main thread can do this; elsewhere the block runs as it is."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    held: list[int] = []
    previous = signal.signal(signal.SIGINT, lambda signum, frame: held.append(signum))
    signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})  # a pending Ctrl-C lands in `held`
        signal.signal(signal.SIGINT, previous)
    if held:
        raise KeyboardInterrupt


@contextlib.contextmanager
def _spawning() -> Iterator[None]:
    """:func:`interrupts_held`, for spawning workers. Multiprocessing's resource tracker is started
    first: starting it unblocks SIGINT (it does so for its own spawn), and the first worker would
    start with it unblocked."""
    resource_tracker.ensure_running()
    with interrupts_held():
        yield


@dataclass(eq=False)
class _Worker:
    process: BaseProcess
    conn: Connection
    task: int | None = field(default=None)
    """Index of the task it runs, None when idle."""


class WorkerPool:
    """``workers`` spawned processes, each running one task at a time; use as a context manager.
    Leaving it (normally, on an error or on Ctrl-C) terminates every worker and waits for them."""

    def __init__(self, workers: int) -> None:
        if workers < 1:
            raise ValueError(f"a pool needs at least one worker, got {workers}")
        self._context = multiprocessing.get_context("spawn")
        self._workers: list[_Worker] = []
        try:
            with _spawning():
                for _ in range(workers):
                    self._workers.append(self._start())
        except BaseException:  # Ctrl-C, or a process that could not start: end those that did
            self.close()
            raise

    def __enter__(self) -> WorkerPool:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    def _start(self) -> _Worker:
        """A new worker (call inside :func:`_spawning`)."""
        ours, theirs = self._context.Pipe()
        process = self._context.Process(target=_serve, args=(theirs, os.getpid()), daemon=True)
        process.start()
        theirs.close()
        return _Worker(process, ours)

    def imap_unordered(self, tasks: Sequence[Task]) -> Iterator[tuple[int, Any]]:
        """Run every task; yield ``(index, result)`` as each finishes, where a task that raised (or
        whose worker died) gives its exception as the result."""
        todo = deque(range(len(tasks)))
        while todo or any(w.task is not None for w in self._workers):
            for worker in self._workers:
                if worker.task is None and todo:
                    index = todo.popleft()
                    try:
                        worker.conn.send(tasks[index])
                        worker.task = index
                    except OSError:  # the idle worker is gone
                        self._replace(worker)
                        yield index, WorkerDiedError("its worker process had ended")
                    except Exception as exc:  # the task cannot be pickled: nothing was sent
                        yield index, exc
            busy = [w for w in self._workers if w.task is not None]
            if not busy:
                continue
            ready = wait([w.conn for w in busy] + [w.process.sentinel for w in busy])
            for worker in busy:
                if worker.conn in ready or worker.process.sentinel in ready:
                    yield self._collect(worker)

    def _collect(self, worker: _Worker) -> tuple[int, Any]:
        """The outcome of ``worker``'s task; a dead worker is replaced by a fresh one."""
        index, worker.task = worker.task, None
        assert index is not None
        try:
            return index, worker.conn.recv()
        except EOFError:
            code = self._replace(worker)
            return index, WorkerDiedError(f"its worker process ended (exit code {code}) while running it")
        except Exception as exc:  # sent whole but cannot be unpickled here: the pipe is still in step
            return index, exc

    def _replace(self, worker: _Worker) -> int | None:
        """Put a fresh worker in the place of ``worker``, which has ended; its exit code."""
        worker.conn.close()
        _end(worker.process, time.monotonic())
        with _spawning():
            self._workers[self._workers.index(worker)] = self._start()
        return worker.process.exitcode

    def map(self, function: Callable[[Any], Any], items: Iterable[Any]) -> list[Any]:
        """``function(item)`` for every item, in order; a task that raised gives its exception."""
        tasks = [(function, (item,)) for item in items]
        results: list[Any] = [None] * len(tasks)
        for index, result in self.imap_unordered(tasks):
            results[index] = result
        return results

    def close(self) -> None:
        """Terminate every worker and wait for it (killed after :data:`_STOP_WAIT_S`)."""
        with interrupts_held():
            for worker in self._workers:
                if worker.process.is_alive():
                    worker.process.terminate()
            start = time.monotonic()
            for worker in self._workers:
                _end(worker.process, start)
                worker.conn.close()
            self._workers = []


def _end(process: BaseProcess, since: float) -> None:
    """Wait for ``process`` to end until :data:`_STOP_WAIT_S` after ``since`` (monotonic s), then kill it."""
    process.join(max(0.0, since + _STOP_WAIT_S - time.monotonic()))
    if process.is_alive():
        process.kill()
        process.join()
