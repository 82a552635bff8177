"""Explore-Bench's metrics (Xu et al., ICRA 2022; github.com/efc-robot/Explore-Bench, the scripts
``exploration_metric_for_single_robot.py`` and ``exploration_metric_for_two_robots.py``), computed
as those scripts compute them, on a ROS map given as the blueprint.

- The *exploration rate* is the area the robots' (merged) map knows, free or occupied, over the
  blueprint's known area: the pixels of its image that are not unknown grey, 205, counted as the
  script's ``get_gt`` counts them, whatever the YAML's thresholds make of that grey.
- ``T_90`` is when the rate first reaches 0.9; ``T_total``, when it first reaches 0.99 (the end
  of an Explore-Bench run); the path length is the distance driven until then (all robots).
- For two or more robots, at ``T_total``: each robot's own rate (the cells its own sensor reached,
  not what it merged), their standard deviation (NumPy's population std, as the script prints
  ``exploration coverage std``) and the overlap rate, their sum minus 1.

What our simulator does differently: the robots start where the episode's seed puts them (on a
random free cell; a team at :func:`~frontier_rl.swarm.starts.team_starts`), where Explore-Bench
places them by hand in its launch files; the time is simulated (s), not the wall clock of a Gazebo
run; a robot's own map is its mapper's cells reached by its own scans (Explore-Bench reads each
robot's Cartographer map). A run whose rate never reaches 0.99 (a SLAM blueprint often knows free
pockets no robot can reach) has no ``T_total``; its path is then the whole episode's.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import partial
from pathlib import Path

import numpy as np

from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import ExplorationPolicy, drive_episode
from frontier_rl.core.world.worlds import World
from frontier_rl.errors import ConfigError, short_repr
from frontier_rl.evaluation.protocols.published import run_jobs
from frontier_rl.evaluation.running.methods import episode_policy
from frontier_rl.io import ros_map_shades
from frontier_rl.swarm import TeamConfig, TeamResult
from frontier_rl.swarm.episode import check_team_policy
from frontier_rl.swarm.team import TeamSimulator
from frontier_rl.world_spec import parse_world_list, resolve_world

T90_RATE = 0.9
"""Explore-Bench's ``T_90``: the exploration rate at which it is taken."""

END_RATE = 0.99
"""Explore-Bench ends a run (``T_total``) when the exploration rate reaches this."""


@dataclass(frozen=True)
class ExploreBenchRun:
    """One (method, map, seed, team size) run, with Explore-Bench's metrics and ours.

    Attributes:
        method, map_name, seed, robots: what ran.
        t90_s, t_total_s: when the exploration rate first reached 0.9 and 0.99 (sim s); None if never.
        path_m: distance driven by all robots until ``T_total`` (the whole episode without one) (m).
        final_rate: the exploration rate at the end of the episode.
        coverage_std, overlap_rate: with two or more robots, at ``T_total`` (the episode's end
            without one): the std of the robots' own rates and their sum minus 1; None for one robot.
        sim_time_s, explored: our metrics: when our episode ended (s) and whether it ended explored.
    """

    method: str
    map_name: str
    seed: int
    robots: int
    t90_s: float | None
    t_total_s: float | None
    path_m: float
    final_rate: float
    coverage_std: float | None
    overlap_rate: float | None
    sim_time_s: float
    explored: bool


UNKNOWN_GREY = 205
"""The pixel value of unknown space in a ROS map image; Explore-Bench's ground truth is the rest."""


def blueprint_known_cells(map_file: Path, cell_m: float) -> float:
    """Explore-Bench's ground-truth area, the pixels of the ROS map's image that are not
    :data:`UNKNOWN_GREY`, in cells of ``cell_m`` m (the simulated world's, which may be coarser
    than the image's). Not the cells the map loads as known: ``nav2_depot``'s YAML has a
    ``free_thresh`` of 0.25, which loads its 8,894 grey pixels as free."""
    shades, resolution = ros_map_shades(map_file)
    return int(np.count_nonzero(np.rint(shades) != UNKNOWN_GREY)) * (resolution / cell_m) ** 2


class _RateRecorder(TeamSimulator):
    """A team that notes Explore-Bench's figures at every map update: the rate of the cells the
    surviving robots know, ``T_90``, and at ``T_total`` the path driven and each robot's own rate."""

    def __init__(self, world: World, config: SimConfig, team: TeamConfig, rng: np.random.Generator, known: float):
        # set before the team's constructor: it records the first scans
        self.blueprint_cells = max(known, 1.0)
        self.t90_s: float | None = None
        self.t_total_s: float | None = None
        self.path_at_end: float | None = None
        self.own_rates_at_end: list[float] | None = None
        super().__init__(world, config, team, rng)

    def own_rates(self) -> list[float]:
        """Each robot's own exploration rate: the cells its own scans reached over the blueprint's."""
        return [int(np.count_nonzero(r.sim.mapper.observed)) / self.blueprint_cells for r in self.robots]

    def rate(self) -> float:
        """The exploration rate of what the surviving robots know."""
        return int(np.count_nonzero(self.known)) / self.blueprint_cells

    def _knowledge_updated(self, time_s: float) -> None:
        if self.t_total_s is not None:
            return
        rate = self.rate()
        if self.t90_s is None and rate >= T90_RATE:
            self.t90_s = time_s
        if rate >= END_RATE:
            self.t_total_s = time_s
            self.path_at_end = sum(r.sim.path_length for r in self.robots)
            self.own_rates_at_end = self.own_rates()


def run_explore_bench(
    method: str, map_file: Path, seed: int, robots: int = 1, config: SimConfig | None = None
) -> ExploreBenchRun:
    """One Explore-Bench run of ``method`` with ``robots`` robots on the ROS map ``map_file``."""
    world = resolve_world(str(map_file), seed)
    known = blueprint_known_cells(map_file, world.grid.resolution)
    policy: ExplorationPolicy = episode_policy(method, False)
    check_team_policy(policy, robots)
    team = TeamConfig(robots=robots)
    sim_config = config or SimConfig()

    def recorder(rng: np.random.Generator) -> _RateRecorder:
        return _RateRecorder(world, sim_config, team, rng, known)

    loop, wall_time = drive_episode(recorder, world, policy, seed, robots)
    result: TeamResult = loop.result(wall_time)
    rates = loop.own_rates_at_end if loop.own_rates_at_end is not None else loop.own_rates()
    team_figures = robots > 1
    return ExploreBenchRun(
        method=method,
        map_name=f"{map_file.parent.name}/{map_file.name}",
        seed=seed,
        robots=robots,
        t90_s=loop.t90_s,
        t_total_s=loop.t_total_s,
        path_m=result.path_length_m if loop.path_at_end is None else loop.path_at_end,
        final_rate=loop.rate(),
        coverage_std=float(np.std(rates)) if team_figures else None,
        overlap_rate=float(np.sum(rates) - 1.0) if team_figures else None,
        sim_time_s=result.sim_time_s,
        explored=result.done,
    )


def explore_bench_maps(text: str) -> list[Path]:
    """The ROS maps (YAML files, or folders of them) of a comma-separated list: the blueprints.

    Raises:
        ConfigError: an entry that is a generator or another kind of map file (a blueprint needs
            its unknown pixels, which only a ROS map keeps), or a folder without ROS maps.
    """
    maps = []
    for entry in parse_world_list(text):
        if Path(entry).suffix.lower() not in (".yaml", ".yml"):
            raise ConfigError(
                f"--maps {short_repr(entry)} is not a ROS map (YAML): Explore-Bench's blueprints need the "
                "unknown pixels that only a ROS map keeps"
            )
        maps.append(Path(entry))
    return maps


@dataclass(frozen=True)
class ExploreBenchJob:
    """One Explore-Bench run: ``method`` with ``robots`` robots on the ROS map ``map_file`` from
    start ``seed``."""

    method: str
    map_file: Path
    seed: int
    robots: int = 1


def run_explore_bench_job(job: ExploreBenchJob) -> ExploreBenchRun:
    """:func:`run_explore_bench` of ``job`` (a worker's task)."""
    return run_explore_bench(job.method, job.map_file, job.seed, job.robots)


def run_explore_bench_all(
    methods: Sequence[str], maps: Sequence[Path], seeds: int, robots: Sequence[int], workers: int | None = None
) -> tuple[list[ExploreBenchRun], list[str]]:
    """Every method with every team size on every map from starts 0..seeds-1, in ``workers``
    processes: the runs, and a line for each run that failed (the others are kept)."""
    jobs = [ExploreBenchJob(m, p, s, n) for m in methods for n in robots for p in maps for s in range(seeds)]
    # a policy of one robot's tour of the true map (the oracle) is refused before any run, not after
    return run_jobs(run_explore_bench_job, jobs, workers, partial(check_team_policy, robots=max(robots)))


@dataclass(frozen=True)
class ExploreBenchSummary:
    """Explore-Bench's line for a (method, team size, map): the means of its metrics over the runs,
    NaN where no run gives one.

    Attributes:
        method, robots, map: which runs (the map as ``folder/file``).
        runs: how many; ended: how many reached ``T_total``.
        t90_s: mean ``T_90`` (s) over the runs that reached it.
        t_total_s, path_m: mean ``T_total`` (s) and path (m) over the runs that ended.
        coverage_std, overlap_rate: the team figures' means over the runs that ended.
        final_rate: mean exploration rate at the end.
        ours_time_s: our mean exploration time (s).
    """

    method: str
    robots: int
    map: str
    runs: int
    ended: int
    t90_s: float
    t_total_s: float
    path_m: float
    coverage_std: float
    overlap_rate: float
    final_rate: float
    ours_time_s: float


def explore_bench_rows(runs: Sequence[ExploreBenchRun]) -> list[ExploreBenchSummary]:
    """Per (method, team size, map), in the runs' order: :class:`ExploreBenchSummary`."""

    def mean(values: list[float | None]) -> float:
        kept = [v for v in values if v is not None]
        return float(np.mean(kept)) if kept else math.nan

    rows = []
    for method, robots, map_name in dict.fromkeys((r.method, r.robots, r.map_name) for r in runs):
        mine = [r for r in runs if (r.method, r.robots, r.map_name) == (method, robots, map_name)]
        ended = [r for r in mine if r.t_total_s is not None]
        rows.append(
            ExploreBenchSummary(
                method=method,
                robots=robots,
                map=map_name,
                runs=len(mine),
                ended=len(ended),
                t90_s=mean([r.t90_s for r in mine]),
                t_total_s=mean([r.t_total_s for r in ended]),
                path_m=mean([r.path_m for r in ended]),
                coverage_std=mean([r.coverage_std for r in ended]),
                overlap_rate=mean([r.overlap_rate for r in ended]),
                final_rate=mean([r.final_rate for r in mine]),
                ours_time_s=mean([r.sim_time_s for r in mine]),
            )
        )
    return rows
