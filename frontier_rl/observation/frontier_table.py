"""Model 5's observation without Gymnasium: the map image and a table of the K cheapest frontiers,
and the order in which a chosen row's frontiers are tried."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.frontiers.detection import Frontiers
from frontier_rl.core.navigation.costmap import Costmap
from frontier_rl.core.navigation.group_costs import group_path_costs
from frontier_rl.core.navigation.tours import first_stop_costs, stop_costs
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.robot import Pose
from frontier_rl.observation.map_image import FRONTIER_FEATURES, MapEncoder, frontier_cells, frontier_features

FEATURE_BOUND = 10.0
"""Frontier features are clipped to ±FEATURE_BOUND (they are scaled to about ±1)."""

UNREACHABLE_COST_M = 100.0
"""Path cost (m) given to a frontier the planner finds no path to."""

TOUR_FEATURE = "tour_regret"
"""Model 7's extra column: how much longer the shortest open tour from the robot through the
table's first :data:`TOUR_STOPS` frontiers gets when it visits this one first (m over 10; 0 for the
tour's own first stop, :data:`FEATURE_BOUND` for the rows beyond them)."""

TOUR_STOPS = 10
"""The frontiers (the cheapest rows) a model-7 table's tour runs through."""


def frontier_path_costs(
    costmap: Costmap, pose: Pose, frontiers: Frontiers, robot_radius: float, want: int | None = None
) -> NDArray[np.float64]:
    """Planner path cost (m) from the robot (from where it sets out when it stands too close to a
    wall, :meth:`~frontier_rl.core.navigation.costmap.Costmap.set_out`) to each frontier: the
    cheapest cell within the robot's radius (a square window) of one of its fringe cells (fringe
    cells hug walls, where the robot centre cannot go); :data:`UNREACHABLE_COST_M` where there is
    no path. With ``want``, only the ``want`` cheapest are searched for (exact, and with them any
    tied): the others are inf unless the search covered all it could reach, so a decision's work
    grows with the distance to its nearest frontiers, not with the size of the map. On a map of more than
    :data:`~frontier_rl.core.navigation.group_costs.MAX_SEARCH_CELLS` cells the costs are
    estimated on blocks of cells (:func:`~frontier_rl.core.navigation.group_costs.group_path_costs`)."""
    grid = costmap.grid
    reach = max(1, math.ceil(robot_radius / grid.resolution) + 1)
    members, groups = frontier_cells(frontiers)
    costs, exhausted = costmap.costs_from(
        grid.world_to_cell(pose.x, pose.y),
        lambda start: group_path_costs(costmap, start, members, groups, len(frontiers), reach, robot_radius, want),
    )
    if exhausted:
        costs[np.isinf(costs)] = UNREACHABLE_COST_M
    return costs


def tour_regret(costmap: Costmap, pose: Pose, frontiers: Frontiers, robot_radius: float) -> NDArray[np.float32]:
    """:data:`TOUR_FEATURE` of ``frontiers`` (in table order, cheapest first) for a robot of
    ``robot_radius`` m at ``pose``."""
    regret = np.full(len(frontiers), FEATURE_BOUND, np.float32)
    stops = min(len(frontiers), TOUR_STOPS)
    if stops:
        start = costmap.grid.world_to_cell(pose.x, pose.y)
        firsts = first_stop_costs(stop_costs(costmap, start, frontiers.goal_cells[:stops], robot_radius))
        regret[:stops] = (firsts - firsts.min()) / 10.0
    return regret


def frontier_observation(
    encoder: MapEncoder,
    top_k: int,
    costmap: Costmap,
    pose: Pose,
    frontiers: Frontiers,
    robot_radius: float,
    sensor_range: float,
    tour: bool = False,
) -> tuple[dict[str, NDArray[Any]], NDArray[np.int64]]:
    """The frontier-choice observation, and for each filled slot the index of its frontier; with
    ``tour``, the table has model 7's :data:`TOUR_FEATURE` as its last column."""
    table = np.zeros((top_k, len(FRONTIER_FEATURES) + tour), np.float32)
    slots = np.zeros(0, np.int64)
    if len(frontiers):
        costs = frontier_path_costs(costmap, pose, frontiers, robot_radius, want=top_k)
        slots = np.argsort(costs, kind="stable")[:top_k].astype(np.int64)
        chosen = frontiers.subset(slots)
        feats = frontier_features(chosen, pose, costs[slots], sensor_range)
        if tour:
            feats = np.column_stack((feats, tour_regret(costmap, pose, chosen, robot_radius)))
        table[: len(slots)] = np.clip(feats, -FEATURE_BOUND, FEATURE_BOUND)
    mask = np.zeros(top_k, np.float32)
    mask[: len(slots)] = 1.0
    obs: dict[str, NDArray[Any]] = {
        "map": encoder.encode(costmap.grid, pose, frontiers),
        "frontiers": table.reshape(-1),
        "mask": mask,
    }
    return obs, slots


def simulator_observation(
    encoder: MapEncoder, top_k: int, sim: ExplorationSimulator, tour: bool = False
) -> tuple[dict[str, NDArray[Any]], NDArray[np.int64]]:
    """:func:`frontier_observation` of a simulator's decision now: its candidates and costmap, its
    pose, its robot's radius and its LiDAR's range (what a frontier-choice env shows its robot)."""
    cand = sim.candidates()
    radius, sensor_range = sim.config.robot.radius, sim.config.lidar.max_range
    return frontier_observation(encoder, top_k, cand.costmap, sim.pose, cand.frontiers, radius, sensor_range, tour)


def slot_order(slots: NDArray[np.int64], action: int) -> NDArray[np.int64]:
    """Frontier indices to try, the chosen slot first (taken modulo the filled slots), then the
    other slots cheapest first: if no path to the chosen one can be planned, the next is tried."""
    chosen = action % len(slots)
    return np.concatenate(([slots[chosen]], np.delete(slots, chosen))).astype(np.int64)
