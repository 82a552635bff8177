"""Policy names as used on the command line: ``nearest``, ``fixed:0.75``, ``explore-lite``, ``my.py:Greedy``, ..."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from frontier_rl.core.sim.episode import ExplorationPolicy
from frontier_rl.policies.baselines import (
    ExploreLite,
    FixedWeight,
    InformationGain,
    LargestFrontier,
    NearestFrontier,
    RandomFrontier,
)
from frontier_rl.policies.oracle import OracleTour
from frontier_rl.policies.spec import BuiltinPolicy, PolicySpec
from frontier_rl.policies.tour import FrontierTour
from frontier_rl.policies.user_policies import build_user_policy

_SIMPLE: dict[BuiltinPolicy, Callable[[], ExplorationPolicy]] = {
    BuiltinPolicy.NEAREST: NearestFrontier,
    BuiltinPolicy.LARGEST: LargestFrontier,
    BuiltinPolicy.EXPLORE_LITE: ExploreLite,
    BuiltinPolicy.INFO_GAIN: InformationGain,
    BuiltinPolicy.RANDOM: RandomFrontier,
    BuiltinPolicy.ORACLE: OracleTour,
}

__all__ = ["make_policy"]


def make_policy(spec: str | PolicySpec, trust_model: bool = False) -> ExplorationPolicy:
    """The policy named by ``spec``: a built-in one (:data:`POLICY_NAMES`: ``fixed:W`` with W in [0, 1],
    ``tour:N`` the tour over the N frontiers cheapest to reach (``tour`` is ``tour:10``), ``learned:PATH``
    a model file of ``frontier-rl train``; ``trust_model`` also admits SB3 zips from elsewhere, which
    unpickles them), or the user's own: ``FILE.py:CLASS``, ``MODULE:CLASS`` or a name an installed
    package registers (:mod:`frontier_rl.policies.user_policies`). Built-in names win.

    Raises:
        FrontierRLError: a bad spec, weight, model file or user policy, in one line naming it.
    """
    parsed = spec if isinstance(spec, PolicySpec) else PolicySpec.parse(spec)
    match parsed.builtin:
        case None:
            return build_user_policy(parsed)
        case BuiltinPolicy.LEARNED:
            from frontier_rl.policies.learned import LearnedPolicy  # torch only when asked for

            return LearnedPolicy(Path(parsed.argument), trust=trust_model)
        case BuiltinPolicy.FIXED:
            assert parsed.weight is not None
            return FixedWeight(parsed.weight)
        case BuiltinPolicy.TOUR:
            assert parsed.stops is not None
            return FrontierTour(max_frontiers=parsed.stops, name=str(parsed))
        case builtin:
            return _SIMPLE[builtin]()
