"""A paired experiment: which methods, on which worlds, for how many episodes, and one episode of it.

Paired design: episode i of every world uses seed ``seed + i`` for the world generator (or the
random start on a map file) and for the sensor noise, so every method meets the same world, start
pose and noise in episode i. :func:`run_job` is a top-level function of plain arguments, so any
backend (a loop, a process pool, Ray tasks) runs the same episode and returns the same row.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property, lru_cache
from pathlib import Path

import numpy as np

from frontier_rl.checked_values import python_integer
from frontier_rl.core.frontiers.thesis import THESIS_BASELINE
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import ExplorationPolicy, run_episode, warm_up
from frontier_rl.core.sim.metrics import EpisodeSummary, sample_step
from frontier_rl.core.world.catalog import WORLD_GENERATORS
from frontier_rl.core.world.worlds import World
from frontier_rl.errors import ConfigError
from frontier_rl.evaluation.results.episode_record import EpisodeKey, EpisodeOutcome, EpisodeRow, EpisodeTrace
from frontier_rl.evaluation.running.methods import ORACLE, episode_policy, team_config
from frontier_rl.policies import make_policy
from frontier_rl.swarm import Failure, TeamConfig, TeamMethod, TeamSummary, run_team_episode
from frontier_rl.world_spec import parse_world_list, resolve_world

MAX_JOBS = 1_000_000
"""Most episodes (methods × worlds × episodes) an experiment may hold: its job list is built whole
(10¹² of them took the machine's memory), and a million office episodes are days of work."""

_TRACE_POINTS = 200
"""Coverage curves are stored at about this many instants per episode (enough for plots)."""


@dataclass(frozen=True)
class ExperimentConfig:
    """What a paired experiment runs.

    Attributes:
        methods: policy specs as on the command line (``fixed:0.75``, ``learned:models/model4.zip``,
            ``oracle``, ...), the baseline among them.
        worlds: generator names and map files (folders already expanded, see :func:`expand_worlds`).
        episodes: episodes per world; episode i uses seed ``seed + i``.
        seed: the first episode's seed.
        baseline: the method every other one is compared with.
        sim: simulation settings shared by every episode.
        resolution: cell size (m) for map files that carry none.
        trust_model: admit SB3 zips from elsewhere for ``learned:`` methods (unpickles them).
        comm_range: communication range (m) of the team methods (``POLICY@N[:STRATEGY]``); None:
            the strategy's default.
        failures: robot failures in every team method's episodes, kept in one order (by robot,
            then time; random ones last) so that the same failures given in another order are the
            same experiment.
    """

    methods: tuple[str, ...]
    worlds: tuple[str, ...]
    episodes: int
    seed: int = 0
    baseline: str = THESIS_BASELINE
    sim: SimConfig = field(default_factory=SimConfig)
    resolution: float | None = None
    trust_model: bool = False
    comm_range: float | None = None
    failures: tuple[Failure, ...] = ()

    def __post_init__(self) -> None:
        order = sorted(self.failures, key=lambda f: (f.robot is None, f.robot or 0, f.time_s is None, f.time_s or 0.0))
        object.__setattr__(self, "failures", tuple(order))  # frozen: set once, here
        self._check_methods()
        self._check_worlds()
        self._check_counts()
        if self.resolution is not None and not self.resolution > 0:
            raise ConfigError(f"resolution must be a positive number of metres, got {self.resolution!r}")

    def _check_methods(self) -> None:
        """The methods: some, each once, their teams and failures possible, the baseline among them."""
        if not self.methods:
            raise ConfigError("an experiment needs at least one method")
        canonical = [self.parsed_methods[m].canonical for m in self.methods]
        twice = [m for m, c in zip(self.methods, canonical, strict=True) if canonical.count(c) > 1]
        if twice:
            raise ConfigError(f"methods are listed twice (the same method written two ways): {', '.join(twice)}")
        teams = [self.team_for(m) for m in self.methods]  # a bad team size, strategy or failure fails here
        if (self.comm_range is not None or self.failures) and not any(teams):
            raise ConfigError("a communication range or failures need team methods (POLICY@N[:STRATEGY])")
        team_policies = {str(self.parsed_methods[m].policy) for m, t in zip(self.methods, teams, strict=True) if t}
        if ORACLE in team_policies:
            raise ConfigError(f"the {ORACLE} plans one robot's tour of the true map; it cannot run in a team")
        if self.baseline not in self.methods:
            raise ConfigError(f"baseline {self.baseline!r} is not among the methods {', '.join(self.methods)}")

    def _check_worlds(self) -> None:
        """The worlds: some, each once (however a map file's path is written)."""
        if not self.worlds:
            raise ConfigError("an experiment needs at least one world")
        resolved = [w if w in WORLD_GENERATORS else str(Path(w).resolve()) for w in self.worlds]
        twice = sorted({w for w, r in zip(self.worlds, resolved, strict=True) if resolved.count(r) > 1})
        if twice:
            raise ConfigError(f"worlds are listed twice (their episodes would count double): {', '.join(twice)}")

    def _check_counts(self) -> None:
        """The seed and the episodes per world (a NumPy integer taken as Python's), and the episodes in all."""
        for name in ("seed", "episodes"):
            object.__setattr__(self, name, python_integer(getattr(self, name)))
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ConfigError(f"seed must be a non-negative integer, got {self.seed!r}")
        if isinstance(self.episodes, bool) or not isinstance(self.episodes, int) or self.episodes < 1:
            raise ConfigError(f"episodes must be a positive integer, got {self.episodes!r}")
        if self.episodes * len(self.worlds) * len(self.methods) > MAX_JOBS:
            raise ConfigError(
                f"{self.episodes:,} episodes on {len(self.worlds)} world(s) with {len(self.methods)} method(s) "
                f"are more than the {MAX_JOBS:,} episodes an experiment may hold"
            )

    def jobs(self) -> list[EpisodeJob]:
        """Every (method, world, episode), episode-major so that partial results stay paired."""
        return [
            EpisodeJob(method, world, episode, self.seed + episode, self.parsed_methods[method])
            for episode in range(self.episodes)
            for world in self.worlds
            for method in self.methods
        ]

    def settings(self) -> EpisodeSettings:
        """What every episode of this experiment shares; relative paths resolve against the
        current directory, wherever a worker runs."""
        return EpisodeSettings(
            self.sim, self.resolution, self.trust_model, str(Path.cwd()), self.comm_range, self.failures
        )

    @cached_property
    def parsed_methods(self) -> dict[str, TeamMethod]:
        """Each method (as given) parsed once: its policy, and the team that runs it.

        Raises:
            ConfigError: a bad policy, team size or strategy (an unknown name an UnknownNameError).
        """
        return {method: TeamMethod.parse(method) for method in self.methods}

    def team_for(self, method: str) -> TeamConfig | None:
        """The team that runs ``method``; None for a single robot."""
        return team_config(self.parsed_methods[method], self.comm_range, self.failures)


@dataclass(frozen=True)
class EpisodeJob:
    """One episode of an experiment: ``method`` (as given) on ``world`` (name or file), episode index
    and seed, and the method parsed (``team_method``: its policy and team)."""

    method: str
    world: str
    episode: int
    seed: int
    team_method: TeamMethod

    @property
    def key(self) -> EpisodeKey:
        """A row's identity in the results."""
        return EpisodeKey(self.method, self.world, self.episode)


@dataclass(frozen=True)
class EpisodeSettings:
    """The shared settings a worker needs besides the job (picklable, small)."""

    sim: SimConfig
    resolution: float | None
    trust_model: bool
    base_dir: str
    comm_range: float | None = None
    failures: tuple[Failure, ...] = ()


def expand_worlds(text: str) -> tuple[str, ...]:
    """Generator names and map files from a comma list that may name folders of maps."""
    return parse_world_list(text)


@lru_cache(maxsize=1)
def _warm() -> None:
    """Load the compiled kernels before the first timed episode of this process (the oracle's too)."""
    warm_up()
    warm_up(make_policy(ORACLE))


def job_parts(job: EpisodeJob, settings: EpisodeSettings) -> tuple[World, ExplorationPolicy, TeamConfig | None]:
    """The world, policy and team (None for one robot) of ``job``; relative paths resolve against
    ``settings.base_dir``."""
    base = Path(settings.base_dir)
    method = job.team_method
    spec = method.policy.against(base)  # a relative model or policy file, against the experiment's folder
    world = resolve_world(job.world, job.seed, resolution=settings.resolution, base_dir=base)
    return (
        world,
        episode_policy(spec, settings.trust_model),
        team_config(method, settings.comm_range, settings.failures),
    )


def run_job(job: EpisodeJob, settings: EpisodeSettings) -> EpisodeOutcome:
    """Run one episode; its result row (scalars) and trace (coverage curve and weights)."""
    _warm()
    world, policy, team = job_parts(job, settings)
    try:
        if team is None:
            result = run_episode(world, policy, settings.sim, seed=job.seed)
        else:
            result = run_team_episode(world, policy, settings.sim, team, seed=job.seed)
    except SystemExit as exc:  # a policy's sys.exit() fails its episode: it ended a worker, or the command silently
        raise RuntimeError(f"the policy called sys.exit({exc.code!r})").with_traceback(exc.__traceback__) from None
    summary = result.summary()
    weights = [(d.time_s, d.weight) for d in result.decision_log if d.weight is not None]
    times, curve = _thin_curve(result.coverage_times_s, result.coverage_curve, result.sim_time_s)
    team_summary = summary if isinstance(summary, TeamSummary) else None
    trace = EpisodeTrace(
        method=job.method,
        world=job.world,
        episode=job.episode,
        coverage_t=tuple(times),
        coverage=tuple(curve),
        weight_t=tuple(round(t, 2) for t, _ in weights),
        weight=tuple(round(float(w), 4) for _, w in weights),
        aborts_by_cause=summary.aborts_by_cause,
        explorable_left_m2=summary.explorable_left_m2,
        frontiers_with_path_left=summary.frontiers_with_path_left,
        frontiers_with_path_to_space_left=summary.frontiers_with_path_to_space_left,
        explorable_given_up_m2=summary.explorable_given_up_m2,
        frontiers_with_path_on_map_left=summary.frontiers_with_path_on_map_left,
        frontiers_unrevealable_left=summary.frontiers_unrevealable_left,
        robot_path_lengths_m=None if team_summary is None else team_summary.robot_path_lengths_m,
        robot_coverage=None if team_summary is None else team_summary.robot_coverage,
        failed_at_s=None if team_summary is None else team_summary.failed_at_s,
    )
    mean_weight = round(float(np.mean([w for _, w in weights])), 4) if weights else None
    return EpisodeOutcome(_episode_row(job, world, summary, mean_weight), trace)


def _episode_row(job: EpisodeJob, world: World, summary: EpisodeSummary, mean_weight: float | None) -> EpisodeRow:
    """The result row of ``job``'s episode on ``world``: its start, its ``summary`` and the mean
    ranking weight it chose (None for a method without a weight)."""
    team = summary if isinstance(summary, TeamSummary) else None
    return EpisodeRow(
        method=job.method,
        world=job.world,
        episode=job.episode,
        seed=job.seed,
        start_x_m=round(world.start.x, 4),
        start_y_m=round(world.start.y, 4),
        start_theta_rad=round(world.start.theta, 4),
        sim_time_s=summary.sim_time_s,
        path_length_m=summary.path_length_m,
        coverage=summary.coverage,
        t90_s=summary.t90_s,
        t99_s=summary.t99_s,
        decisions=summary.decisions,
        aborts=summary.aborts,
        done=summary.done,
        truncated=summary.truncated,
        end_reason=summary.end_reason,
        free_coverage=summary.free_coverage,
        unknown_left_m2=summary.unknown_left_m2,
        mean_weight=mean_weight,
        robots=1 if team is None else team.robots,
        overlap=0.0 if team is None else team.overlap,
        wall_time_s=summary.wall_time_s,
    )


def _thin_curve(times: np.ndarray, curve: np.ndarray, end: float) -> tuple[list[float], list[float]]:
    """The coverage curve (a step function) sampled at :data:`_TRACE_POINTS` instants from 0 to ``end`` (s)."""
    if len(times) == 0:
        return [], []
    grid = np.linspace(0.0, max(end, float(times[-1])), _TRACE_POINTS)
    values = sample_step(times, curve, grid)
    return [round(float(t), 2) for t in grid], [round(float(v), 5) for v in values]
