"""A robot's worker process without ROS: a large map's answer equal to ranking in the node's own
process, a default socket timeout (rospy sets 60 s) under which the pipe must stay blocking, and a
worker that dies and comes back with the last map."""

from __future__ import annotations

import os
import signal
import socket
import threading
import time
from collections.abc import Iterator

import numpy as np
import pytest

from frontier_rl.core.world.robot import Pose
from frontier_rl.policies import make_policy
from frontier_rl.policies.frontier_request import grid_from_message, rank_frontiers
from frontier_rl.ros.robot_worker import MapCells, RankJob, RankResult, RobotWorker


class _Results:
    """Collects a worker's results and waits for the one of a job."""

    def __init__(self) -> None:
        self.results: dict[int, RankResult] = {}
        self._arrived = threading.Condition()

    def __call__(self, result: RankResult) -> None:
        with self._arrived:
            self.results[result.job] = result
            self._arrived.notify_all()

    def wait(self, job: int, timeout: float = 60.0) -> RankResult:
        with self._arrived:
            assert self._arrived.wait_for(lambda: job in self.results, timeout), f"no result for job {job}"
            return self.results[job]


@pytest.fixture
def worker() -> Iterator[tuple[RobotWorker, _Results]]:
    results = _Results()
    handle = RobotWorker("fixed:0.75", 10, 4, results)
    try:
        assert handle.ready.wait(120)
        yield handle, results
    finally:
        handle.close()


def _room() -> MapCells:
    cells = np.full((60, 60), -1, np.int8)
    cells[10:50, 10:30] = 0
    return MapCells(60, 60, 0.05, cells.reshape(-1))


def _hall(size: int) -> MapCells:
    """A free hall of ``size`` × ``size`` cells in unknown space, with a wall and a few probabilities."""
    cells = np.full((size, size), -1, np.int8)
    cells[20 : size - 20, 20 : size // 2] = 0
    cells[size // 3, 20 : size // 2 - 30] = 100
    cells[size // 4, 40:60] = 70  # occupied by the thresholds, like SLAM's probabilities
    return MapCells(size, size, 0.05, cells.reshape(-1))


def test_a_large_map_is_ranked_as_in_the_nodes_own_process(worker: tuple[RobotWorker, _Results]) -> None:
    handle, results = worker
    hall = _hall(1500)
    handle.send_map(hall)
    handle.submit(RankJob(1, 5.0, 5.0))
    answer = results.wait(1)
    grid = grid_from_message(hall.width, hall.height, hall.resolution, hall.data)
    ranked, weight = rank_frontiers(grid, Pose(5.0, 5.0, 0.0), make_policy("fixed:0.75"), 10, 4)
    assert not answer.error and answer.centres == tuple((f.x, f.y) for f in ranked) and answer.weight == weight
    assert len(answer.centres) >= 2


def test_a_default_socket_timeout_leaves_the_pipe_blocking() -> None:
    """rospy sets ``socket.setdefaulttimeout(60)``. A socket made on the pipe's file under it (as
    ``multiprocessing.reduction.send_handle`` makes one, tried for passing maps as file descriptors)
    turns the pipe non-blocking, and the reader thread's next read fails with EAGAIN: the worker was
    restarted on every map."""
    previous = socket.getdefaulttimeout()
    socket.setdefaulttimeout(60.0)
    try:
        results = _Results()
        handle = RobotWorker("fixed:0.75", 10, 4, results)
        try:
            assert handle.ready.wait(120)
            for job in range(1, 6):
                handle.send_map(_room())
                handle.submit(RankJob(job, 1.0, 1.5))
                answer = results.wait(job)
                assert not answer.error and answer.centres, answer
            assert handle._process.is_alive()
        finally:
            handle.close()
    finally:
        socket.setdefaulttimeout(previous)


def test_a_worker_ranks_and_comes_back_after_it_is_killed(worker: tuple[RobotWorker, _Results]) -> None:
    handle, results = worker
    handle.send_map(_room())
    handle.submit(RankJob(1, 1.0, 1.5))
    first = results.wait(1)
    assert first.centres and not first.error
    pid = handle._process.pid
    assert pid is not None
    os.kill(pid, signal.SIGKILL)
    deadline = time.monotonic() + 120
    while handle._process.pid == pid and time.monotonic() < deadline:
        time.sleep(0.05)
    assert handle.ready.wait(120)
    handle.submit(RankJob(2, 1.0, 1.5))  # the new process has the last map
    assert results.wait(2).centres == first.centres
