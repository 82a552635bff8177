"""Exploration policies behind one interface: the classic baselines, the oracle and tour, learned
models (``learned:PATH``), and the user's own (``FILE.py:CLASS``, ``MODULE:CLASS``, installed packages).

The names below load their module on first use: importing ``frontier_rl.policies.spec`` (how a policy
is named) loads no engine."""

from __future__ import annotations

from typing import TYPE_CHECKING

from frontier_rl.lazy_exports import lazy_exports

_NAMES = {
    **dict.fromkeys(
        ("ExploreLite", "FixedWeight", "InformationGain", "LargestFrontier", "NearestFrontier", "RandomFrontier"),
        "frontier_rl.policies.baselines",
    ),
    "OracleTour": "frontier_rl.policies.oracle",
    "make_policy": "frontier_rl.policies.registry",
    **dict.fromkeys(
        ("POLICY_NAMES", "BuiltinPolicy", "PolicyKind", "PolicySpec", "ENTRY_POINT_GROUP"), "frontier_rl.policies.spec"
    ),
    "FrontierTour": "frontier_rl.policies.tour",
    "installed_policies": "frontier_rl.policies.user_policies",
}
"""Each public name and the module that defines it."""

__all__ = [
    "ENTRY_POINT_GROUP",
    "POLICY_NAMES",
    "BuiltinPolicy",
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
__getattr__, __dir__ = lazy_exports(__name__, _NAMES)

if TYPE_CHECKING:
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
    from frontier_rl.policies.spec import ENTRY_POINT_GROUP, POLICY_NAMES, BuiltinPolicy, PolicyKind, PolicySpec
    from frontier_rl.policies.tour import FrontierTour
    from frontier_rl.policies.user_policies import installed_policies
