"""The thesis's ranking service without ROS: ``/frontier_request`` → ``/frontier_list``, as the
ROS 1 node and the ROS 2 node both serve it.

A request names a robot (and optionally a request id); it is answered with that robot's top
frontier centres in its map frame, stamped with the map they were computed on, and a status line.
Every request is answered: an empty list, with the reason, when it cannot be ranked (unknown robot,
no map, a stale map, no pose, a pose off the map, too many requests queued, a failed ranking). Each
robot's map and ranking live in a worker process of its own
(:class:`~frontier_rl.robot.ranking_worker.RobotWorker`); a malformed map is rejected and the
robot's last good map kept (``keep_last_map``).
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass

from frontier_rl.errors import FrontierRLError, MapError, short_text
from frontier_rl.policies import make_policy
from frontier_rl.policies.baselines import FixedWeight
from frontier_rl.robot.answers import (
    MapCells,
    MapInfo,
    Note,
    Problem,
    Status,
    check_request,
    parse_request,
    stale_reason,
)
from frontier_rl.robot.node_settings import StaleMapAnswer, check_node_policy
from frontier_rl.robot.ranking_worker import RankJob, RankResult, RobotWorker
from frontier_rl.robot.throttled_log import ThrottledLog

WORKER_START_S = 120.0
"""How long the service waits for its workers to load their policy and kernels (s)."""

RobotPose = tuple[float, float, float]
"""A robot's pose in its map frame: x, y (m), yaw (rad)."""


@dataclass(frozen=True, kw_only=True)
class ServiceSettings:
    """What the service answers with.

    Attributes:
        robots: the robots' namespaces ("" for one robot without a namespace).
        policy: the policy spec that ranks (any but the oracle and the point models).
        top_k: frontiers per answer.
        min_cells: frontier clusters of this many cells or fewer are left out.
        max_map_age: a map older than this is stale (s; 0: any age).
        stale: what a stale map is answered with (ranked and said so, or empty).
        keep_last_map: keep a robot's last good map when a malformed one arrives.
        max_pending: requests queued per robot; more are answered empty at once.
    """

    robots: tuple[str, ...]
    policy: str
    top_k: int = 10
    min_cells: int = 4
    max_map_age: float = 30.0
    stale: StaleMapAnswer = StaleMapAnswer.STALE
    keep_last_map: bool = True
    max_pending: int = 8


@dataclass(frozen=True)
class Answer:
    """One answer: the robot and request, the map it was ranked on, the frontier centres (map
    frame, m) best first, the weight used (None for a frontier-choice model), and its status line."""

    robot: str
    request: str
    info: MapInfo | None
    centres: tuple[tuple[float, float], ...]
    weight: float | None
    status: Status


@dataclass(frozen=True)
class _Job:
    """A request at a worker: robot, request id, the sequence of the map checked, what to say of it so far,
    and when it arrived (monotonic s)."""

    robot: str
    request: str
    checked: int
    note: Note
    arrived: float


class RankingService:
    """The service's state; the node converts messages and publishes what :attr:`publish` gets.

    Args:
        settings: what it answers with (its policy is made here: a bad one raises, naming it).
        publish: called with every answer, in order, under the service's lock.
        warn: logs a warning (throttled per robot and kind here).
        clock: the time now (s) on the maps' clock (ROS time).

    The three may be given later, with :meth:`connect` (a ROS 2 node is made after the workers
    start, so that rclpy's signal handlers are installed last); until then answers are dropped.
    """

    def __init__(
        self,
        settings: ServiceSettings,
        publish: Callable[[Answer], None] = lambda answer: None,
        warn: Callable[[str], None] = lambda text: None,
        clock: Callable[[], float] = time.time,
    ) -> None:
        policy = make_policy(settings.policy)  # a bad policy, weight or model file fails here, with its message
        check_node_policy(policy, settings.policy)
        self.settings = settings
        self.policy_name = policy.name
        # a user policy may have a weight of its own that changes: only a fixed weight is announced
        self.fixed_weight = policy.weight if isinstance(policy, FixedWeight) else None
        self._publish, self._warn_line, self._clock = publish, warn, clock
        self.maps: dict[str, MapInfo | None] = dict.fromkeys(settings.robots)
        self.poses: dict[str, RobotPose] = {}
        self._jobs: dict[int, _Job] = {}
        self._job_count = self._request_count = 0
        self.answered = 0
        self._lock = threading.Lock()  # the job table and the answers' order
        self._log = ThrottledLog()
        self.workers: dict[str, RobotWorker] = {}

    def connect(
        self, publish: Callable[[Answer], None], warn: Callable[[str], None], clock: Callable[[], float]
    ) -> None:
        """Publish, log and tell the time with these from now on."""
        self._publish, self._warn_line, self._clock = publish, warn, clock

    def start(self, stopped: Callable[[], bool]) -> bool:
        """Start a worker per robot and wait for each to load its policy; False if ``stopped()``
        turns true meanwhile (a Ctrl-C while it starts)."""
        s = self.settings
        self.workers = {  # a random policy's draws differ from robot to robot
            ns: RobotWorker(s.policy, s.top_k, s.min_cells, self._on_result, seed=index)
            for index, ns in enumerate(s.robots)
        }
        deadline = time.monotonic() + WORKER_START_S
        for ns, worker in self.workers.items():
            while not worker.ready.wait(0.1):
                if stopped():
                    return False
                if time.monotonic() > deadline:
                    raise FrontierRLError(f"the worker of robot {ns!r} did not start within {WORKER_START_S:g} s")
        return True

    def close(self) -> None:
        """Stop every worker (none is started again)."""
        for worker in self.workers.values():
            worker.close()

    def warn(self, ns: str, kind: Problem, text: str) -> None:
        """Log ``text`` unless a warning of this robot and kind was logged a moment ago (an unknown
        robot's under one name: a request may name any)."""
        robot = "" if kind is Problem.UNKNOWN_ROBOT else ns
        if self._log.due(robot, kind, time.monotonic()):
            self._warn_line(text)

    # ------------------------------------------------------------------ inputs
    def on_map(self, ns: str, read: Callable[[int], MapCells]) -> None:
        """A map message of robot ``ns``: ``read(sequence)`` gives its cells as the robot's
        ``sequence``-th good map, or raises :class:`MapError`."""
        previous = self.maps[ns]
        try:
            cells = read(0 if previous is None else previous.sequence + 1)
        except MapError as exc:
            kept = self.settings.keep_last_map and previous is not None
            then = "the last good map is kept" if kept else "no map until a good one arrives"
            self.warn(ns, Problem.MAP_REJECTED, f"map of {ns!r} rejected ({exc}); {then}")
            if not self.settings.keep_last_map:
                self.maps[ns] = None
            return
        self.maps[ns] = cells.info
        self.workers[ns].send_map(cells)

    def on_pose(self, ns: str, pose: RobotPose) -> None:
        """Robot ``ns`` is at ``pose`` (its map frame)."""
        self.poses[ns] = pose

    def on_request(self, text: str, pose_of: Callable[[str, MapInfo | None], RobotPose | None] | None = None) -> None:
        """A request (``"NAMESPACE [ID]"``): answered at once when it cannot be ranked, else by the
        robot's worker. ``pose_of`` finds a pose where no pose message came (TF)."""
        arrived = time.monotonic()
        with self._lock:
            self._request_count += 1
            ns, request = parse_request(text, self._request_count)
        s = self.settings
        try:
            info = self.maps.get(ns)
            pose = self.poses.get(ns)  # once: a new pose may arrive while the request is checked
            if pose is None and pose_of is not None:
                pose = pose_of(ns, info)
            verdict = check_request(ns, list(s.robots), info, pose, self._clock(), s.max_map_age, s.stale)
            if not verdict.rank or info is None or pose is None:
                self._answer(ns, request, info, (), None, verdict.note, arrived)
                return
            if self.workers[ns].pending >= s.max_pending:
                busy = f"robot {ns!r} has {s.max_pending} requests queued (~max_pending)"
                self._answer(ns, request, info, (), None, Note(busy, Problem.BUSY), arrived)
                return
            with self._lock:
                self._job_count += 1
                job = self._job_count
                self._jobs[job] = _Job(ns, request, info.sequence, verdict.note, arrived)
            self.workers[ns].submit(RankJob(job, pose[0], pose[1]))
        except Exception as exc:  # every request gets an answer, whatever failed in preparing it
            failed = Note(f"request failed: {type(exc).__name__}: {exc}", Problem.FAILED)
            self._answer(ns, request, self.maps.get(ns), (), None, failed, arrived)

    # ----------------------------------------------------------------- answers
    def _on_result(self, result: RankResult) -> None:
        with self._lock:
            job = self._jobs.pop(result.job)
        info = result.info or self.maps.get(job.robot)  # the map the worker ranked on: it may be newer
        note = job.note
        if info is not None and info.sequence != job.checked:  # judged on the map that was ranked
            stale = stale_reason(job.robot, info, self._clock(), self.settings.max_map_age)
            note = Note(stale, Problem.STALE_MAP if stale else None)
        if result.error:
            note = Note("; ".join(part for part in (note.text, result.error) if part), Problem.FAILED)
        self._answer(job.robot, job.request, info, result.centres, result.weight, note, job.arrived)

    def _answer(
        self,
        ns: str,
        request: str,
        info: MapInfo | None,
        centres: tuple[tuple[float, float], ...],
        weight: float | None,
        note: Note,
        arrived: float,
    ) -> None:
        reason = note.text
        if note.problem is not None:
            answered = " answered empty" if not centres else ""
            self.warn(ns, note.problem, f"request {short_text(request)} of {ns!r}{answered}: {reason}")
        used = weight if weight is not None else (self.fixed_weight if centres else None)
        status = Status(
            ns,
            request,
            len(centres),
            reason,
            self.policy_name,
            used,
            None if info is None else info.stamp_s,
            None if info is None else info.age_s(self._clock()),
            time.monotonic() - arrived,
        )
        with self._lock:
            self.answered += 1
            self._publish(Answer(ns, request, info, centres, used, status))
