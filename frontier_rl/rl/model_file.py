"""Model files as training writes and resumes them: Stable-Baselines3 zips with a
``frontier_rl.json`` entry saying what they are (:class:`~frontier_rl.inference.model_file.ModelInfo`).

Reading a model file is :mod:`frontier_rl.inference.model_file`'s job, with every check an untrusted
file needs; this module writes them (replaced whole, never half written, without the privileged
critic's head) and rebuilds a file's network as an SB3 policy, for ``train --init``.
"""

from __future__ import annotations

import io
import json
import zipfile
from dataclasses import asdict
from pathlib import Path
from typing import Any

import gymnasium as gym
import torch
from stable_baselines3 import A2C, PPO
from stable_baselines3.common.base_class import BaseAlgorithm
from stable_baselines3.common.policies import ActorCriticCnnPolicy, ActorCriticPolicy

import frontier_rl.envs
from frontier_rl.atomic_write import write_bytes_atomic
from frontier_rl.errors import ConfigError, TrainingDivergedError, model_file_label, short_repr
from frontier_rl.inference.bounded_zip import first_line
from frontier_rl.inference.model_file import (
    METADATA_ENTRY,
    WEIGHTS_ENTRY,
    ModelInfo,
    check_fit,
    open_model,
    read_model,
)
from frontier_rl.inference.sb3_zip import load_trusted_policy
from frontier_rl.registration import ENV_IDS, FRONTIER_CHOICE_MODELS, MODELS, Algorithm, ModelKind
from frontier_rl.rl.networks import PRIVILEGED_HEAD, FrontierPooling, FrontierScorer, GridCNN, PointerPolicy

SB3_ALGORITHMS: dict[Algorithm, type[BaseAlgorithm]] = {Algorithm.A2C: A2C, Algorithm.PPO: PPO, Algorithm.DAGGER: A2C}
"""SB3 class of each :class:`~frontier_rl.registration.Algorithm`; a DAgger
policy is kept in an A2C container (no optimizer of its own)."""


def policy_setup(model: int, features_dim: int) -> tuple[type[ActorCriticPolicy], dict[str, Any]]:
    """The policy class and keyword arguments of model ``model``."""
    if model in FRONTIER_CHOICE_MODELS:
        return PointerPolicy, {
            "features_extractor_class": FrontierScorer,
            "features_extractor_kwargs": {"context_dim": features_dim},
            "net_arch": {"pi": [], "vf": [64]},
        }
    if MODELS[model].kind is ModelKind.WEIGHT_TABLE:
        return ActorCriticPolicy, {
            "features_extractor_class": FrontierPooling,
            "features_extractor_kwargs": {"context_dim": features_dim},
            "net_arch": {"pi": [64], "vf": [64]},
        }
    return ActorCriticCnnPolicy, {
        "features_extractor_class": GridCNN,
        "features_extractor_kwargs": {"features_dim": features_dim},
        "net_arch": {"pi": [64], "vf": [64]},
    }


def write_metadata(path: Path, info: ModelInfo) -> None:
    """Add (or replace) the metadata entry of the SB3 zip at ``path`` (the file is replaced whole,
    never left half written)."""
    with zipfile.ZipFile(path) as archive:
        entries = {name: archive.read(name) for name in archive.namelist() if name != METADATA_ENTRY}
    write_bytes_atomic(path, _zip_bytes(entries, info))


def check_finite_weights(model: BaseAlgorithm) -> None:
    """Raise :class:`~frontier_rl.errors.TrainingDivergedError` if a policy weight is NaN or inf."""
    if not all(bool(torch.isfinite(p).all()) for p in model.policy.parameters()):
        raise TrainingDivergedError(
            f"training diverged by decision {model.num_timesteps:,}: the policy's weights are no longer "
            "finite (NaN or inf); a smaller --learning-rate may help"
        )


def save_model(model: BaseAlgorithm, path: Path, info: ModelInfo | None = None) -> None:
    """Save ``model`` as an SB3 zip at ``path``, with the metadata ``info`` when given; the file is
    replaced whole or not at all (a full disk leaves the previous one). A policy whose weights
    are not finite is not saved (:func:`check_finite_weights`)."""
    check_finite_weights(model)
    buffer = io.BytesIO()
    model.save(buffer)
    if info is None:
        write_bytes_atomic(path, buffer.getvalue())
        return
    with zipfile.ZipFile(buffer) as archive:
        entries = {name: archive.read(name) for name in archive.namelist() if name != METADATA_ENTRY}
    write_bytes_atomic(path, _zip_bytes(entries, info))


def _zip_bytes(entries: dict[str, bytes], info: ModelInfo) -> bytes:
    """A deflated zip of ``entries`` plus the metadata entry of ``info``: a model file, whose
    weights leave out a privileged value head (training only; :class:`PointerPolicy`)."""
    if WEIGHTS_ENTRY in entries:
        entries = {**entries, WEIGHTS_ENTRY: _without_privileged_head(entries[WEIGHTS_ENTRY])}
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, data in entries.items():
            archive.writestr(name, data)
        archive.writestr(METADATA_ENTRY, json.dumps(asdict(info), indent=2))
    return buffer.getvalue()


def _without_privileged_head(weights: bytes) -> bytes:
    """``policy.pth`` as SB3 just wrote it, without the weights of the privileged value head."""
    state = torch.load(io.BytesIO(weights), map_location="cpu", weights_only=True)
    kept = {key: value for key, value in state.items() if not key.startswith(f"{PRIVILEGED_HEAD}.")}
    if len(kept) == len(state):
        return weights
    buffer = io.BytesIO()
    torch.save(kept, buffer)
    return buffer.getvalue()


def env_spaces(env_id: str) -> tuple[gym.Space[Any], gym.Space[Any]]:
    """Observation and action spaces of one of the project's registered ids (the env is built, not
    reset); any other id is refused, so no module it names is imported."""
    if env_id not in ENV_IDS:
        raise ConfigError(f"{short_repr(env_id)} is not a frontier_rl environment id such as {ENV_IDS[-1]!r}")
    frontier_rl.envs.register_envs()
    env = gym.make(env_id)
    try:
        return env.observation_space, env.action_space
    finally:
        env.close()


def load_policy(path: str | Path, trust: bool = False) -> tuple[ActorCriticPolicy, ModelInfo | None]:
    """The policy network of a model file as an SB3 policy, in evaluation mode on the CPU (to train
    on from it; running a model needs only :func:`frontier_rl.inference.actor.load_actor`).

    Args:
        path: a zip written by ``frontier-rl train``.
        trust: allow SB3's full (unpickling) load for zips without frontier_rl metadata.
    """
    path = Path(path)
    where = model_file_label(path)
    info, state = read_model(path, trust)
    if info is None:
        return load_trusted_policy(path), None
    policy_cls, kwargs = policy_setup(info.model, info.features_dim)
    obs_space, act_space = env_spaces(info.env_id)
    policy = policy_cls(obs_space, act_space, lambda _: 0.0, **kwargs)
    check_fit(policy.state_dict(), state, info, where)
    try:
        policy.load_state_dict(state)
    except Exception as exc:
        raise ConfigError(f"{where} does not fit {info.env_id} ({first_line(exc)})") from None
    policy.set_training_mode(False)
    return policy, info


def check_model_zip(path: Path) -> None:
    """Refuse the zip at ``path`` (a model file or a training checkpoint) before SB3 reads it, if
    what its directory declares is too big or too compressed (:mod:`frontier_rl.inference.bounded_zip`)."""
    with open_model(path):
        pass
