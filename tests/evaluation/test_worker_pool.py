"""The evaluation's worker pool: every task gets an outcome, whatever it does to its worker, and
closing the pool ends its workers at once."""

from __future__ import annotations

import importlib
import math
import operator
import os
import signal
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from frontier_rl.evaluation.running.worker_pool import RemoteTracebackError, WorkerDiedError, WorkerPool
from frontier_rl.worker_signals import interrupts_held

#: Closing is timed (within 3 s) and Ctrl-C is sent to this process: ``make test`` runs these alone.
pytestmark = pytest.mark.serial


@pytest.fixture(scope="module")
def pool() -> Iterator[WorkerPool]:
    with WorkerPool(2) as workers:
        yield workers


def test_results_come_back_in_order(pool: WorkerPool) -> None:
    assert pool.map(math.sqrt, [0.0, 1.0, 4.0, 9.0, 16.0]) == [0.0, 1.0, 2.0, 3.0, 4.0]


def test_a_task_that_raises_gives_its_exception_and_the_others_run(pool: WorkerPool) -> None:
    outcomes = dict(pool.imap_unordered([(operator.truediv, (1, 2)), (operator.truediv, (1, 0))]))
    assert outcomes[0] == 0.5
    assert isinstance(outcomes[1], ZeroDivisionError)
    cause = outcomes[1].__cause__  # where it was raised, as the worker saw it
    assert isinstance(cause, RemoteTracebackError) and "ZeroDivisionError" in str(cause)


class _PicklingFails:
    """An argument whose pickling raises OSError (as pickling an open connection may)."""

    def __reduce__(self) -> tuple[object, ...]:
        raise OSError("not picklable here")


def test_an_oserror_while_pickling_is_the_tasks_error_not_a_dead_worker(pool: WorkerPool) -> None:
    before = [w.process.pid for w in pool._workers]
    outcomes = dict(pool.imap_unordered([(abs, (_PicklingFails(),)), (abs, (-4,))]))
    assert isinstance(outcomes[0], OSError) and "not picklable here" in str(outcomes[0])
    assert outcomes[1] == 4
    assert [w.process.pid for w in pool._workers] == before  # no worker was ended for it


def test_one_loop_at_a_time(pool: WorkerPool) -> None:
    first = pool.imap_unordered([(abs, (-1,)), (abs, (-2,))])
    outcomes = [next(first)]
    with pytest.raises(ValueError, match="another loop"):
        next(pool.imap_unordered([(abs, (-3,))]))
    outcomes += list(first)  # the first loop goes on unharmed
    assert sorted(outcomes) == [(0, 1), (1, 2)]
    assert pool.map(abs, [-5]) == [5]  # and a loop after it may start


def test_a_task_the_worker_cannot_unpickle_fails_alone(pool: WorkerPool, tmp_path: Path) -> None:
    (tmp_path / "only_here.py").write_text("def double(x):\n    return 2 * x\n")
    sys.path.insert(0, str(tmp_path))  # after the workers started: they cannot import it
    try:
        only_here = importlib.import_module("only_here")
        outcomes = dict(pool.imap_unordered([(only_here.double, (2,)), (abs, (-5,))]))
    finally:
        sys.path.remove(str(tmp_path))
        sys.modules.pop("only_here", None)
    assert isinstance(outcomes[0], ModuleNotFoundError) and outcomes[1] == 5
    assert pool.map(abs, [-1, -2]) == [1, 2]  # no worker was lost


def test_tasks_and_results_that_cannot_be_pickled_fail_alone(pool: WorkerPool) -> None:
    outcomes = dict(pool.imap_unordered([(lambda: 1, ()), (threading.Lock, ()), (abs, (-3,))]))
    assert "pickle" in str(outcomes[0]).lower()  # never reached a worker
    assert isinstance(outcomes[1], RuntimeError) and "could not be sent back" in str(outcomes[1])
    assert outcomes[2] == 3


def test_a_worker_that_dies_fails_only_its_task_and_is_replaced(pool: WorkerPool) -> None:
    tasks = [(os._exit, (3,)), *[(abs, (-i,)) for i in range(6)], (os._exit, (4,)), (abs, (-9,))]
    outcomes = dict(pool.imap_unordered(tasks))
    assert isinstance(outcomes[0], WorkerDiedError) and "exit code 3" in str(outcomes[0])
    assert isinstance(outcomes[7], WorkerDiedError) and "exit code 4" in str(outcomes[7])
    assert [outcomes[i] for i in (*range(1, 7), 8)] == [0, 1, 2, 3, 4, 5, 9]
    assert pool.map(abs, [-1, -2]) == [1, 2]  # still two working workers


def test_a_worker_killed_while_idle_costs_no_task(pool: WorkerPool) -> None:
    os.kill(pool._workers[0].process.pid, signal.SIGKILL)  # as the out-of-memory killer would
    pool._workers[0].process.join(5)
    assert pool.map(abs, [-10, -20, -30, -40]) == [10, 20, 30, 40]


def test_a_worker_killed_before_it_reads_its_task_fails_that_task_only() -> None:
    """Killed while it still starts (importing takes most of a second), with its first task unread
    in its pipe: that task fails as a died worker's, and a fresh worker runs the next one."""
    with WorkerPool(1) as pool:
        victim = pool._workers[0].process.pid
        killer = threading.Timer(0.05, os.kill, (victim, signal.SIGKILL))
        killer.start()
        outcomes = dict(pool.imap_unordered([(abs, (-1,)), (abs, (-2,))]))
        killer.join()
    assert outcomes[0] == 1 or isinstance(outcomes[0], WorkerDiedError)  # 1: the kill came before the task
    assert outcomes[1] == 2


def test_closing_ends_running_tasks_at_once() -> None:
    pool = WorkerPool(2)
    processes = [w.process for w in pool._workers]
    running = pool.imap_unordered([(time.sleep, (60.0,)), (abs, (-1,))])
    assert next(running) == (1, 1)  # the other worker sleeps
    start = time.monotonic()
    pool.close()
    assert time.monotonic() - start < 3.0
    assert not any(p.is_alive() for p in processes)
    running.close()


def test_leaving_the_loop_early_closes_the_pool() -> None:
    pool = WorkerPool(2)
    processes = [w.process for w in pool._workers]
    running = pool.imap_unordered([(time.sleep, (60.0,)), (abs, (-1,))])
    assert next(running) == (1, 1)
    running.close()  # a result no one reads: its worker is ended
    assert not any(p.is_alive() for p in processes)
    with pytest.raises(ValueError, match="closed"):
        pool.map(abs, [1])


def test_a_loop_resumed_after_close_is_refused() -> None:
    pool = WorkerPool(1)
    running = pool.imap_unordered([(abs, (-1,)), (abs, (-2,)), (abs, (-3,))])
    assert next(running) == (0, 1)
    pool.close()
    with pytest.raises(ValueError, match="closed"):
        next(running)


def test_spawning_from_another_thread_keeps_ctrl_c_from_the_workers() -> None:
    masks: list[set[signal.Signals]] = []

    def spawn() -> None:
        with interrupts_held():
            masks.append(signal.pthread_sigmask(signal.SIG_BLOCK, []))
        masks.append(signal.pthread_sigmask(signal.SIG_BLOCK, []))

    thread = threading.Thread(target=spawn)
    thread.start()
    thread.join()
    assert signal.SIGINT in masks[0] and signal.SIGINT not in masks[1]


def test_held_interrupts_are_raised_when_the_block_ends() -> None:
    reached_end_of_block = False
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)  # as in a terminal, however pytest started
    try:
        with pytest.raises(KeyboardInterrupt), interrupts_held():
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(0.05)
            reached_end_of_block = True
    finally:
        signal.signal(signal.SIGINT, previous)
    assert reached_end_of_block


def test_an_ignored_interrupt_stays_ignored() -> None:
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        with interrupts_held():
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(0.05)
        time.sleep(0.05)
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
    finally:
        signal.signal(signal.SIGINT, previous)


def test_a_pool_needs_a_worker() -> None:
    with pytest.raises(ValueError, match="at least one worker, got 0"):
        WorkerPool(0)
