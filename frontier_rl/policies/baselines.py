"""Classic frontier-selection baselines behind the :class:`ExplorationPolicy` interface."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from frontier_rl.checked_values import check_weight
from frontier_rl.core.frontiers.ranking import (
    ExploreLiteParams,
    explore_lite_cost,
    information_gain_cost,
    largest_cost,
    nearest_cost,
    random_cost,
    rank,
    weighted_cost,
)
from frontier_rl.core.frontiers.thesis import THESIS_WEIGHT
from frontier_rl.core.sim.episode import DecisionContext, Ranking


@dataclass(frozen=True)
class NearestFrontier:
    """Nearest frontier first (Yamauchi 1997)."""

    name: str = "nearest"

    def rank(self, context: DecisionContext, rng: np.random.Generator) -> Ranking:
        """Order by straight-line distance to the centre."""
        return Ranking(rank(nearest_cost(context.frontiers)))


@dataclass(frozen=True)
class LargestFrontier:
    """Largest frontier first."""

    name: str = "largest"

    def rank(self, context: DecisionContext, rng: np.random.Generator) -> Ranking:
        """Order by number of cells, largest first."""
        return Ranking(rank(largest_cost(context.frontiers)))


@dataclass(frozen=True)
class FixedWeight:
    """Thesis eq. 3.1 with a fixed weight ``w`` (0.75 is the thesis's baseline)."""

    weight: float = THESIS_WEIGHT
    name: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        check_weight(self.weight)
        if not self.name:
            object.__setattr__(self, "name", f"fixed:{self.weight:g}")

    def rank(self, context: DecisionContext, rng: np.random.Generator) -> Ranking:
        """Order by ``w·d + (1 − w)·(1 − g)``."""
        return Ranking(rank(weighted_cost(context.frontiers, self.weight)), self.weight)


@dataclass(frozen=True)
class ExploreLite:
    """explore_lite's cost: ``potential_scale·distance − gain_scale·size``."""

    params: ExploreLiteParams = field(default_factory=ExploreLiteParams)
    name: str = "explore-lite"

    def rank(self, context: DecisionContext, rng: np.random.Generator) -> Ranking:
        """Order by explore_lite's cost; frontiers under its minimum size are skipped unless
        nothing else is left (explore_lite would stop there, leaving the map unfinished)."""
        order = rank(explore_lite_cost(context.frontiers, self.params))
        if order.size == 0:
            order = rank(nearest_cost(context.frontiers))
        return Ranking(order)


@dataclass(frozen=True)
class InformationGain:
    """Most unknown cells revealed per scan, discounted by distance (González-Baños & Latombe)."""

    distance_decay: float = 0.2
    name: str = "info-gain"

    def rank(self, context: DecisionContext, rng: np.random.Generator) -> Ranking:
        """Order by ``gain·exp(−λ·d)``, highest first."""
        costs = information_gain_cost(context.frontiers, context.sensor_range, self.distance_decay)
        return Ranking(rank(costs))


@dataclass(frozen=True)
class RandomFrontier:
    """A uniformly random frontier."""

    name: str = "random"

    def rank(self, context: DecisionContext, rng: np.random.Generator) -> Ranking:
        """A random order drawn from ``rng``."""
        return Ranking(rank(random_cost(context.frontiers, rng)))
