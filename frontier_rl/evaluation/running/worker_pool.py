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
import pickle
import threading
import time
import traceback
from collections import deque
from collections.abc import Callable, Generator, Iterable, Sequence
from dataclasses import dataclass, field
from multiprocessing.connection import Connection, wait
from multiprocessing.process import BaseProcess
from multiprocessing.reduction import ForkingPickler
from typing import Any

from frontier_rl.errors import FrontierRLError
from frontier_rl.worker_signals import ignore_interrupts, interrupts_held, spawning_workers

Task = tuple[Callable[..., Any], tuple[Any, ...]]
"""A function and its arguments; both are pickled to the worker."""

_STOP_WAIT_S = 5.0
"""How long a terminated worker may take to end before it is killed (s)."""


class WorkerDiedError(FrontierRLError):
    """A worker process ended while it ran a task (killed, or out of memory).

    Attributes:
        exit_code: the process's exit code (negative: the signal that ended it); None where not known.
    """

    def __init__(self, message: str, exit_code: int | None = None) -> None:
        super().__init__(message)
        self.exit_code = exit_code


def exit_with_parent(parent: int) -> None:
    """End this worker when the process that started it is gone (killed with SIGKILL, it cannot
    end its workers), instead of finishing an episode no one will read."""

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(0.5)
        os._exit(1)

    threading.Thread(target=watch, daemon=True).start()


class RemoteTracebackError(Exception):
    """The traceback, as text, of an exception a task raised in a worker (set as its ``__cause__``)."""

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else ""


@dataclass(frozen=True)
class _Failed:
    """A task's exception, with its traceback as text, on its way back from a worker."""

    exception: BaseException
    traceback: str = ""


def _serve(conn: Connection, parent: int) -> None:
    """A worker's loop: run each task the pipe brings, send back its result or :class:`_Failed`;
    end when the pipe closes."""
    ignore_interrupts()
    exit_with_parent(parent)
    while True:
        try:
            message = conn.recv_bytes()
        except EOFError:
            return
        try:
            function, args = pickle.loads(message)  # a task whose function cannot be found here fails alone
            outcome = function(*args)
        except Exception as exc:  # handed back: the task failed, the worker goes on
            outcome = _Failed(exc, "".join(traceback.format_exception(exc)))
        try:
            data = ForkingPickler.dumps(outcome)
        except Exception as exc:  # the outcome cannot be pickled
            why = f"the task's outcome could not be sent back: {type(exc).__name__}: {exc}"
            data = ForkingPickler.dumps(_Failed(RuntimeError(why)))
        conn.send_bytes(data)


@dataclass(eq=False)
class _Worker:
    process: BaseProcess
    conn: Connection
    task: int | None = field(default=None)
    """Index of the task it runs, None when idle."""


class WorkerPool:
    """``workers`` spawned processes, each running one task at a time; use as a context manager.
    Leaving it (normally, on an error or on Ctrl-C) terminates every worker and waits for them.
    Tasks are run from one thread; :meth:`close` may come from another."""

    def __init__(self, workers: int) -> None:
        if workers < 1:
            raise ValueError(f"a pool needs at least one worker, got {workers}")
        self._context = multiprocessing.get_context("spawn")
        self._workers: list[_Worker] = []
        self._iterating = False
        self._lock = threading.RLock()
        try:
            with spawning_workers():
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
        """A new worker (call inside :func:`~frontier_rl.worker_signals.spawning_workers`)."""
        ours, theirs = self._context.Pipe()
        process = self._context.Process(target=_serve, args=(theirs, os.getpid()), daemon=True)
        process.start()
        theirs.close()
        return _Worker(process, ours)

    def imap_unordered(self, tasks: Sequence[Task]) -> Generator[tuple[int, Any], None, None]:
        """Run every task; yield ``(index, result)`` as each finishes, where a task that raised (or
        whose worker died) gives its exception as the result. One loop at a time; leaving it
        before its end closes the pool: its workers still run tasks no one will read."""
        if self._iterating:
            raise ValueError("the worker pool is running another loop over tasks")
        self._iterating = True
        todo = deque(range(len(tasks)))
        resent: set[int] = set()
        finished = False
        try:
            while todo or any(w.task is not None for w in self._workers):
                if not self._workers:
                    raise ValueError("the worker pool is closed")
                for slot, worker in enumerate(self._workers):
                    if worker.task is None and todo:
                        index = todo.popleft()
                        failure = self._send(slot, index, tasks[index])
                        if failure is None:
                            continue
                        if isinstance(failure, WorkerDiedError) and index not in resent:
                            resent.add(index)  # it never reached a worker: once more
                            todo.appendleft(index)
                        else:
                            yield index, failure
                busy = [w for w in self._workers if w.task is not None]
                if busy:
                    ready = wait([w.conn for w in busy] + [w.process.sentinel for w in busy])
                    for worker in busy:
                        if worker.conn in ready or worker.process.sentinel in ready:
                            yield self._collect(worker)
            finished = True
        finally:
            self._iterating = False
            if not finished:
                self.close()

    def _send(self, slot: int, index: int, task: Task) -> BaseException | None:
        """Hand task ``index`` to the idle worker in ``slot`` (a fresh one if it has ended); the
        reason it could not be sent, if so."""
        if not self._workers[slot].process.is_alive():
            self._replace(self._workers[slot])
        worker = self._workers[slot]
        try:
            data = ForkingPickler.dumps(task)
        except Exception as exc:  # the task cannot be pickled
            return exc
        try:
            worker.conn.send_bytes(data)
        except OSError:  # the worker ended meanwhile
            self._replace(worker)
            return WorkerDiedError("its worker process had ended")
        worker.task = index
        return None

    def _collect(self, worker: _Worker) -> tuple[int, Any]:
        """The outcome of ``worker``'s task; a dead worker is replaced by a fresh one."""
        index, worker.task = worker.task, None
        assert index is not None
        try:
            data = worker.conn.recv_bytes()
        except (EOFError, OSError):  # it ended before sending the outcome, or while sending it
            code = self._replace(worker)
            return index, WorkerDiedError(
                f"its worker process ended (exit code {code}) before sending its outcome", code
            )
        try:
            outcome = pickle.loads(data)
        except Exception as exc:  # cannot be unpickled here
            return index, exc
        if isinstance(outcome, _Failed):
            if outcome.traceback:
                outcome.exception.__cause__ = RemoteTracebackError(outcome.traceback)
            return index, outcome.exception
        return index, outcome

    def _replace(self, worker: _Worker) -> int | None:
        """Put a fresh worker in the place of ``worker``, which has ended (or is ended here); its
        exit code. None is started if the pool was closed meanwhile."""
        worker.conn.close()
        if worker.process.is_alive():
            worker.process.terminate()
        _end(worker.process, time.monotonic())
        with self._lock:  # a close() from another thread waits for the new worker, and ends it
            if worker in self._workers:
                slot = self._workers.index(worker)
                with spawning_workers():
                    self._workers[slot] = self._start()
        return worker.process.exitcode

    def map(self, function: Callable[[Any], Any], items: Iterable[Any]) -> list[Any]:
        """``function(item)`` for every item, in order; a task that raised gives its exception."""
        tasks = [(function, (item,)) for item in items]
        results: list[Any] = [None] * len(tasks)
        with contextlib.closing(self.imap_unordered(tasks)) as outcomes:
            for index, result in outcomes:
                results[index] = result
        return results

    def close(self) -> None:
        """Terminate every worker and wait for it (killed after :data:`_STOP_WAIT_S`)."""
        with self._lock:
            if not self._workers:
                return
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
