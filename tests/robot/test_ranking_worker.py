"""A robot's worker process without ROS: a large map's answer equal to ranking in the node's own
process, answers in the frame of the map they were ranked on, requests that queued behind a ranking
answered together at the newest pose, a default socket timeout (rospy sets 60 s) under which the
pipe must stay blocking, a hand-over that never waits for a busy worker, a pose off the map the
worker holds, and a worker that dies (again while it restarts) and comes back with the last map."""

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
from frontier_rl.robot.answers import MapCells, MapFrame, MapInfo
from frontier_rl.robot.map_message import grid_from_message
from frontier_rl.robot.ranking import rank_frontiers
from frontier_rl.robot.ranking_worker import RankJob, RankResult, RobotWorker, _HeldMap, _rank

AT_ORIGIN = MapFrame("map", 0.0, 0.0, 0.0)


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
    return MapCells(MapInfo(AT_ORIGIN, 60, 60, 0.05, 10**9), cells.reshape(-1))


def _hall(size: int, frame: MapFrame = AT_ORIGIN, stamp_ns: int = 10**9) -> MapCells:
    """A free hall of ``size`` × ``size`` cells in unknown space, with a wall and a few probabilities."""
    cells = np.full((size, size), -1, np.int8)
    cells[20 : size - 20, 20 : size // 2] = 0
    cells[size // 3, 20 : size // 2 - 30] = 100
    cells[size // 4, 40:60] = 70  # occupied by the thresholds, like SLAM's probabilities
    return MapCells(MapInfo(frame, size, size, 0.05, stamp_ns), cells.reshape(-1))


def test_a_large_map_is_ranked_as_in_the_nodes_own_process(worker: tuple[RobotWorker, _Results]) -> None:
    handle, results = worker
    hall = _hall(1500)
    handle.send_map(hall)
    handle.submit(RankJob(1, 5.0, 5.0))
    answer = results.wait(1)
    assert not answer.error and answer.centres == _ranked_here(hall, 5.0, 5.0) and answer.info == hall.info
    assert len(answer.centres) >= 2 and answer.weight == 0.75


def _ranked_here(cells: MapCells, x: float, y: float) -> tuple[tuple[float, float], ...]:
    """The map-frame centres that ranking ``cells`` at the map-frame point (x, y) gives in this process."""
    info = cells.info
    grid = grid_from_message(info.width, info.height, info.resolution, cells.data)
    gx, gy = info.frame.to_grid(x, y)
    ranked, _ = rank_frontiers(grid, Pose(gx, gy, 0.0), make_policy("fixed:0.75"), 10, 4, rng=np.random.default_rng(0))
    return tuple(info.frame.to_map(f.x, f.y) for f in ranked)


def test_answers_are_in_the_frame_of_the_map_they_were_ranked_on(worker: tuple[RobotWorker, _Results]) -> None:
    """A SLAM map grows and moves its origin: each job is placed on, and answered in the frame of,
    the map the worker holds when it ranks, and says which map that was (the node stamps with it)."""
    handle, results = worker
    first, moved = _hall(200), _hall(200, MapFrame("map", -3.0, 2.0, 0.4), stamp_ns=2 * 10**9)
    handle.send_map(first)
    handle.submit(RankJob(1, 2.0, 2.0))
    one = results.wait(1)
    handle.send_map(moved)
    handle.submit(RankJob(2, -2.0, 4.5))
    two = results.wait(2)
    assert one.info == first.info and one.centres == _ranked_here(first, 2.0, 2.0)
    assert two.info == moved.info and two.centres == _ranked_here(moved, -2.0, 4.5)
    assert len(two.centres) >= 2 and two.centres != one.centres


def test_a_map_whose_walls_changed_is_ranked_as_a_new_one(worker: tuple[RobotWorker, _Results]) -> None:
    """The worker inflates a new map only where its walls changed, and not at all for a job on the
    same map: every answer is the one a ranking from scratch gives."""
    handle, results = worker
    before = _hall(300)
    cells = before.data.reshape(300, 300).copy()
    cells[70:74, 10:160] = 100  # a wall across the hall with a gap the robot cannot pass, and one gone
    cells[70:74, 80:83] = 0
    cells[100, 20:120] = 0
    after = MapCells(MapInfo(AT_ORIGIN, 300, 300, 0.05, 2 * 10**9), cells.reshape(-1))
    poses = [(before, 3.0, 2.0), (before, 4.0, 2.5), (after, 3.0, 2.0), (after, 4.0, 2.5)]
    for job, (cells_sent, x, y) in enumerate(poses):
        if job % 2 == 0:
            handle.send_map(cells_sent)
        handle.submit(RankJob(job, x, y))
        answer = results.wait(job)
        assert not answer.error and answer.centres == _ranked_here(cells_sent, x, y), job
    assert results.results[0].centres != results.results[2].centres


def test_a_worker_keeps_its_inflation_for_maps_on_the_same_cells() -> None:
    """A map in the same frame keeps the last one's inflation memory, which the ranking uses; a map
    whose origin moved starts a new one (its cells lie elsewhere in the grid)."""
    first = _HeldMap.of(_hall(200))
    assert _rank([RankJob(1, 2.0, 2.0)], first, make_policy("fixed:0.75"), 10, 4, np.random.default_rng(0))[0].centres
    assert first.memory._state is not None  # the ranking inflated through it
    again = _HeldMap.of(_hall(200, stamp_ns=2 * 10**9), first)
    moved = _HeldMap.of(_hall(200, MapFrame("map", -3.0, 2.0, 0.0), stamp_ns=3 * 10**9), again)
    assert again.memory is first.memory and moved.memory is not first.memory


def test_jobs_queued_behind_a_ranking_are_answered_together_at_the_newest_pose(
    worker: tuple[RobotWorker, _Results],
) -> None:
    handle, results = worker
    hall = _hall(1500)  # a ranking long enough (tenths of a second) for the later jobs to queue
    handle.send_map(hall)
    poses = [(5.0 + job, 5.0 + job) for job in range(6)]
    for job, (x, y) in enumerate(poses, start=1):
        handle.submit(RankJob(job, x, y))
    answers = [results.wait(job) for job in range(1, 7)]
    assert all(not a.error and a.centres for a in answers)
    assert answers[-1].centres == _ranked_here(hall, *poses[-1])  # the newest pose is the one ranked
    assert any(a.shared > 1 for a in answers), [a.shared for a in answers]
    first = 0
    while first < len(answers):  # each ranking answers a run of consecutive jobs, all alike
        run = answers[first : first + answers[first].shared]
        assert all(a.shared == len(run) and a.centres == run[0].centres for a in run), [a.shared for a in answers]
        first += len(run)
    assert first == len(answers) and handle.pending == 0


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


@pytest.mark.serial
def test_maps_and_jobs_are_handed_over_at_once_while_the_worker_is_busy(worker: tuple[RobotWorker, _Results]) -> None:
    """The node's callbacks hand over and return: with the worker stopped (a long ranking), a map
    larger than the pipe's buffer and a job take no time, and the job is answered on that map once
    the worker goes on. Writing into the pipe from the callback held it, and every robot whose
    requests rospy delivers on the same thread, until the worker read again."""
    handle, results = worker
    pid = handle._process.pid
    assert pid is not None
    hall = _hall(1500)  # 2.25 MB: more than a socket pair's buffer
    os.kill(pid, signal.SIGSTOP)
    resume = threading.Timer(3.0, os.kill, (pid, signal.SIGCONT))  # a hand-over that waits, waits this long
    resume.start()
    try:
        start = time.monotonic()
        handle.send_map(hall)
        handle.submit(RankJob(1, 5.0, 5.0))
        handed_over = time.monotonic() - start
    finally:
        resume.join()
    assert handed_over < 1.0, handed_over
    answer = results.wait(1)
    assert not answer.error and answer.info == hall.info and answer.centres == _ranked_here(hall, 5.0, 5.0)


def test_a_pose_off_the_map_the_worker_holds_is_answered_with_a_reason() -> None:
    """The node checks a pose on its newest map; the worker may rank another (a map moved since)."""
    held = _HeldMap.of(_hall(200))  # 10 m × 10 m from the origin
    answer = _rank([RankJob(1, 25.0, 2.0)], held, make_policy("fixed:0.75"), 10, 4, np.random.default_rng(0))[0]
    assert answer.centres == () and "off the map" in answer.error and answer.info == held.info


def test_a_worker_that_dies_again_while_it_restarts_comes_back(worker: tuple[RobotWorker, _Results]) -> None:
    """The last map goes to a new process by the writer thread: a process killed before it read
    that map broke the restart's own write, and the robot's worker stayed dead for good."""
    handle, results = worker
    handle.send_map(_hall(1500))  # larger than the pipe's buffer: a restart's write of it waits for the reader
    handle.submit(RankJob(1, 5.0, 5.0))
    first = results.wait(1)
    for _ in range(2):  # the worker, then its replacement before it has loaded its policy
        pid = handle._process.pid
        assert pid is not None
        os.kill(pid, signal.SIGKILL)
        deadline = time.monotonic() + 60
        while handle._process.pid in (pid, None) and time.monotonic() < deadline:  # None: being started
            time.sleep(0.01)
        assert handle._process.pid not in (pid, None), "no restart"
    assert handle.ready.wait(120)
    handle.submit(RankJob(2, 5.0, 5.0))
    assert results.wait(2).centres == first.centres


@pytest.mark.serial
def test_a_worker_outlives_a_sigint_to_its_process_group(worker: tuple[RobotWorker, _Results]) -> None:
    """Ctrl-C in a terminal reaches the node and its workers; the node stops them itself."""
    handle, results = worker
    pid = handle._process.pid
    assert pid is not None
    os.kill(pid, signal.SIGINT)
    handle.send_map(_room())
    handle.submit(RankJob(1, 1.0, 1.5))
    assert results.wait(1).centres and handle._process.pid == pid and handle._process.is_alive()


def test_a_random_policy_draws_afresh_at_every_request_of_a_robot() -> None:
    """The worker ranked with a generator seeded alike at every request: ``random`` gave one order."""
    cells = np.full((80, 80), -1, np.int8)
    cells[10:70, 10:70] = 0
    for k in range(10, 70, 10):  # walls cut the room's edge into many frontiers
        cells[10, k] = cells[69, k] = cells[k, 10] = cells[k, 69] = 100
    held = _HeldMap.of(MapCells(MapInfo(AT_ORIGIN, 80, 80, 0.05, 10**9), cells.reshape(-1)), None)
    policy, rng = make_policy("random"), np.random.default_rng(0)
    orders = [_rank([RankJob(job, 2.0, 2.0)], held, policy, 10, 4, rng)[0].centres for job in range(5)]
    assert len(orders[0]) == 10 and len(set(orders)) == 5
