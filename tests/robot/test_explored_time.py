"""The time a robot has explored: a clock that jumps back or is paused counts no time then."""

from __future__ import annotations

import pytest

from frontier_rl.robot.explored_time import ExploredTime


def test_the_time_explored_follows_the_clock_but_not_its_jumps_back_nor_pauses() -> None:
    explored = ExploredTime()
    assert explored.advanced(100.0) == 0.0  # the first reading starts it
    assert explored.advanced(103.5) == pytest.approx(3.5)
    assert explored.advanced(1.0) == pytest.approx(3.5)  # a restarted simulator's clock
    assert explored.advanced(2.0) == pytest.approx(4.5)
    explored.held(10.0)  # paused from 2 s to 10 s
    explored.held(30.0)
    assert explored.advanced(31.0) == pytest.approx(5.5) and explored.elapsed_s == pytest.approx(5.5)
