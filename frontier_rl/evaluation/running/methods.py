"""The methods of an experiment: their list (the baseline first, the oracle last, every team size and
strategy) and the policy each episode of one of them runs."""

from __future__ import annotations

from collections.abc import Sequence
from functools import lru_cache
from typing import TYPE_CHECKING

from frontier_rl.core.sim.episode import ExplorationPolicy
from frontier_rl.errors import ConfigError
from frontier_rl.policies import BuiltinPolicy, PolicySpec, make_policy
from frontier_rl.swarm import Failure, Strategy, TeamConfig, TeamMethod

if TYPE_CHECKING:
    from frontier_rl.evaluation.running.experiment import ExperimentConfig

ORACLE: str = BuiltinPolicy.ORACLE.value
"""The full-knowledge reference every report measures methods against."""


def method_list(methods: Sequence[str], baseline: str, oracle: bool) -> tuple[str, ...]:
    """The methods of an experiment, each once: ``baseline`` first, then ``methods``, and the
    :data:`ORACLE` last when ``oracle``."""
    return tuple(dict.fromkeys([baseline, *methods, *([ORACLE] if oracle else [])]))


def team_methods(methods: list[str], robots: list[int], strategies: list[Strategy]) -> list[str]:
    """Every method run by every team size (a size of 1 is the method alone) and, above 1, every
    strategy; methods already written as POLICY@N[:STRATEGY] are kept as they are.

    Raises:
        ConfigError: a team size out of range, or teams and no strategy (``--strategy ''``).
    """
    if not strategies and any(n > 1 for n in robots):
        raise ConfigError("--strategy names no strategy for the teams of --robots")
    out: list[str] = []
    for method in methods:
        parsed = TeamMethod.parse(method)
        if parsed.robots is not None:
            out.append(method)
            continue
        for n in robots:
            if n == 1:
                out.append(method)
            else:
                out += [str(TeamMethod(parsed.policy, n, s)) for s in strategies]
    for n in robots:
        TeamConfig(robots=n)  # a size out of range fails here, named
    return list(dict.fromkeys(out))


def team_config(method: TeamMethod, comm_range: float | None, failures: tuple[Failure, ...]) -> TeamConfig | None:
    """The team of a parsed method under an experiment's range and failures; None for one robot."""
    if method.robots is None:
        return None
    return TeamConfig(method.robots, method.strategy, comm_range, failures)


def check_methods(config: ExperimentConfig) -> None:
    """Build every method once, so a bad name or model file fails before any episode runs."""
    for method in config.parsed_methods.values():
        episode_policy(method.policy, config.trust_model)


def episode_policy(method: str | PolicySpec, trust_model: bool) -> ExplorationPolicy:
    """The policy of ``method`` for an episode: a built-in one is built once per process and version of
    its model file (loading a model takes longer than an episode); a user policy afresh for every
    episode (its module is loaded once), so that no state it keeps carries over from another episode."""
    spec = method if isinstance(method, PolicySpec) else PolicySpec.parse(method)
    if spec.is_user_code:
        return make_policy(spec)
    path = spec.file
    stat = path.stat() if path is not None and path.is_file() else None
    return _policy_version(spec, trust_model, None if stat is None else (stat.st_size, stat.st_mtime_ns))


@lru_cache(maxsize=32)
def _policy_version(spec: PolicySpec, trust_model: bool, version: tuple[int, int] | None) -> ExplorationPolicy:
    if spec.builtin is BuiltinPolicy.LEARNED:
        import torch

        torch.set_num_threads(1)  # one episode per core; a tiny network gains nothing from threads
    return make_policy(spec, trust_model=trust_model)
