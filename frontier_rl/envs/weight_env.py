"""Thesis models 3 and 4: the policy picks the ranking weight w of eq. 3.1 from the map; model 6
picks it from the map and the frontier table of model 5."""

from __future__ import annotations

from typing import Any

import gymnasium as gym

from frontier_rl.core.frontiers.ranking import rank, weighted_cost
from frontier_rl.core.sim.leg_result import LegResult
from frontier_rl.envs.base import ExplorationEnv, MapImageEnv
from frontier_rl.envs.frontier_env import FrontierTableEnv
from frontier_rl.observation.weight_bins import WEIGHT_BINS, bin_to_weight


class WeightAction(ExplorationEnv[Any]):
    """The weight models' action, mixed into an env class before its observation's base: a weight
    bin; the frontiers are ranked by ``w·d + (1 − w)·(1 − g)`` and the robot drives to the best
    one it can plan to. The step's info holds the weight."""

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


class WeightEnv(WeightAction, MapImageEnv):
    """Observation: the map image (model 4), or the map, frontier and pose channels (model 3).
    Action: a weight bin (:class:`WeightAction`). Arguments as :class:`MapImageEnv`
    (``with_frontiers_and_pose`` makes it model 3).
    """


class WeightTableEnv(WeightAction, FrontierTableEnv):
    """Model 6: the observation of model 5 (:class:`FrontierTableEnv`: the map image and a table
    of the cheapest frontiers' features), the action of model 3 (a weight bin,
    :class:`WeightAction`). A weight that depends on the map needs to see what the ranking trades
    off; the table shows the distances, sizes and information gains of the frontiers cheapest to
    reach (eq. 3.1 ranks, and normalises over, all of them, so with more than K candidates some lie
    outside the table). Arguments as :class:`FrontierTableEnv`.
    """
