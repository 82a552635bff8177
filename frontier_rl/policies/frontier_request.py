"""What the ROS frontier node answers, without ROS: a map message's cells to a grid, and the
ranked frontiers of that grid for a robot pose.

Kept free of rospy so that it is tested and used anywhere; the node only converts messages.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.navigation.inflation import InflationMemory
from frontier_rl.core.sim.candidates import reachable_frontiers
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import DecisionContext, ExplorationPolicy
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.errors import MapError


@dataclass(frozen=True)
class MapThresholds:
    """How occupancy values (0 to 100, -1 unknown) become cell states, as map_server reads them.

    Attributes:
        occupied_above: values above this are occupied (%).
        free_below: values below this are free (%); values in between are unknown.
    """

    occupied_above: float = 65.0
    free_below: float = 19.6


@dataclass(frozen=True)
class RankedFrontier:
    """One frontier of the answer: its centre in the map frame (m) and its size (cells)."""

    x: float
    y: float
    size: int


def check_map_message(width: int, height: int, resolution: float, values: int) -> None:
    """Raise :class:`MapError` for a ``nav_msgs/OccupancyGrid`` of zero size, a resolution (m) that
    is not a positive number, or ``values`` data values that are not width × height."""
    if width <= 0 or height <= 0:
        raise MapError(f"map of size {width} × {height} has no cells")
    if not (math.isfinite(resolution) and resolution > 0):
        raise MapError(f"map resolution must be a positive number of metres, got {resolution!r}")
    if values != width * height:
        raise MapError(f"map data has {values} values, expected width × height = {width * height}")


def grid_from_message(
    width: int,
    height: int,
    resolution: float,
    data: Sequence[int] | NDArray[np.integer[Any]],
    thresholds: MapThresholds | None = None,
) -> OccupancyGrid:
    """A grid (origin 0, 0: the map's own cell frame) from a ``nav_msgs/OccupancyGrid``'s size,
    resolution (m) and row-major data; probabilities are thresholded, not rejected. A map of zero
    size, a resolution that is not positive, or data of the wrong length is a :class:`MapError`.
    The message's resolution is a float32 and is read as the decimal it was written as (0.05 m,
    not 0.0500000007 m), so that the grid's cells are those of the same map loaded from its YAML."""
    t = thresholds or MapThresholds()
    check_map_message(width, height, resolution, len(data))
    values = np.asarray(data, dtype=np.int16).reshape(height, width)
    cells = np.full(values.shape, CellState.UNKNOWN, np.int8)
    known = values >= 0
    cells[known & (values > t.occupied_above)] = CellState.OCCUPIED
    cells[known & (values < t.free_below)] = CellState.FREE
    return OccupancyGrid(cells, as_written(resolution), (0.0, 0.0))


def as_written(resolution: float) -> float:
    """A float32 ``resolution`` (m) as the decimal it was written as: 0.05 for 0.0500000007. A value
    a float32 cannot hold (a float64 from elsewhere) is kept as it is."""
    single = np.finfo(np.float32)
    if not (float(single.tiny) <= resolution <= float(single.max)):
        return float(resolution)
    return float(str(np.float32(resolution)))


def rank_frontiers(
    grid: OccupancyGrid,
    pose: Pose,
    policy: ExplorationPolicy,
    top_k: int = 10,
    min_cluster_cells: int = 4,
    sim: SimConfig | None = None,
    rng: np.random.Generator | None = None,
    memory: InflationMemory | None = None,
) -> tuple[list[RankedFrontier], float | None]:
    """The ``top_k`` frontiers of ``grid`` that the robot at ``pose`` (grid frame, m) can reach
    through known free space, best first by ``policy``, and the weight the policy used. With
    ``memory`` (the robot's last costmap inflation), the costmap is inflated again only where the
    walls changed since the last request."""
    sim = sim or SimConfig()
    costmap, _, frontiers = reachable_frontiers(grid, pose, sim, min_cluster_cells, memory=memory)
    if len(frontiers) == 0:
        return [], None
    context = DecisionContext(grid, frontiers, pose, 0.0, sim.lidar.max_range, costmap, robot_radius=sim.robot.radius)
    ranking = policy.rank(context, rng or np.random.default_rng(0))
    order = [int(i) for i in ranking.order[:top_k]]
    ranked = [
        RankedFrontier(float(frontiers.centers[i, 0]), float(frontiers.centers[i, 1]), int(frontiers.sizes[i]))
        for i in order
    ]
    return ranked, ranking.weight
