"""What an experiment's rows depend on (:class:`~frontier_rl.evaluation.results.identity.ExperimentIdentity`):
the seed, the settings, and each method and world named with a hash of the files it reads, so that
rows of two experiments are mixed only where they would be the same."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from frontier_rl.config_files import to_dict
from frontier_rl.errors import ConfigError, model_file_label, short_repr
from frontier_rl.evaluation.results.identity import ExperimentIdentity, TeamIdentity
from frontier_rl.file_digest import file_sha256
from frontier_rl.policies.spec import BuiltinPolicy, PolicySpec
from frontier_rl.policies.user_policies import user_policy_fingerprint
from frontier_rl.swarm import TeamMethod
from frontier_rl.world_spec import world_fingerprint

if TYPE_CHECKING:
    from frontier_rl.evaluation.running.experiment import ExperimentConfig


def method_fingerprint(method: str) -> str:
    """What a method's results depend on besides its name: a model file's or a policy file's content
    hash, a policy module's source hash, an installed policy's package and version."""
    return _policy_fingerprint(method, TeamMethod.parse(method).policy)


def _policy_fingerprint(method: str, spec: PolicySpec) -> str:
    """:func:`method_fingerprint` of ``method``, whose policy is ``spec``."""
    if spec.is_user_code:
        extra = user_policy_fingerprint(spec)
        return f"{method}#{extra}" if extra else method
    if spec.builtin is not BuiltinPolicy.LEARNED:
        return method
    path = Path(spec.argument)
    if not path.is_file():
        raise ConfigError(f"{model_file_label(spec.argument)} of method {short_repr(method)} does not exist")
    return f"{method}#sha256:{file_sha256(path)}"


def identity(config: ExperimentConfig) -> ExperimentIdentity:
    """Everything a row's values depend on: rows of two experiments may be mixed only where these
    agree (methods may be added and episodes extended; worlds, seed and settings not)."""
    team = None
    if config.comm_range is not None or config.failures:  # only then, so older results folders still match
        team = TeamIdentity(config.comm_range, tuple(str(f) for f in config.failures))
    return ExperimentIdentity(
        seed=config.seed,
        worlds=tuple(world_fingerprint(w, config.resolution) for w in config.worlds),
        resolution=config.resolution,
        sim=to_dict(config.sim),
        methods={m: _policy_fingerprint(m, team.policy) for m, team in config.parsed_methods.items()},
        team=team,
    )
