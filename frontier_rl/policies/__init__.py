"""Exploration policies: classic baselines (and, later, learned ones) behind one interface."""

from frontier_rl.policies.baselines import (
    ExploreLite,
    FixedWeight,
    InformationGain,
    LargestFrontier,
    NearestFrontier,
    RandomFrontier,
)
from frontier_rl.policies.oracle import OracleTour
from frontier_rl.policies.registry import POLICY_NAMES, make_policy
from frontier_rl.policies.tour import FrontierTour

__all__ = [
    "POLICY_NAMES",
    "ExploreLite",
    "FixedWeight",
    "FrontierTour",
    "InformationGain",
    "LargestFrontier",
    "NearestFrontier",
    "OracleTour",
    "RandomFrontier",
    "make_policy",
]
