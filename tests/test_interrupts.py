"""A Ctrl-C while a compiled kernel runs ends the command with one line: numba turned an interrupt
raised in a kernel's callback into a SystemError, printed as a traceback with exit status 1 (every
time for a team exploring by ``tour``), and counted as a failed run by the benchmarks."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from types import SimpleNamespace

import pytest

from frontier_rl import launch
from frontier_rl.errors import caused_by_interrupt
from tests.processes import sigint_as_in_a_terminal


def test_an_error_raised_while_handling_a_ctrl_c_counts_as_one() -> None:
    try:
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt:
            raise SystemError("CPUDispatcher(<function _group_costs>) returned a result with an exception set")  # noqa: B904
    except SystemError as error:
        assert caused_by_interrupt(error)
    assert not caused_by_interrupt(SystemError("a fault of its own"))
    assert caused_by_interrupt(KeyboardInterrupt())


@pytest.mark.parametrize(
    "fragile",
    [
        f"{os.sep}numba{os.sep}core{os.sep}serialize.py",
        f"{os.sep}site-packages{os.sep}torch{os.sep}serialization.py",  # a checkpoint's save: its writer tore
    ],
)
def test_a_ctrl_c_inside_numbas_own_code_waits_until_it_is_left(monkeypatch: pytest.MonkeyPatch, fragile: str) -> None:
    timers: list[float] = []
    monkeypatch.setattr(signal, "setitimer", lambda which, seconds: timers.append(seconds))
    in_numba = SimpleNamespace(f_code=SimpleNamespace(co_filename=fragile))
    ours = SimpleNamespace(f_code=SimpleNamespace(co_filename="frontier_rl/core/sim/leg.py"), f_back=None)
    in_numba.f_back = ours
    interrupts = launch.CommandInterrupts()
    interrupts.on_sigint(signal.SIGINT, in_numba)  # type: ignore[arg-type]
    assert interrupts.deferred and timers == [launch.REDELIVER_S] and interrupts.raised_at is None
    with pytest.raises(KeyboardInterrupt):
        launch.CommandInterrupts().on_sigint(signal.SIGINT, ours)  # type: ignore[arg-type]


@pytest.mark.slow
def test_ctrl_c_while_a_team_explores_by_tour_is_one_line() -> None:
    command = [sys.executable, "-c", "import sys; from frontier_rl.launch import main; sys.exit(main())", "explore",
               "--world", "building", "--robots", "3", "--strategy", "coordinated", "--policy", "tour"]  # fmt: skip
    for wait_s in (4.0, 6.0):
        process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                                   start_new_session=True, preexec_fn=sigint_as_in_a_terminal)  # fmt: skip
        time.sleep(wait_s)
        os.killpg(process.pid, signal.SIGINT)
        _, stderr = process.communicate(timeout=60)
        assert process.returncode == 130 and stderr == "interrupted\n", stderr
