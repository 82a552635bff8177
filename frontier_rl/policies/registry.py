"""Policy names as used on the command line: ``nearest``, ``fixed:0.75``, ``explore-lite``, ``my.py:Greedy``, ..."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from frontier_rl.core.sim.episode import ExplorationPolicy
from frontier_rl.errors import ConfigError, short_repr
from frontier_rl.policies.baselines import (
    ExploreLite,
    FixedWeight,
    InformationGain,
    LargestFrontier,
    NearestFrontier,
    RandomFrontier,
)
from frontier_rl.policies.oracle import OracleTour
from frontier_rl.policies.spec import PolicyKind, PolicySpec, unknown_policy
from frontier_rl.policies.tour import FrontierTour
from frontier_rl.policies.user_policies import build_user_policy

_SIMPLE: dict[str, Callable[[], ExplorationPolicy]] = {
    "nearest": NearestFrontier,
    "largest": LargestFrontier,
    "explore-lite": ExploreLite,
    "info-gain": InformationGain,
    "random": RandomFrontier,
    "oracle": OracleTour,
    "tour": FrontierTour,
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
    if parsed.kind is not PolicyKind.BUILTIN:
        return build_user_policy(parsed)
    text = str(parsed)
    if parsed.name == "learned":
        if not parsed.argument:
            raise ConfigError(f"learned:PATH needs a model file, got {short_repr(text)}")
        from frontier_rl.policies.learned import LearnedPolicy  # torch only when asked for

        return LearnedPolicy(Path(parsed.argument), trust=trust_model)
    if parsed.name == "fixed":
        try:
            weight = float(parsed.argument)
        except ValueError:
            raise ConfigError(f"fixed:W needs a weight in [0, 1], got {short_repr(text)}") from None
        try:
            return FixedWeight(weight)
        except ConfigError as exc:
            raise ConfigError(f"{short_repr(text)}: {exc}") from None
    if parsed.name == "tour" and parsed.argument:
        if not (parsed.argument.isascii() and parsed.argument.isdigit()):
            raise ConfigError(f"tour:N needs a whole number of stops, got {short_repr(text)}")
        try:
            return FrontierTour(max_frontiers=int(parsed.argument), name=text)
        except ConfigError as exc:
            raise ConfigError(f"{short_repr(text)}: {exc}") from None
    if parsed.name in _SIMPLE:
        return _SIMPLE[parsed.name]()
    raise unknown_policy(text)
