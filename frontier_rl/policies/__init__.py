"""Exploration policies behind one interface: the classic baselines, the oracle and tour, learned
models (``learned:PATH``), and the user's own (``FILE.py:CLASS``, ``MODULE:CLASS``, installed packages)."""

from frontier_rl.policies.baselines import (
    ExploreLite,
    FixedWeight,
    InformationGain,
    LargestFrontier,
    NearestFrontier,
    RandomFrontier,
)
from frontier_rl.policies.oracle import OracleTour
from frontier_rl.policies.registry import make_policy
from frontier_rl.policies.spec import POLICY_NAMES, PolicyKind, PolicySpec
from frontier_rl.policies.tour import FrontierTour
from frontier_rl.policies.user_policies import ENTRY_POINT_GROUP, installed_policies

__all__ = [
    "ENTRY_POINT_GROUP",
    "POLICY_NAMES",
    "ExploreLite",
    "FixedWeight",
    "FrontierTour",
    "InformationGain",
    "LargestFrontier",
    "NearestFrontier",
    "OracleTour",
    "PolicyKind",
    "PolicySpec",
    "RandomFrontier",
    "installed_policies",
    "make_policy",
]
