"""The ranking node's settings, without ROS: the policy its parameters name, the robots it serves,
and every other parameter checked. A bad one is a :class:`~frontier_rl.errors.SettingError` naming
the parameter (``top_k``), which each front end names as its user writes it
(:func:`settings_named`: ROS 1's ``~top_k``, ``frontier-rl ros2 rank``'s ``--top-k``)."""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from enum import StrEnum

from frontier_rl.checked_values import not_a_boolean
from frontier_rl.errors import ConfigError, SettingError, short_repr


class StaleMapAnswer(StrEnum):
    """What the node answers on a map older than ``~max_map_age``."""

    STALE = "stale"
    """Rank the old map anyway, saying so in the status (the answer's stamp shows its age)."""
    EMPTY = "empty"
    """Answer with an empty list."""


@contextmanager
def settings_named(name: Callable[[str], str]) -> Iterator[None]:
    """A bad setting's error (a :class:`SettingError`) as a one-line :class:`ConfigError` naming the
    setting as ``name`` writes it (``lambda s: "~" + s`` for ROS 1's private parameters)."""
    try:
        yield
    except SettingError as error:
        raise ConfigError(f"{name(error.setting)} {error.problem}") from None


def stale_map_parameter(value: object) -> StaleMapAnswer:
    """``stale_map`` as a :class:`StaleMapAnswer`; a :class:`SettingError` naming it otherwise."""
    if not isinstance(value, str) or value not in tuple(StaleMapAnswer):
        raise SettingError("stale_map", f"must be stale or empty, got {short_repr(value)}")
    return StaleMapAnswer(value)


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
    """``robots`` (a list or a comma string of namespaces) as names without slashes; a
    :class:`SettingError` for anything else, an empty name beside others, a name given twice or
    more than :data:`MAX_NODE_ROBOTS` (each robot gets a worker and subscriptions of its own)."""
    if not isinstance(value, str | list) or not all(isinstance(r, str) for r in value):
        raise SettingError("robots", f"must be namespaces such as tb3_0,tb3_1, got {short_repr(value)}")
    names = [r.strip().strip("/") for r in (value.split(",") if isinstance(value, str) else value)]
    if not names:
        raise SettingError("robots", "names no robot: give [''] (or leave it out) for one robot without a namespace")
    if len(names) > MAX_NODE_ROBOTS:
        raise SettingError(
            "robots", f"names {len(names):,} robots; a node serves {MAX_NODE_ROBOTS} at most (a process each)"
        )
    if len(names) > 1 and "" in names:
        what = "only empty namespaces" if not any(names) else "an empty namespace beside others"
        raise SettingError("robots", f"names {what}: {short_repr(value)}")
    twice = sorted(n for n, count in Counter(names).items() if count > 1)
    if twice:
        raise SettingError("robots", f"names {short_repr(twice[0])} twice: {short_repr(value)}")
    return names


MAX_CHECK_PERIOD_S = 3600.0
"""Longest ``~master_check_period`` (s): a master restart should be noticed within the hour."""


def count_parameter(name: str, value: object, least: int, most: int | None = None) -> int:
    """Setting ``name`` as an integer of at least ``least`` (and at most ``most``); a
    :class:`SettingError` naming it otherwise."""
    if isinstance(value, bool) or not isinstance(value, int) or value < least or (most is not None and value > most):
        rule = f">= {least}" if most is None else f"{least} to {most:,}"
        raise SettingError(name, f"must be an integer {rule}, got {short_repr(value)}")
    return value


def seconds_parameter(name: str, value: object, *, zero: bool, most: float = math.inf) -> float:
    """Setting ``name`` as a finite number of seconds, at most ``most``, above zero (or zero too,
    when ``zero``); a :class:`SettingError` naming it otherwise."""
    seconds = float(value) if isinstance(value, int | float) and not isinstance(value, bool) else math.nan
    if not (math.isfinite(seconds) and 0 <= seconds <= most) or (seconds == 0 and not zero):
        rule = (">= 0" if zero else "> 0") + (f" and <= {most:g}" if math.isfinite(most) else "")
        raise SettingError(name, f"must be a number of seconds {rule}, got {short_repr(value)}")
    return seconds


def flag_parameter(name: str, value: object) -> bool:
    """Setting ``name`` as true or false; a :class:`SettingError` naming it otherwise ("false" as a
    string would be true)."""
    if not isinstance(value, bool):
        raise SettingError(name, not_a_boolean(value))
    return value


def check_node_policy(policy: object, spec: str) -> None:
    """Raise a :class:`SettingError` of ``policy`` if the policy (made from ``spec``) plans on the true world (an
    :class:`~frontier_rl.core.sim.episode.EpisodeAwarePolicy`, the oracle), which a node does not
    have, or chooses a goal cell instead of ranking frontiers (the point models 1 and 2), which
    would leave every answer empty."""
    from frontier_rl.core.sim.episode import EpisodeAwarePolicy  # the engine, once a policy is made
    from frontier_rl.registration import ModelKind

    if isinstance(policy, EpisodeAwarePolicy):
        raise SettingError("policy", f"{short_repr(spec)} plans on the true map, which the node does not have")
    if getattr(policy, "kind", None) == ModelKind.POINT:
        raise SettingError(
            "policy",
            f"{short_repr(spec)} is a point model (it chooses a goal cell, as models 1 and 2 do), not a ranking "
            "of frontiers, which is what the node answers with",
        )
