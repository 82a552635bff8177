"""Model 5's observation without Gymnasium: the map image and a table of the K cheapest frontiers,
and the order in which a chosen row's frontiers are tried."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from frontier_rl.core.frontiers.detection import Frontiers
from frontier_rl.core.navigation.costmap import Costmap
from frontier_rl.core.world.robot import Pose
from frontier_rl.observation.map_image import FRONTIER_FEATURES, MapEncoder, frontier_features

FEATURE_BOUND = 10.0
"""Frontier features are clipped to ±FEATURE_BOUND (they are scaled to about ±1)."""

UNREACHABLE_COST_M = 100.0
"""Path cost (m) given to a frontier the planner finds no path to."""


def frontier_path_costs(costmap: Costmap, pose: Pose, frontiers: Frontiers, robot_radius: float) -> NDArray[np.float64]:
    """Planner path cost (m) from the robot to each frontier: the cheapest cell within the robot's
    radius of one of its fringe cells (fringe cells hug walls, where the robot centre cannot go)."""
    grid = costmap.grid
    field = costmap.cost_to_go(grid.world_to_cell(pose.x, pose.y))
    reach = max(1, math.ceil(robot_radius / grid.resolution) + 1)
    near = ndimage.minimum_filter(field, size=2 * reach + 1, mode="constant", cval=np.inf).reshape(-1)
    costs = np.full(len(frontiers), UNREACHABLE_COST_M)
    for i, (start, end) in enumerate(frontiers.spans):
        best = near[frontiers.flat_cells[start:end]].min()
        if np.isfinite(best):
            costs[i] = best
    return costs


def frontier_observation(
    encoder: MapEncoder,
    top_k: int,
    costmap: Costmap,
    pose: Pose,
    frontiers: Frontiers,
    robot_radius: float,
    sensor_range: float,
) -> tuple[dict[str, NDArray[Any]], NDArray[np.int64]]:
    """The frontier-choice observation, and for each filled slot the index of its frontier."""
    table = np.zeros((top_k, len(FRONTIER_FEATURES)), np.float32)
    slots = np.zeros(0, np.int64)
    if len(frontiers):
        costs = frontier_path_costs(costmap, pose, frontiers, robot_radius)
        slots = np.argsort(costs, kind="stable")[:top_k].astype(np.int64)
        feats = frontier_features(frontiers, pose, costs, sensor_range)
        table[: len(slots)] = np.clip(feats[slots], -FEATURE_BOUND, FEATURE_BOUND)
    mask = np.zeros(top_k, np.float32)
    mask[: len(slots)] = 1.0
    obs: dict[str, NDArray[Any]] = {
        "map": encoder.encode(costmap.grid, pose, frontiers),
        "frontiers": table.reshape(-1),
        "mask": mask,
    }
    return obs, slots


def slot_order(slots: NDArray[np.int64], action: int) -> NDArray[np.int64]:
    """Frontier indices to try, the chosen slot first (taken modulo the filled slots), then the
    other slots cheapest first: if no path to the chosen one can be planned, the next is tried."""
    chosen = action % len(slots)
    return np.concatenate(([slots[chosen]], np.delete(slots, chosen))).astype(np.int64)
