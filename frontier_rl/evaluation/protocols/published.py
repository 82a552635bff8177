"""Published evaluation protocols, run as their papers' code runs them, with their metric printed
beside ours.

``ariadne``: the test driver of ARiADNE (Cao et al., ICRA 2023; github.com/marmotlab/ARiADNE,
``test_driver.py``, ``env.py``): every DungeonMaps test map once, the robot starting at the 128th
pixel of the start marker (row-major, as ``np.nonzero`` lists them), a sensor range of 80 px, and
a run that ends when at most 250 of the map's free pixels are unseen; its metric is the distance
travelled in pixels, printed as the mean and the (population) standard deviation over the maps.

What our simulator does differently, and how the protocol is met on it: our robot drives with the
navigator, the follower and the LiDAR of every other episode (it turns, keeps clear of walls and
sees along 360 beams), where ARiADNE's moves straight between graph nodes and senses a disc of
rays; the distance is the one our robot drove until the map update at which the 250-pixel rule was
first met (every scan is folded into the map, as ARiADNE updates its belief at every step;
Gmapping's time threshold is off). The free pixels counted are those the
robot could see from where it can go (the world's explorable space; on DungeonMaps nearly all).
A run whose robot ends (no frontier left) before the rule is met counts with its whole distance,
as ARiADNE counts a run that ends with no utility left.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Generic, Protocol, TypeVar

import numpy as np

from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import ExplorationPolicy, run_episode
from frontier_rl.core.world.robot import Pose
from frontier_rl.core.world.worlds import World, make_world
from frontier_rl.errors import ConfigError, MapError, caused_by_interrupt, short_path
from frontier_rl.evaluation.running.backends import check_workers, default_workers
from frontier_rl.evaluation.running.methods import episode_policy
from frontier_rl.evaluation.running.worker_pool import WorkerPool
from frontier_rl.io.dungeon import DUNGEON_RESOLUTION, load_dungeon_map, marker_pixels
from frontier_rl.policies import make_policy

R = TypeVar("R")


class ProtocolJob(Protocol):
    """One run a protocol asks for: a method on a map file (and whatever else its runner takes)."""

    @property
    def method(self) -> str:
        """The policy, as :func:`~frontier_rl.policies.make_policy` takes it."""

    @property
    def map_file(self) -> Path:
        """The map the run explores."""


J = TypeVar("J", bound=ProtocolJob)

ARIADNE_SENSOR_PX = 80
"""ARiADNE's sensor range (pixels)."""

ARIADNE_UNSEEN_PX = 250
"""A test run ends when at most this many free pixels are unseen."""

ARIADNE_START_INDEX = 127
"""The start is this entry of the marker's pixels in row-major order."""


@dataclass(frozen=True)
class ProtocolRun:
    """One (method, map) run of a protocol.

    Attributes:
        method: the policy.
        map_name: the map file's name.
        distance_px: ARiADNE's metric: pixels travelled until the 250-pixel rule was met.
        rule_met: whether the rule was met (else the run ended with no frontier left first).
        sim_time_s: our metric: the time until our episode ended (s).
        path_length_m: the distance our robot drove in the whole episode (m).
        explored: our episode ended with the map explored.
    """

    method: str
    map_name: str
    distance_px: float
    rule_met: bool
    sim_time_s: float
    path_length_m: float
    explored: bool


def ariadne_config(resolution: float = DUNGEON_RESOLUTION, config: SimConfig | None = None) -> SimConfig:
    """``config`` with ARiADNE's sensor: 80 px of range for the LiDAR and the mapper, and every
    scan folded into the map."""
    base = config or SimConfig()
    reach = ARIADNE_SENSOR_PX * resolution
    lidar = replace(base.lidar, max_range=reach)
    mapper = replace(base.mapper, usable_range=reach, temporal_update=1e-6)
    return replace(base, lidar=lidar, mapper=mapper)


def ariadne_world(path: Path, resolution: float = DUNGEON_RESOLUTION) -> World:
    """The DungeonMaps test map at ``path`` with ARiADNE's start pixel (the marker's centre where
    that pixel leaves our robot no room), explorable space seen with its 80 px range."""
    loaded = load_dungeon_map(path, resolution)
    pixels = marker_pixels(path)
    row, col = pixels[min(ARIADNE_START_INDEX, len(pixels) - 1)]
    grid, reach = loaded.grid, ARIADNE_SENSOR_PX * resolution
    x, y = grid.cell_to_world(grid.height - 1 - int(row), int(col))
    try:
        return make_world(grid, path.stem, start=Pose(x, y, 0.0), sensor_range=reach)
    except MapError:  # that pixel is too close to a wall for our robot: the marker's centre
        return make_world(grid, path.stem, start=loaded.start, sensor_range=reach)


def run_ariadne(method: str, path: Path, resolution: float = DUNGEON_RESOLUTION) -> ProtocolRun:
    """One ARiADNE test run of ``method`` on the map at ``path`` (seed 0: one noise stream)."""
    world = ariadne_world(path, resolution)
    result = run_episode(world, episode_policy(method, False), ariadne_config(resolution), seed=0)
    assert result.coverage_path_m is not None  # a single robot's episode
    unseen = world.explorable_count - np.rint(np.asarray(result.coverage_curve) * world.explorable_count)
    met = np.flatnonzero(unseen <= ARIADNE_UNSEEN_PX)
    driven = float(result.coverage_path_m[met[0]]) if met.size else result.path_length_m
    return ProtocolRun(
        method, path.name, driven / resolution, bool(met.size), result.sim_time_s, result.path_length_m, result.done
    )


@dataclass(frozen=True)
class AriadneJob:
    """One ARiADNE test run: ``method`` on the DungeonMaps map ``map_file`` at ``resolution`` (m/px)."""

    method: str
    map_file: Path
    resolution: float = DUNGEON_RESOLUTION


def run_ariadne_job(job: AriadneJob) -> ProtocolRun:
    """:func:`run_ariadne` of ``job`` (a worker's task)."""
    return run_ariadne(job.method, job.map_file, job.resolution)


@dataclass(frozen=True)
class _Catching(Generic[J, R]):
    """``run`` on a job, or the one-line reason it failed (one map must not cost the others'
    results)."""

    run: Callable[[J], R]

    def __call__(self, job: J) -> R | str:
        try:
            return self.run(job)
        except Exception as exc:  # reported with the map's name; the other runs go on
            if caused_by_interrupt(exc):  # a Ctrl-C numba turned into an error: not the run's failure
                raise KeyboardInterrupt from None
            return _failure_line(job, exc)


def _failure_line(job: ProtocolJob, exc: BaseException) -> str:
    """The line that reports ``job`` failing with ``exc``."""
    return f"{job.method} on {job.map_file.name}: {type(exc).__name__}: {exc}"


def run_jobs(
    run: Callable[[J], R],
    jobs: Sequence[J],
    workers: int | None = None,
    check_policy: Callable[[ExplorationPolicy], object] = lambda policy: None,
) -> tuple[list[R], list[str]]:
    """``run(job)`` for every job, in ``workers`` spawned processes (default: every core; ``run``
    must be a module-level function): the results in job order, and a line for each job that
    failed (the others are kept). Every job's method is built once first and passed to
    ``check_policy``, so that an unknown one, a bad model file or a policy the protocol cannot run
    fails before any work."""
    check_workers(workers)
    for method in dict.fromkeys(job.method for job in jobs):
        check_policy(make_policy(method))
    workers = max(1, min(workers or default_workers(), len(jobs)))
    catching = _Catching(run)
    if workers == 1:
        outcomes = [catching(job) for job in jobs]
    else:
        with WorkerPool(workers) as pool:
            outcomes = [  # an exception: the job's outcome never came back (its worker died)
                _failure_line(job, o) if isinstance(o, BaseException) else o
                for job, o in zip(jobs, pool.map(catching, jobs), strict=True)
            ]
    return [o for o in outcomes if not isinstance(o, str)], [o for o in outcomes if isinstance(o, str)]


def ariadne_maps(folder: Path, limit: int | None = None) -> list[Path]:
    """The test maps of ``folder`` in ARiADNE's order (file names sorted in reverse), at most ``limit``."""
    if not folder.is_dir():
        raise ConfigError(f"--maps {short_path(folder)} is not a folder")
    maps = sorted((p for p in folder.iterdir() if p.suffix.lower() == ".png"), key=lambda p: p.name, reverse=True)
    if not maps:
        raise ConfigError(f"--maps {short_path(folder)} holds no PNG maps")
    return maps[:limit] if limit else maps


def run_protocol(
    methods: Sequence[str], maps: Sequence[Path], workers: int | None = None, resolution: float = DUNGEON_RESOLUTION
) -> tuple[list[ProtocolRun], list[str]]:
    """Every method on every map, in ``workers`` processes (default: every core): the runs, and a
    line for each run that failed (the others are kept)."""
    return run_jobs(run_ariadne_job, [AriadneJob(m, p, resolution) for m in methods for p in maps], workers)


@dataclass(frozen=True)
class AriadneSummary:
    """A method's line of the ARiADNE protocol: its numbers and ours (NaN means over no run).

    Attributes:
        method: the method as given.
        tests: the maps it ran on.
        average_length_px, length_std_px: ARiADNE's ``#Average length`` and ``#Length std`` (px;
            NumPy's population std, as its driver prints).
        rule_met: the runs that ended by ARiADNE's rule.
        mean_time_s, mean_path_m: our mean exploration time (s) and path length (m).
        explored: the runs that ended with the map explored.
    """

    method: str
    tests: int
    average_length_px: float
    length_std_px: float
    rule_met: int
    mean_time_s: float
    mean_path_m: float
    explored: int


def summary_rows(runs: Sequence[ProtocolRun], methods: Sequence[str]) -> list[AriadneSummary]:
    """Per method: ARiADNE's numbers and ours (:class:`AriadneSummary`)."""
    rows = []
    for method in methods:
        mine = [r for r in runs if r.method == method]
        lengths = np.array([r.distance_px for r in mine])
        rows.append(
            AriadneSummary(
                method=method,
                tests=len(mine),
                average_length_px=float(lengths.mean()) if mine else math.nan,
                length_std_px=float(lengths.std()) if mine else math.nan,
                rule_met=sum(r.rule_met for r in mine),
                mean_time_s=float(np.mean([r.sim_time_s for r in mine])) if mine else math.nan,
                mean_path_m=float(np.mean([r.path_length_m for r in mine])) if mine else math.nan,
                explored=sum(r.explored for r in mine),
            )
        )
    return rows
