"""The ranked frontiers of a robot's map for its pose, without ROS: what the ROS frontier nodes answer."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from frontier_rl.core.navigation.inflation import InflationMemory
from frontier_rl.core.sim.candidates import reachable_frontiers
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import DecisionContext, ExplorationPolicy
from frontier_rl.core.world.grid import OccupancyGrid
from frontier_rl.core.world.robot import Pose


@dataclass(frozen=True)
class RankedFrontier:
    """One frontier of the answer: its centre in the map frame (m) and its size (cells)."""

    x: float
    y: float
    size: int


def rank_frontiers(
    grid: OccupancyGrid,
    pose: Pose,
    policy: ExplorationPolicy,
    top_k: int = 10,
    min_cluster_cells: int = 4,
    sim: SimConfig | None = None,
    *,
    rng: np.random.Generator,
    memory: InflationMemory | None = None,
) -> tuple[list[RankedFrontier], float | None]:
    """The ``top_k`` frontiers of ``grid`` that the robot at ``pose`` (grid frame, m) can reach
    through known free space, best first by ``policy``, and the weight the policy used. ``rng`` is
    what a random policy draws from: one generator for all of a robot's requests (a fresh one seeded
    alike each time gave the ``random`` policy the same order every time). With ``memory`` (the
    robot's last costmap inflation), the costmap is inflated again only where the walls changed
    since the last request."""
    sim = sim or SimConfig()
    costmap, _, frontiers = reachable_frontiers(grid, pose, sim, min_cluster_cells, memory=memory)
    if len(frontiers) == 0:
        return [], None
    context = DecisionContext(grid, frontiers, pose, 0.0, sim.lidar.max_range, costmap, robot_radius=sim.robot.radius)
    ranking = policy.rank(context, rng)
    order = [int(i) for i in ranking.order[:top_k]]
    ranked = [
        RankedFrontier(float(frontiers.centers[i, 0]), float(frontiers.centers[i, 1]), int(frontiers.sizes[i]))
        for i in order
    ]
    return ranked, ranking.weight
