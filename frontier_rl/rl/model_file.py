"""Model files: Stable-Baselines3 zips with a ``frontier_rl.json`` entry saying what they are.

Loading never unpickles: the network is rebuilt from the JSON entry and only the weights are read
(``torch.load(weights_only=True)``). SB3's own ``load`` unpickles parts of the zip, which can run
code from the file; it is used only when the caller says the file is trusted.
"""

from __future__ import annotations

import json
import zipfile
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import gymnasium as gym
import torch
from stable_baselines3 import A2C, PPO
from stable_baselines3.common.base_class import BaseAlgorithm
from stable_baselines3.common.policies import ActorCriticCnnPolicy, ActorCriticPolicy
from stable_baselines3.common.save_util import load_from_zip_file

import frontier_rl
from frontier_rl.errors import ConfigError
from frontier_rl.rl.networks import FrontierScorer, GridCNN, PointerPolicy

METADATA_ENTRY = "frontier_rl.json"
FORMAT_VERSION = 1
ALGORITHMS: dict[str, type[BaseAlgorithm]] = {"a2c": A2C, "ppo": PPO}


@dataclass(frozen=True)
class ModelInfo:
    """What a model file holds.

    Attributes:
        model: thesis model number 1-5.
        env_id: the Gymnasium id it was trained on.
        observation_size: map image edge (pixels).
        algo: "a2c" or "ppo".
        features_dim: CNN feature size.
        timesteps: decisions it was trained for.
        format: version of this metadata.
    """

    model: int
    env_id: str
    observation_size: int
    algo: str
    features_dim: int
    timesteps: int
    format: int = FORMAT_VERSION


def policy_setup(model: int, features_dim: int) -> tuple[type[ActorCriticPolicy], dict[str, Any]]:
    """The policy class and keyword arguments of thesis model ``model``."""
    if model == 5:
        return PointerPolicy, {
            "features_extractor_class": FrontierScorer,
            "features_extractor_kwargs": {"context_dim": features_dim},
            "net_arch": {"pi": [], "vf": [64]},
        }
    return ActorCriticCnnPolicy, {
        "features_extractor_class": GridCNN,
        "features_extractor_kwargs": {"features_dim": features_dim},
        "net_arch": {"pi": [64], "vf": [64]},
    }


def write_metadata(path: Path, info: ModelInfo) -> None:
    """Add (or replace) the metadata entry of the SB3 zip at ``path``."""
    with zipfile.ZipFile(path) as archive:
        entries = {name: archive.read(name) for name in archive.namelist() if name != METADATA_ENTRY}
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, data in entries.items():
            archive.writestr(name, data)
        archive.writestr(METADATA_ENTRY, json.dumps(asdict(info), indent=2))


def read_metadata(path: str | Path) -> ModelInfo | None:
    """The metadata of the model file at ``path``; None for an SB3 zip without it. Raises
    :class:`ConfigError` for a missing or unreadable file."""
    path = Path(path)
    if not path.is_file():
        raise ConfigError(f"model file {str(path)!r} not found")
    try:
        with zipfile.ZipFile(path) as archive:
            if METADATA_ENTRY not in archive.namelist():
                return None
            values = json.loads(archive.read(METADATA_ENTRY))
        return ModelInfo(**values)
    except (zipfile.BadZipFile, json.JSONDecodeError, TypeError, OSError) as exc:
        raise ConfigError(f"model file {str(path)!r} is corrupt or not a frontier_rl model: {exc}") from None


def env_spaces(env_id: str) -> tuple[gym.Space[Any], gym.Space[Any]]:
    """Observation and action spaces of a registered id (the env is built, not reset)."""
    frontier_rl.register_envs()
    env = gym.make(env_id)
    try:
        return env.observation_space, env.action_space
    finally:
        env.close()


def load_policy(path: str | Path, trust: bool = False) -> tuple[ActorCriticPolicy, ModelInfo | None]:
    """The policy network of a model file, in evaluation mode on the CPU.

    Args:
        path: a zip written by ``frontier-rl train``.
        trust: allow SB3's full (unpickling) load for zips without frontier_rl metadata.
    """
    info = read_metadata(path)
    if info is None:
        if not trust:
            raise ConfigError(
                f"model file {str(path)!r} was not written by 'frontier-rl train'; loading it would unpickle "
                "(and could run) code from the file. Pass --trust-model if you trust it"
            )
        return _load_trusted(Path(path)), None
    if info.format != FORMAT_VERSION:
        raise ConfigError(f"model file {str(path)!r} has metadata format {info.format}, expected {FORMAT_VERSION}")
    policy_cls, kwargs = policy_setup(info.model, info.features_dim)
    obs_space, act_space = env_spaces(info.env_id)
    policy = policy_cls(obs_space, act_space, lambda _: 0.0, **kwargs)
    try:
        _, params, _ = load_from_zip_file(str(path), device="cpu", load_data=False)
        state: dict[str, Any] = params["policy"]  # type: ignore[assignment]
    except Exception as exc:
        raise ConfigError(f"model file {str(path)!r} is corrupt: {exc}") from None
    try:
        policy.load_state_dict(state)
    except RuntimeError as exc:
        first = str(exc).strip().splitlines()[-1].strip()
        raise ConfigError(f"model file {str(path)!r} does not fit {info.env_id} ({first})") from None
    policy.set_training_mode(False)
    return policy, info


def _load_trusted(path: Path) -> ActorCriticPolicy:
    last: Exception | None = None
    for algo in ALGORITHMS.values():
        try:
            policy = algo.load(str(path), device="cpu").policy
        except Exception as exc:
            last = exc
            continue
        if isinstance(policy, ActorCriticPolicy):
            policy.set_training_mode(False)
            return policy
    raise ConfigError(f"model file {str(path)!r} could not be loaded as an SB3 A2C or PPO model: {last}")


def predict_action(policy: ActorCriticPolicy, observation: Any) -> int:
    """The policy's most likely action for one observation."""
    with torch.no_grad():
        action, _ = policy.predict(observation, deterministic=True)
    return int(action)
