"""Thesis models 1 and 2: the policy picks a cell of the map image and the robot navigates there."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.sim.leg_result import LegResult
from frontier_rl.core.world.grid import CellState
from frontier_rl.envs.base import MapImageEnv
from frontier_rl.observation.map_image import MAP_FREE, MAP_OCCUPIED


class PointEnv(MapImageEnv):
    """Observation: the map image (model 2), or the map, frontier and pose channels (model 1).
    Action: a pixel of the image, ``row · size + col``; the robot drives to the reachable cell
    nearest to that pixel's centre. On top of the preset's leg reward, the chosen cell earns the
    thesis's table 3.1 reward by its state in the image (free, unknown, occupied, next to a wall).

    Arguments as :class:`MapImageEnv` (``with_frontiers_and_pose`` makes it model 1).
    """

    _last_obs: NDArray[np.uint8] | None = None

    def _make_action_space(self) -> gym.spaces.Discrete:
        return gym.spaces.Discrete(self.encoder.size * self.encoder.size)

    def _observe(self) -> NDArray[np.uint8]:
        self._last_obs = super()._observe()
        return self._last_obs

    def _act(self, action: int) -> tuple[LegResult, float]:
        row, col = divmod(action, self.encoder.size)
        sim = self.sim
        x, y = self.encoder.pixel_to_world(sim.map(), sim.pose, row, col)
        assert self._last_obs is not None
        cell_reward = self.rewards.cell_reward(pixel_states(self._last_obs[0]), row, col)
        return sim.go_to(x, y), cell_reward


def pixel_states(map_channel: NDArray[np.uint8]) -> NDArray[np.int8]:
    """The cell states an agent sees in the map channel of an observation."""
    states = np.full(map_channel.shape, CellState.UNKNOWN, np.int8)
    states[map_channel == MAP_OCCUPIED] = CellState.OCCUPIED
    states[map_channel == MAP_FREE] = CellState.FREE
    return states
