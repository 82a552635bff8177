"""The ranking node's settings, without ROS: the policy its parameters name, the robots it serves,
and every other parameter checked with a one-line error naming it (ROS 1's ``~name`` parameters
and ``frontier-rl ros2 rank``'s options alike)."""

from __future__ import annotations

import math
from collections import Counter
from enum import StrEnum

from frontier_rl.checked_values import coerce
from frontier_rl.errors import ConfigError, short_repr


class StaleMapAnswer(StrEnum):
    """What the node answers on a map older than ``~max_map_age``."""

    STALE = "stale"
    """Rank the old map anyway, saying so in the status (the answer's stamp shows its age)."""
    EMPTY = "empty"
    """Answer with an empty list."""


def node_policy_spec(policy: str, model: str, weight: float) -> str:
    """The policy spec (:func:`~frontier_rl.policies.make_policy`) the node's parameters name:
    ``~policy`` (e.g. ``tour`` or ``learned:models/model7.zip``), else ``~model`` (a model file),
    else ``~weight``. Naming both a policy and a model is a :class:`ConfigError`."""
    policy, model = policy.strip(), model.strip()
    if policy and model:
        raise ConfigError(
            f"give ~policy or ~model, not both (got {short_repr(policy)} and {short_repr(model)}; a "
            "private parameter of an earlier run stays on the parameter server: rosparam delete it)"
        )
    if policy:
        return policy
    return f"learned:{model}" if model else f"fixed:{weight}"


MAX_NODE_ROBOTS = 64
"""Most robots one node serves: each has a worker process with its map and policy (0.2-0.5 GB)."""


def robot_namespaces(value: object) -> list[str]:
    """``~robots`` (a list or a comma string of namespaces) as names without slashes; a
    :class:`ConfigError` for anything else, an empty name beside others, a name given twice or
    more than :data:`MAX_NODE_ROBOTS` (each robot gets a worker and subscriptions of its own)."""
    if not isinstance(value, str | list) or not all(isinstance(r, str) for r in value):
        raise ConfigError(f"~robots must be namespaces such as tb3_0,tb3_1, got {short_repr(value)}")
    names = [r.strip().strip("/") for r in (value.split(",") if isinstance(value, str) else value)]
    if not names:
        raise ConfigError("~robots names no robot: give [''] (or leave it out) for one robot without a namespace")
    if len(names) > MAX_NODE_ROBOTS:
        many = f"{len(names):,} robots"
        raise ConfigError(f"~robots names {many}; a node serves {MAX_NODE_ROBOTS} at most (a process each)")
    if len(names) > 1 and "" in names:
        raise ConfigError(f"~robots names an empty namespace beside others: {short_repr(value)}")
    twice = sorted(n for n, count in Counter(names).items() if count > 1)
    if twice:
        raise ConfigError(f"~robots names {short_repr(twice[0])} twice: {short_repr(value)}")
    return names


MAX_CHECK_PERIOD_S = 3600.0
"""Longest ``~master_check_period`` (s): a master restart should be noticed within the hour."""


def count_parameter(name: str, value: object, least: int, most: int | None = None) -> int:
    """``~name`` as an integer of at least ``least`` (and at most ``most``); a :class:`ConfigError`
    naming it otherwise."""
    count: int = coerce(int, value, f"~{name}")
    if count < least or (most is not None and count > most):
        rule = f">= {least}" if most is None else f"{least} to {most:,}"
        raise ConfigError(f"~{name} must be an integer {rule}, got {short_repr(value)}")
    return count


def seconds_parameter(name: str, value: object, *, zero: bool, most: float = math.inf) -> float:
    """``~name`` as a finite number of seconds, at most ``most``, above zero (or zero too, when
    ``zero``); a :class:`ConfigError` naming it otherwise."""
    seconds: float = coerce(float, value, f"~{name}")
    if not (math.isfinite(seconds) and 0 <= seconds <= most) or (seconds == 0 and not zero):
        rule = (">= 0" if zero else "> 0") + (f" and <= {most:g}" if math.isfinite(most) else "")
        raise ConfigError(f"~{name} must be a number of seconds {rule}, got {short_repr(value)}")
    return seconds


def flag_parameter(name: str, value: object) -> bool:
    """``~name`` as true or false; a :class:`ConfigError` naming it otherwise ("false" as a string
    would be true)."""
    flag: bool = coerce(bool, value, f"~{name}")
    return flag


def check_node_policy(policy: object, spec: str) -> None:
    """Raise :class:`ConfigError` if ``policy`` (made from ``spec``) plans on the true world (an
    :class:`~frontier_rl.core.sim.episode.EpisodeAwarePolicy`, the oracle), which a node does not
    have, or chooses a goal cell instead of ranking frontiers (the point models 1 and 2), which
    would leave every answer empty."""
    from frontier_rl.core.sim.episode import EpisodeAwarePolicy  # the engine, once a policy is made
    from frontier_rl.policies.learned import ModelKind

    if isinstance(policy, EpisodeAwarePolicy):
        raise ConfigError(f"~policy {short_repr(spec)} plans on the true map, which the node does not have")
    if getattr(policy, "kind", None) == ModelKind.POINT:
        raise ConfigError(
            f"{short_repr(spec)} is a point model (it chooses a goal cell, as models 1 and 2 do), not a ranking "
            "of frontiers, which is what the node answers with"
        )
