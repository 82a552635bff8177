"""Frontier ranking: the thesis's weighted cost, explore_lite's cost and the classic orderings.

Every function returns a cost per frontier (lower is better); :func:`rank` turns costs into an
order. Ties are broken by frontier index, so rankings are deterministic.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from frontier_rl.checked_values import check_weight
from frontier_rl.core.frontiers.detection import Frontiers
from frontier_rl.errors import ConfigError


def normalise(values: NDArray[np.float64]) -> NDArray[np.float64]:
    """Min-max scale to [0, 1] over the candidates; all zeros when every value is equal."""
    values = np.asarray(values, dtype=np.float64)
    if values.size == 0:
        return values
    low, high = float(values.min()), float(values.max())
    if high - low <= 1e-12:
        return np.zeros_like(values)
    return (values - low) / (high - low)


def weighted_cost(frontiers: Frontiers, weight: float) -> NDArray[np.float64]:
    """Thesis eq. 3.1: ``w·d + (1 − w)·(1 − g)``, d the distance to the centre and g the size,
    both normalised to [0, 1] over the current candidates."""
    w = check_weight(weight)
    d = normalise(frontiers.distances)
    g = normalise(frontiers.sizes.astype(np.float64))
    return w * d + (1.0 - w) * (1.0 - g)


@dataclass(frozen=True)
class ExploreLiteParams:
    """explore_lite's frontier cost parameters (its defaults).

    Attributes:
        potential_scale: weight of the distance to the frontier's nearest cell (per m).
        gain_scale: weight of the frontier's size (per m of frontier length).
        min_frontier_size: frontiers shorter than this (m) are ignored.
    """

    potential_scale: float = 3.0
    gain_scale: float = 1.0
    min_frontier_size: float = 0.75


def explore_lite_cost(frontiers: Frontiers, params: ExploreLiteParams | None = None) -> NDArray[np.float64]:
    """explore_lite: ``potential_scale·distance − gain_scale·size`` with both in metres;
    frontiers shorter than ``min_frontier_size`` cost ``inf``."""
    p = params or ExploreLiteParams()
    res = frontiers.grid.resolution
    size_m = frontiers.sizes * res
    cost = p.potential_scale * frontiers.min_distances - p.gain_scale * size_m
    return np.where(size_m >= p.min_frontier_size, cost, np.inf)


def nearest_cost(frontiers: Frontiers) -> NDArray[np.float64]:
    """Nearest frontier first (Yamauchi 1997): the distance to the centre (m)."""
    return np.asarray(frontiers.distances, dtype=np.float64)


def largest_cost(frontiers: Frontiers) -> NDArray[np.float64]:
    """Largest frontier first: minus the number of cells."""
    return -frontiers.sizes.astype(np.float64)


def information_gain_cost(
    frontiers: Frontiers, sensor_range: float, distance_decay: float = 0.2
) -> NDArray[np.float64]:
    """Information gain discounted by distance (González-Baños & Latombe 2002):
    ``−gain·exp(−λ·d)``, gain the unknown cells a scan from the centre would reveal, λ in 1/m."""
    if not (distance_decay >= 0 and math.isfinite(distance_decay)):
        raise ConfigError(f"distance_decay must be >= 0, got {distance_decay!r}")
    gains = frontiers.information_gain(sensor_range).astype(np.float64)
    return -gains * np.exp(-distance_decay * frontiers.distances)


def random_cost(frontiers: Frontiers, rng: np.random.Generator) -> NDArray[np.float64]:
    """A random order: i.i.d. uniform costs drawn from ``rng``."""
    return rng.random(len(frontiers))


def rank(costs: NDArray[np.float64]) -> NDArray[np.int64]:
    """Frontier indices sorted by cost, lowest first; ``inf`` costs are left out."""
    costs = np.asarray(costs, dtype=np.float64)
    order = np.argsort(costs, kind="stable")
    return order[np.isfinite(costs[order])].astype(np.int64)
