"""One process per robot that holds its last good map and ranks its frontiers, so that a large map
or a slow model for one robot never delays another (the engine's compiled kernels hold Python's
global lock while they run, so threads would not do). Free of ROS: the node hands it map cells and
rank jobs, a writer thread puts them into its pipe, and a reader thread gets the results back. The
node's callbacks never write to the pipe themselves: a worker busy ranking reads nothing, and a
large map written then would hold up the callback, and with it every robot's requests that rospy
delivers on the same thread."""

from __future__ import annotations

import contextlib
import multiprocessing
import sys
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from multiprocessing.connection import Connection
from typing import Any

import numpy as np

from frontier_rl.core.navigation.inflation import InflationMemory
from frontier_rl.core.world.grid import FREE_I8, OCCUPIED_I8, UNKNOWN_I8, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.errors import FrontierRLError
from frontier_rl.policies import make_policy
from frontier_rl.robot.answers import MapCells, MapInfo
from frontier_rl.robot.map_message import grid_from_message
from frontier_rl.robot.ranking import rank_frontiers
from frontier_rl.worker_signals import ignore_interrupts, spawning_workers


@dataclass(frozen=True)
class RankJob:
    """Rank the frontiers of the current map for a robot at (x, y), map frame (m)."""

    job: int
    x: float
    y: float


@dataclass(frozen=True)
class RankResult:
    """A job's answer: frontier centres (map frame, m) best first, the weight used and the map they
    were computed on, or the error that stopped it.

    Attributes:
        shared: how many jobs this one ranking answered (jobs queued behind a ranking are answered
            together, at the newest job's pose; 1 when the worker kept up).
    """

    job: int
    centres: tuple[tuple[float, float], ...] = ()
    weight: float | None = None
    error: str = ""
    info: MapInfo | None = None
    shared: int = 1


@dataclass(frozen=True)
class _HeldMap:
    """The map a worker ranks on, with the costmap inflation of its robot's maps in its frame."""

    grid: OccupancyGrid
    info: MapInfo
    memory: InflationMemory

    @classmethod
    def of(cls, cells: MapCells, last: _HeldMap | None = None) -> _HeldMap:
        """The map ``cells`` bring, keeping ``last``'s memory when it lies in the same frame (a map
        whose origin moved puts its cells elsewhere in the grid: a new memory, inflated whole), so
        that requests on it inflate nothing and a new map is inflated where its walls changed."""
        info = cells.info
        grid = grid_from_message(info.width, info.height, info.resolution, cells.data)
        if last is not None and last.info.frame == info.frame and last.info.resolution == info.resolution:
            return cls(grid, info, last.memory)
        return cls(grid, info, InflationMemory())


def _serve(conn: Connection, policy_spec: str, top_k: int, min_cells: int, seed: int) -> None:
    """The worker process: a map replaces the current one; the jobs that queued while it ranked are
    answered by one ranking on the newest map at the newest job's pose (a robot asks about where it
    is now, and a queue must not grow behind a slow model). It ends when the node's end of the
    pipe closes (the node exited, however), never on SIGINT: Ctrl-C in a terminal reaches the whole
    process group, and the node stops its workers itself (a worker that died of it printed a
    traceback and was restarted while the node shut down)."""
    ignore_interrupts()  # spawned with SIGINT blocked: a Ctrl-C while it started is dropped
    policy = make_policy(policy_spec)
    if "torch" in sys.modules:  # a learned policy: one thread, as every robot has a worker of its own
        sys.modules["torch"].set_num_threads(1)
    _warm_up(policy, top_k, min_cells)
    rng = np.random.default_rng(seed)  # after the warm-up: its draws are not the robot's
    held: _HeldMap | None = None
    try:
        conn.send(READY)  # the node may have gone meanwhile
        while True:
            jobs: list[RankJob] = []
            message = conn.recv()
            while True:
                if isinstance(message, MapCells):
                    with contextlib.suppress(FrontierRLError):  # the node checks maps first; keep the last good one
                        held = _HeldMap.of(message, held)
                else:
                    jobs.append(message)
                if not conn.poll(0):
                    break
                message = conn.recv()
            for result in _rank(jobs, held, policy, top_k, min_cells, rng):
                conn.send(result)
    except (EOFError, OSError):
        return


def _rank(
    jobs: list[RankJob], held: _HeldMap | None, policy: Any, top_k: int, min_cells: int, rng: np.random.Generator
) -> list[RankResult]:
    """One result per job, all from one ranking at the last job's pose (a random policy drawing from ``rng``)."""
    if not jobs:
        return []
    if held is None:  # the node sends a map before any job; kept as a guard
        return [RankResult(job.job, error="no map in the worker") for job in jobs]
    frame, shared = held.info.frame, len(jobs)
    if not held.info.contains(jobs[-1].x, jobs[-1].y):  # checked on the node's map, which may be older
        error = "the robot's pose is off the map it was ranked on"
        return [RankResult(job.job, error=error, info=held.info, shared=shared) for job in jobs]
    try:
        gx, gy = frame.to_grid(jobs[-1].x, jobs[-1].y)
        pose = Pose(gx, gy, 0.0)
        ranked, weight = rank_frontiers(held.grid, pose, policy, top_k, min_cells, rng=rng, memory=held.memory)
        centres = tuple(frame.to_map(f.x, f.y) for f in ranked)
    except (Exception, SystemExit) as exc:  # a model, map or policy problem comes back as an answer, not the end
        error = f"ranking failed: {type(exc).__name__}: {exc}"
        return [RankResult(job.job, error=error, info=held.info, shared=shared) for job in jobs]
    return [RankResult(job.job, centres, weight, info=held.info, shared=shared) for job in jobs]


_RESTART_DELAY_S = 0.5
"""Pause before a dead worker is started again (s)."""

READY = "ready"
"""What a worker sends once its policy is loaded and its kernels compiled."""


def _warm_up(policy: Any, top_k: int, min_cells: int) -> None:
    """Rank a small room, then the same room with a wall more, so that the first real requests do
    not pay for loading the kernels (the second map's inflation is worked out where it changed)."""
    memory, rng = InflationMemory(), np.random.default_rng(0)
    cells = np.full((120, 120), UNKNOWN_I8)  # large enough that a wall is inflated on a window of it
    cells[5:115, 5:60] = FREE_I8
    for wall in (False, True):
        cells[60, 5:10] = OCCUPIED_I8 if wall else FREE_I8
        ranked = grid_from_message(120, 120, 0.05, cells.reshape(-1))
        rank_frontiers(ranked, Pose(0.6, 1.0, 0.0), policy, top_k, min_cells, rng=rng, memory=memory)


class _Outbox:
    """What the node has for a worker process and has not yet written into its pipe: the newest map
    (a newer one replaces one still waiting, which no job would be ranked on) and the jobs in order."""

    def __init__(self) -> None:
        self._changed = threading.Condition()
        self._map: MapCells | None = None
        self._jobs: list[RankJob] = []
        self._closed = False

    def put(self, message: MapCells | RankJob) -> None:
        """Queue ``message`` for the pipe; returns at once."""
        with self._changed:
            if isinstance(message, MapCells):
                self._map = message
            else:
                self._jobs.append(message)
            self._changed.notify()

    def close(self) -> None:
        """Let :meth:`take` return None (the process behind the pipe is gone or being stopped)."""
        with self._changed:
            self._closed = True
            self._changed.notify()

    def take(self) -> list[MapCells | RankJob] | None:
        """Everything queued, the map first (the worker ranks queued jobs on its newest map
        anyway); waits while nothing is; None once closed."""
        with self._changed:
            while not self._closed and self._map is None and not self._jobs:
                self._changed.wait()
            if self._closed:
                return None
            batch: list[MapCells | RankJob] = [] if self._map is None else [self._map]
            batch += self._jobs
            self._map, self._jobs = None, []
            return batch


class RobotWorker:
    """The node's handle on one robot's worker process.

    ``on_result`` is called on a reader thread with every :class:`RankResult`; a random policy draws
    from one generator seeded with ``seed`` (a restarted worker's seeded again); if the process dies
    (killed, out of memory), the jobs it held are answered with an error and a new process starts
    with the last map.
    """

    def __init__(
        self, policy_spec: str, top_k: int, min_cells: int, on_result: Callable[[RankResult], None], seed: int = 0
    ) -> None:
        self._args = (policy_spec, top_k, min_cells, seed)
        self._on_result = on_result
        self._lock = threading.RLock()  # close() may run again, from a shutdown hook, on a thread inside it
        self._pending: set[int] = set()
        self._last_map: MapCells | None = None
        self._closing = False
        self.ready = threading.Event()
        """Set once the worker process has loaded its policy (again after a restart)."""
        self._start()

    def _start(self) -> None:
        self.ready.clear()
        context = multiprocessing.get_context("spawn")  # no fork of a process that runs rospy's threads
        self._conn, child = context.Pipe()
        self._process = context.Process(target=_serve, args=(child, *self._args), daemon=True)
        with spawning_workers():
            self._process.start()
        child.close()
        self._outbox = _Outbox()
        if self._last_map is not None:
            self._outbox.put(self._last_map)
        writer = threading.Thread(target=self._write, args=(self._conn, self._outbox), daemon=True)
        writer.start()
        threading.Thread(target=self._read, args=(self._conn, self._outbox, writer), daemon=True).start()

    @property
    def pending(self) -> int:
        """Jobs sent and not yet answered."""
        return len(self._pending)

    def send_map(self, cells: MapCells) -> None:
        """Make ``cells`` the map every later job is ranked on; returns at once."""
        with self._lock:
            self._last_map = cells
            self._outbox.put(cells)  # a dead worker: its restart sends the last map

    def submit(self, job: RankJob) -> None:
        """Queue ``job`` and return at once; its result comes to ``on_result`` (an error result if
        the worker dies first)."""
        with self._lock:
            self._pending.add(job.job)
            self._outbox.put(job)  # a dead worker: the restart answers the pending jobs

    def close(self) -> None:
        """Stop the process (its reader and writer threads then end); none is started again."""
        with self._lock:  # a restart under way finishes first, and then none follows
            self._closing = True
            process, outbox = self._process, self._outbox
        outbox.close()
        process.terminate()
        process.join(timeout=5)
        if process.is_alive():
            process.kill()

    @staticmethod
    def _write(conn: Connection, outbox: _Outbox) -> None:
        """Put what the node queued into the pipe, waiting while the worker is busy, until the
        outbox closes or the pipe breaks (the process died: the reader restarts it)."""
        while (batch := outbox.take()) is not None:
            try:
                for message in batch:
                    conn.send(message)
            except OSError:
                return

    def _read(self, conn: Connection, outbox: _Outbox, writer: threading.Thread) -> None:
        while True:
            try:
                result: Any = conn.recv()
            except (EOFError, OSError):
                break
            if isinstance(result, str) and result == READY:
                self.ready.set()
                continue
            self._pending.discard(result.job)
            self._on_result(result)
        outbox.close()
        writer.join(timeout=5)  # a write to the dead process fails at once; then the pipe may close
        conn.close()
        if self._closing:
            return
        time.sleep(_RESTART_DELAY_S)  # a worker that cannot start must not make a hot loop
        self._process.join(timeout=5)
        code = self._process.exitcode
        with self._lock:
            if self._closing:  # closed while it slept
                return
            lost, self._pending = sorted(self._pending), set()
            self._start()
        for job in lost:
            self._on_result(RankResult(job, error=f"the robot's worker process ended (exit code {code}); restarted"))
