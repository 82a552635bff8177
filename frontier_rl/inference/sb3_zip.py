"""A Stable-Baselines3 zip without this project's metadata, as an actor: SB3's own (unpickling)
load, only for a file the caller trusts (``--trust-model``), and the most likely action of its
policy without SB3's per-call overhead.

SB3's ``predict`` sets the training mode of every module, deep-copies a dict observation, checks
whether it is batched and builds a ``torch.distributions.Categorical`` (validating its arguments)
only to take its mode. :func:`predict_action` feeds the observation to the same network and takes
the same argmax (tested against ``predict``). This is the one module of :mod:`frontier_rl.inference`
that imports Gymnasium and SB3, and only a trusted file reaches it.
"""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
import torch
from stable_baselines3 import A2C, PPO
from stable_baselines3.common.distributions import CategoricalDistribution
from stable_baselines3.common.policies import ActorCriticPolicy
from stable_baselines3.common.preprocessing import is_image_space, preprocess_obs

from frontier_rl.errors import ConfigError, model_file_label, short_repr
from frontier_rl.inference.bounded_zip import first_line
from frontier_rl.inference.interface import Observation, ObservationShape
from frontier_rl.inference.model_file import open_model
from frontier_rl.inference.tensors import observation_tensor


def network_input(policy: ActorCriticPolicy, observation: Any) -> torch.Tensor | dict[str, torch.Tensor]:
    """``observation`` as the features extractor takes it: SB3's ``obs_to_tensor`` and
    ``preprocess_obs`` (a batch of one; images over 255 when the policy normalises them, the rest
    as float32), the arithmetic done in NumPy, the same float32 division. Spaces other than boxes
    go SB3's way."""
    space = policy.observation_space
    spaces = space.spaces if isinstance(space, gym.spaces.Dict) else {"": space}
    if not all(isinstance(sub, gym.spaces.Box) for sub in spaces.values()):
        return preprocess_obs(policy.obs_to_tensor(observation)[0], space, normalize_images=policy.normalize_images)
    values = observation if isinstance(space, gym.spaces.Dict) else {"": observation}
    tensors = {
        key: observation_tensor(values[key], sub.shape or (), policy.normalize_images and is_image_space(sub)).to(
            policy.device
        )
        for key, sub in spaces.items()
    }
    return tensors if isinstance(space, gym.spaces.Dict) else tensors[""]


def predict_action(policy: ActorCriticPolicy, observation: Any) -> int:
    """The policy's most likely action for one observation (``policy`` in evaluation mode): SB3's
    deterministic ``predict``."""
    with torch.inference_mode():
        if not isinstance(policy.action_dist, CategoricalDistribution):  # no model of this project
            tensors, _ = policy.obs_to_tensor(observation)
            return int(policy.get_distribution(tensors).mode().item())
        # the actor's features, as get_distribution takes them (one extractor, one tensor)
        features = policy.pi_features_extractor(network_input(policy, observation))
        logits = policy.action_net(policy.mlp_extractor.forward_actor(features))
        normalized = logits - logits.logsumexp(dim=-1, keepdim=True)  # as torch's Categorical keeps them
        return int(torch.argmax(torch.softmax(normalized, dim=-1), dim=1).item())


def load_trusted_policy(path: Path) -> ActorCriticPolicy:
    """SB3's own (unpickling) load of the zip at ``path``, after the zip checks; tried as A2C, then
    PPO. The policy is in evaluation mode on the CPU."""
    with open_model(path):  # the size checks, before SB3 reads a byte
        pass
    last: Exception | None = None
    for algo in (A2C, PPO):
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                policy = algo.load(str(path), device="cpu").policy
        except Exception as exc:
            last = exc
            continue
        if isinstance(policy, ActorCriticPolicy):
            policy.set_training_mode(False)
            return policy
    reason = f" ({first_line(last)})" if last is not None else ""
    raise ConfigError(f"{model_file_label(path)} could not be loaded as an SB3 A2C or PPO model{reason}")


def _dims(space: gym.Space[Any] | None) -> tuple[int, ...]:
    return tuple(int(n) for n in getattr(space, "shape", None) or ())


def observation_shape(policy: ActorCriticPolicy, where: str) -> ObservationShape:
    """What ``policy`` reads, if it is a map image or a map with a frontier table and mask, with a
    discrete action; otherwise a :class:`ConfigError` naming the file."""
    actions = getattr(policy.action_space, "n", 0)
    if not isinstance(actions, int | np.integer) or actions < 1:
        raise ConfigError(f"{where} does not have a discrete action space")
    space = policy.observation_space
    entries = space.spaces if isinstance(space, gym.spaces.Dict) else {}
    image = _dims(entries.get("map") if isinstance(space, gym.spaces.Dict) else space)
    if len(image) != 3:
        raise ConfigError(f"{where} expects observations of shape {short_repr(image or None)}, not a map")
    if not isinstance(space, gym.spaces.Dict):
        return ObservationShape((image[0], image[1], image[2]), int(actions))
    rows, table = _dims(entries.get("mask")), _dims(entries.get("frontiers"))
    if len(rows) != 1 or len(table) != 1 or rows[0] < 1:
        raise ConfigError(f"{where} has a frontier table of {short_repr(table)} values and {short_repr(rows)} rows")
    return ObservationShape((image[0], image[1], image[2]), int(actions), rows[0], table[0])


class SB3Actor:
    """A trusted SB3 policy behind :class:`~frontier_rl.inference.interface.Actor`."""

    def __init__(self, policy: ActorCriticPolicy, where: str) -> None:
        self.policy = policy
        self._shape = observation_shape(policy, where)

    @property
    def shape(self) -> ObservationShape:
        """What the policy reads and answers."""
        return self._shape

    def act(self, observation: Observation) -> int:
        """The policy's most likely action (:func:`predict_action`)."""
        return predict_action(self.policy, observation)


def load_sb3_actor(path: Path) -> SB3Actor:
    """The trusted SB3 zip at ``path`` as an actor (:func:`load_trusted_policy`)."""
    return SB3Actor(load_trusted_policy(path), model_file_label(path))
