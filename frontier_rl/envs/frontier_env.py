"""Model 5, the thesis's future work: the policy chooses one of the top-K candidate frontiers."""

from __future__ import annotations

import math
from typing import Any

import gymnasium as gym
import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from frontier_rl.core.frontiers.detection import Frontiers
from frontier_rl.core.navigation.costmap import Costmap
from frontier_rl.core.sim.leg import LegResult
from frontier_rl.core.world.robot import Pose
from frontier_rl.envs.base import EnvConfig, ExplorationEnv
from frontier_rl.envs.observation import FRONTIER_FEATURES, MapEncoder, frontier_features
from frontier_rl.errors import ConfigError

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


class FrontierChoiceEnv(ExplorationEnv[dict[str, NDArray[Any]]]):
    """Observation (a dict): ``map``, the map with frontier and pose channels; ``frontiers``, a
    (K, 6) table, flattened row by row, of per-frontier features (:data:`FRONTIER_FEATURES`) for
    the K candidates with the lowest path cost, cheapest first; ``mask``, 1 for the rows that hold
    a frontier. Action: a row
    of the table. A masked row (fewer than K frontiers) is taken modulo the number of frontiers, so
    every action in the space is legal; :meth:`action_masks` gives the mask for maskable algorithms.

    Args:
        config: shared settings (:class:`EnvConfig`).
        top_k: number of candidate slots K.
        render_mode: None or "rgb_array".
        **overrides: fields of :class:`EnvConfig`.
    """

    def __init__(
        self, config: EnvConfig | None = None, top_k: int = 16, render_mode: str | None = None, **overrides: Any
    ) -> None:
        super().__init__(config, render_mode, **overrides)
        if not 1 <= top_k <= 256:
            raise ConfigError(f"top_k must be between 1 and 256, got {top_k!r}")
        self.top_k = top_k
        self.encoder = MapEncoder(self.config.observation_size, frontier_channel=True, pose_channel=True)
        self.observation_space = gym.spaces.Dict(  # type: ignore[assignment]
            {
                "map": gym.spaces.Box(0, 255, self.encoder.shape, np.uint8),
                "frontiers": gym.spaces.Box(
                    -FEATURE_BOUND, FEATURE_BOUND, (top_k * len(FRONTIER_FEATURES),), np.float32
                ),
                "mask": gym.spaces.Box(0.0, 1.0, (top_k,), np.float32),
            }
        )
        self.action_space = gym.spaces.Discrete(top_k)
        self._slots = np.zeros(0, np.int64)  # slot -> index into the simulator's frontiers

    def action_masks(self) -> NDArray[np.bool_]:
        """Which actions point at a real frontier (for MaskablePPO and the like)."""
        mask = np.zeros(self.top_k, np.bool_)
        mask[: len(self._slots)] = True
        return mask

    def _observe(self) -> dict[str, NDArray[Any]]:
        sim = self.sim
        cand = sim.candidates()
        obs, self._slots = frontier_observation(
            self.encoder, self.top_k, cand.costmap, sim.pose, cand.frontiers, sim.config.robot.radius,
            sim.config.lidar.max_range,
        )  # fmt: skip
        return obs

    def _act(self, action: int) -> tuple[LegResult, float]:
        return self.sim.execute(slot_order(self._slots, action)), 0.0
