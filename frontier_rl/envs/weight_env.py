"""Thesis models 3 and 4: the policy picks the ranking weight w of eq. 3.1 from the map."""

from __future__ import annotations

from typing import Any

import gymnasium as gym

from frontier_rl.core.frontiers.ranking import rank, weighted_cost
from frontier_rl.core.sim.leg import LegResult
from frontier_rl.envs.base import MapImageEnv
from frontier_rl.observation.weight_bins import WEIGHT_BINS, bin_to_weight


class WeightEnv(MapImageEnv):
    """Observation: the map image (model 4), or the map, frontier and pose channels (model 3).
    Action: a weight bin; the frontiers are ranked by ``w·d + (1 − w)·(1 − g)`` and the robot
    drives to the best one it can plan to. Arguments as :class:`MapImageEnv`
    (``with_frontiers_and_pose`` makes it model 3).
    """

    def _make_action_space(self) -> gym.spaces.Discrete:
        return gym.spaces.Discrete(WEIGHT_BINS)

    def _act(self, action: int) -> tuple[LegResult, float]:
        weight = bin_to_weight(action)
        order = rank(weighted_cost(self.sim.frontiers(), weight))
        return self.sim.execute(order, weight), 0.0

    def _info(self, leg: LegResult | None) -> dict[str, Any]:
        info = super()._info(leg)
        if leg is not None and self.sim.log.decisions:
            info["weight"] = self.sim.log.decisions[-1].weight
        return info
