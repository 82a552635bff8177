"""Thesis models 3 and 4: the policy picks the ranking weight w of eq. 3.1 from the map; model 6
picks it from the map and the frontier table of model 5."""

from __future__ import annotations

from typing import Any

import gymnasium as gym

from frontier_rl.core.frontiers.ranking import rank, weighted_cost
from frontier_rl.core.sim.leg import LegResult
from frontier_rl.envs.base import ExplorationEnv, MapImageEnv
from frontier_rl.envs.frontier_env import FrontierTableEnv
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
        return _weighted_leg(self, action)

    def _info(self, leg: LegResult | None) -> dict[str, Any]:
        return _with_weight(self, super()._info(leg), leg)


class WeightTableEnv(FrontierTableEnv):
    """Model 6: the observation of model 5 (:class:`FrontierTableEnv`: the map image and a table
    of the cheapest frontiers' features), the action of model 3 (a weight bin, the frontiers
    ranked by eq. 3.1 with it). A weight that depends on the map needs to see what the ranking
    trades off; the table shows the frontiers' distances, sizes and information gains. Arguments
    as :class:`FrontierTableEnv`.
    """

    def _make_action_space(self) -> gym.spaces.Discrete:
        return gym.spaces.Discrete(WEIGHT_BINS)

    def _act(self, action: int) -> tuple[LegResult, float]:
        return _weighted_leg(self, action)

    def _info(self, leg: LegResult | None) -> dict[str, Any]:
        return _with_weight(self, super()._info(leg), leg)


def _weighted_leg(env: ExplorationEnv[Any], action: int) -> tuple[LegResult, float]:
    """The drive to the best frontier by eq. 3.1 with weight bin ``action``."""
    weight = bin_to_weight(action)
    order = rank(weighted_cost(env.sim.frontiers(), weight))
    return env.sim.execute(order, weight), 0.0


def _with_weight(env: ExplorationEnv[Any], info: dict[str, Any], leg: LegResult | None) -> dict[str, Any]:
    """``info`` with the weight the last decision used."""
    if leg is not None and env.sim.log.decisions:
        info["weight"] = env.sim.log.decisions[-1].weight
    return info
