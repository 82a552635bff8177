"""What a team episode did: the single-robot metrics for the team, plus per-robot figures."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.sim.metrics import EpisodeResult, EpisodeSummary
from frontier_rl.core.world.grid import OccupancyGrid
from frontier_rl.swarm.config import Strategy


@dataclass(frozen=True)
class TeamResult(EpisodeResult):
    """A team episode. The inherited fields describe the team: ``sim_time_s`` is when the last
    robot stopped, ``coverage`` and its curve count the cells the surviving robots know,
    ``path_length_m``, ``decisions`` and ``aborts`` are team totals, ``decision_log`` holds every
    robot's decisions in time order (a tie in robot order), ``trajectory`` and ``final_map`` are
    robot 0's (see ``trajectories`` and ``team_map`` for all).

    Attributes:
        robots: team size.
        strategy: how the robots shared the work.
        overlap: share of the explorable cells the robots' own sensors reached that more than one
            robot's did (0 = no double work).
        robot_path_lengths_m: distance each robot drove (m).
        robot_coverage: share of the explorable cells each robot's own sensor reached.
        failed_at_s: when each robot failed (s), None for robots that did not.
        trajectories: each robot's (n, 3) poses.
        team_map: the surviving robots' maps merged, at the end.
    """

    robots: int = 1
    strategy: Strategy = Strategy.UNCOORDINATED
    overlap: float = 0.0
    robot_path_lengths_m: tuple[float, ...] = ()
    robot_coverage: tuple[float, ...] = ()
    failed_at_s: tuple[float | None, ...] = ()
    trajectories: tuple[NDArray[np.float64], ...] = field(repr=False, default=())
    team_map: OccupancyGrid | None = field(repr=False, default=None)

    def summary(self) -> TeamSummary:
        """The scalar metrics, rounded as the result files keep them, with the team's figures."""
        return TeamSummary(
            **vars(super().summary()),
            robots=self.robots,
            strategy=self.strategy,
            overlap=round(self.overlap, 5),
            robot_path_lengths_m=tuple(round(v, 3) for v in self.robot_path_lengths_m),
            robot_coverage=tuple(round(v, 5) for v in self.robot_coverage),
            failed_at_s=tuple(None if t is None else round(t, 3) for t in self.failed_at_s),
        )


@dataclass(frozen=True)
class TeamSummary(EpisodeSummary):
    """A team episode's scalar metrics (:meth:`TeamResult.summary`), rounded as those of one robot;
    each of the team's fields is the :class:`TeamResult` attribute of the same name."""

    robots: int
    strategy: Strategy
    overlap: float
    robot_path_lengths_m: tuple[float, ...]
    robot_coverage: tuple[float, ...]
    failed_at_s: tuple[float | None, ...]


def overlap_share(observed: list[NDArray[np.bool_]], explorable: NDArray[np.bool_]) -> float:
    """Share of the explorable cells reached by any robot's own sensor that more than one reached."""
    counts = np.zeros(explorable.shape, np.int16)
    for seen in observed:
        counts += seen & explorable
    reached = np.count_nonzero(counts)
    return float(np.count_nonzero(counts > 1) / reached) if reached else 0.0
