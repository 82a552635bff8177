"""Policy names as used on the command line: ``nearest``, ``fixed:0.75``, ``explore-lite``, ..."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from frontier_rl.core.sim.episode import ExplorationPolicy
from frontier_rl.errors import ConfigError, UnknownNameError, short_repr
from frontier_rl.policies.baselines import (
    ExploreLite,
    FixedWeight,
    InformationGain,
    LargestFrontier,
    NearestFrontier,
    RandomFrontier,
)
from frontier_rl.policies.oracle import OracleTour
from frontier_rl.policies.tour import FrontierTour

_SIMPLE: dict[str, Callable[[], ExplorationPolicy]] = {
    "nearest": NearestFrontier,
    "largest": LargestFrontier,
    "explore-lite": ExploreLite,
    "info-gain": InformationGain,
    "random": RandomFrontier,
    "oracle": OracleTour,
    "tour": FrontierTour,
}

POLICY_NAMES: tuple[str, ...] = (*_SIMPLE, "fixed:W", "tour:N", "learned:PATH.zip")


def make_policy(spec: str, trust_model: bool = False) -> ExplorationPolicy:
    """The policy named by ``spec`` (one of :data:`POLICY_NAMES`, ``fixed:W`` with W in [0, 1],
    ``tour:N`` the tour over the N frontiers cheapest to reach (``tour`` is ``tour:10``),
    ``learned:PATH`` a model file of ``frontier-rl train``; ``trust_model`` also admits SB3 zips from
    elsewhere, which unpickles them)."""
    name, _, arg = spec.strip().partition(":")
    if name == "learned":
        if not arg:
            raise ConfigError(f"learned:PATH needs a model file, got {short_repr(spec)}")
        from frontier_rl.policies.learned import LearnedPolicy  # torch only when asked for

        return LearnedPolicy(Path(arg), trust=trust_model)
    if name == "fixed":
        try:
            weight = float(arg)
        except ValueError:
            raise ConfigError(f"fixed:W needs a weight in [0, 1], got {short_repr(spec)}") from None
        try:
            return FixedWeight(weight)
        except ConfigError as exc:
            raise ConfigError(f"{short_repr(spec)}: {exc}") from None
    if name == "tour" and ":" in spec:
        if not (arg.isascii() and arg.isdigit()):
            raise ConfigError(f"tour:N needs a whole number of stops, got {short_repr(spec)}")
        try:
            return FrontierTour(max_frontiers=int(arg), name=spec.strip())
        except ConfigError as exc:
            raise ConfigError(f"{short_repr(spec)}: {exc}") from None
    if name in _SIMPLE and ":" not in spec:
        return _SIMPLE[name]()
    raise UnknownNameError(f"unknown policy {short_repr(spec)}; choose one of {', '.join(POLICY_NAMES)}")
