"""A frontier tour: drive to the first frontier of the shortest open tour over the nearest ones.

Greedy policies (``nearest``, the cheapest path) leave small pockets behind and come back for them
later across the map; planners such as FUEL (Zhou et al. 2021) and TARE (Cao et al. 2021) instead
order the frontiers by a travelling-salesman tour from the robot and go to its first stop. This is
that idea on the robot's own map: planner path costs between the robot and its ``max_frontiers``
cheapest frontiers, an exact open tour over them (Held-Karp), and its first stop ranked first.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from frontier_rl.core.frontiers.ranking import nearest_cost, rank
from frontier_rl.core.navigation.config import MAX_STOPS
from frontier_rl.core.navigation.tours import costs_to_stops, open_tour, stop_costs
from frontier_rl.core.sim.episode import DecisionContext, Ranking
from frontier_rl.errors import ConfigError
from frontier_rl.policies.spec import TOUR_STOPS


@dataclass(frozen=True)
class FrontierTour:
    """The first stop of the shortest open tour (planner path costs on the robot's map) over the
    ``max_frontiers`` frontiers cheapest to reach; the rest follow by path cost (by straight-line
    distance where a large map's search stopped before them). The context's robot radius sets the
    blocks a large map is searched on (:func:`~frontier_rl.core.navigation.tours.costs_to_stops`)."""

    max_frontiers: int = TOUR_STOPS
    name: str = "tour"

    def __post_init__(self) -> None:
        if not 1 <= self.max_frontiers <= MAX_STOPS:
            raise ConfigError(f"max_frontiers must be 1 to {MAX_STOPS}, got {self.max_frontiers!r}")

    def rank(self, context: DecisionContext, rng: np.random.Generator) -> Ranking:
        """Order the candidates: the tour's stops first, in tour order, then the rest by path cost."""
        frontiers, costmap = context.frontiers, context.costmap
        if costmap is None or len(frontiers) < 2:
            return Ranking(rank(nearest_cost(frontiers)))
        start = context.grid.world_to_cell(context.pose.x, context.pose.y)
        goals = np.asarray(frontiers.goal_cells, np.int64)
        radius = context.robot_radius
        from_robot = costs_to_stops(costmap, start, goals, radius, self.max_frontiers)
        by_cost = np.lexsort((nearest_cost(frontiers), from_robot))
        stops = by_cost[: self.max_frontiers]
        tour = stops[open_tour(stop_costs(costmap, start, goals[stops], radius, from_robot[stops]))]
        return Ranking(np.concatenate((tour, by_cost[self.max_frontiers :])).astype(np.int64))
