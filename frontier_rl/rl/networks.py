"""The models' networks as Stable-Baselines3 builds them for training: the plain-torch networks of
:mod:`frontier_rl.inference.networks` made from the env's observation space, and the pointer
policy of the frontier-choice models with its privileged critic."""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import torch
from stable_baselines3.common.policies import ActorCriticPolicy
from torch import nn

from frontier_rl.inference.networks import (
    GRID_CNN_FEATURES,
    FirstColumns,
    FrontierPool,
    FrontierScores,
    GridFeatures,
    grid_cnn,
)


def _shape(space: gym.Space[Any]) -> tuple[int, ...]:
    assert space.shape is not None
    return tuple(int(n) for n in space.shape)


def _table(observation_space: gym.spaces.Dict) -> tuple[int, int, int]:
    """The map image's channels, the table's rows and its columns."""
    top_k = _shape(observation_space["mask"])[0]
    return _shape(observation_space["map"])[0], top_k, _shape(observation_space["frontiers"])[0] // top_k


class GridCNN(GridFeatures):
    """SB3's features extractor of models 1-4 (:class:`~frontier_rl.inference.networks.GridFeatures`):
    SB3 has already scaled the image to [0, 1] (``normalize_images``) when it reaches ``forward``."""

    def __init__(self, observation_space: gym.spaces.Box, features_dim: int = 128) -> None:
        super().__init__(_shape(observation_space)[0], features_dim)


class FrontierScorer(FrontierScores):
    """SB3's features extractor of models 5 and 7 (:class:`~frontier_rl.inference.networks.FrontierScores`)."""

    def __init__(self, observation_space: gym.spaces.Dict, context_dim: int = 128) -> None:
        super().__init__(*_table(observation_space), context_dim)


class FrontierPooling(FrontierPool):
    """SB3's features extractor of model 6 (:class:`~frontier_rl.inference.networks.FrontierPool`)."""

    def __init__(self, observation_space: gym.spaces.Dict, context_dim: int = 128) -> None:
        super().__init__(*_table(observation_space), context_dim)


PRIVILEGED_HEAD = "privileged_value"
"""The module name (and weight-name prefix) of :class:`PointerPolicy`'s privileged value head."""


class PrivilegedValue(nn.Module):
    """The privileged value head: an MLP over what the observation holds of the ``privileged``
    features and the ``privileged_map`` image (a uint8 image, read as [0, 1], through a CNN of its
    own). Its last layer starts at zero, so the critic starts as the plain one."""

    def __init__(self, spaces: dict[str, gym.Space[Any]]) -> None:
        super().__init__()
        self.scalars = "privileged" in spaces
        n_in = int(spaces["privileged"].shape[0]) if self.scalars else 0  # type: ignore[index]
        self.cnn: nn.Module | None = None
        if "privileged_map" in spaces:
            self.cnn = grid_cnn(int(spaces["privileged_map"].shape[0]))  # type: ignore[index]
            n_in += GRID_CNN_FEATURES
        last = nn.Linear(64, 1)
        nn.init.zeros_(last.weight)
        nn.init.zeros_(last.bias)
        self.mlp = nn.Sequential(nn.Linear(n_in, 64), nn.ReLU(), last)

    def forward(self, obs: dict[str, torch.Tensor]) -> torch.Tensor:
        """The head's addition to the value, (batch, 1)."""
        parts = [obs["privileged"]] if self.scalars else []
        if self.cnn is not None:
            image = obs["privileged_map"].float() / 255.0  # the raw observation: SB3 scales only its extractor's input
            parts.append(self.cnn(image))
        return self.mlp(torch.cat(parts, dim=1))  # type: ignore[no-any-return]


class PointerPolicy(ActorCriticPolicy):
    """Actor-critic whose action logits are :class:`FrontierScorer`'s per-frontier scores; the
    critic reads all the features (the scores and the map context). Use with ``net_arch=dict(pi=[], vf=[64])``.

    When the observation holds ``privileged`` (what only the simulator knows, in training), a small
    head on it (:class:`PrivilegedValue`, with ``privileged_map`` too where the observation holds
    it) adds to the value: a privileged critic, as ARiADNE's successors train with. The
    actor never reads it, and a model file leaves the head out (:data:`PRIVILEGED_HEAD`), so the
    deployed policy needs no privileged input; its value is then the critic's without the head.
    """

    def _build(self, lr_schedule: Any) -> None:
        super()._build(lr_schedule)
        top_k = int(self.action_space.n)  # type: ignore[attr-defined]
        self.action_net = FirstColumns(top_k)
        spaces = getattr(self.observation_space, "spaces", {})
        if "privileged" in spaces or "privileged_map" in spaces:
            self.add_module(PRIVILEGED_HEAD, PrivilegedValue(spaces))
        # the optimizer was created over the old action_net; rebuild it over the current modules
        self.optimizer = self.optimizer_class(self.parameters(), lr=lr_schedule(1), **self.optimizer_kwargs)  # type: ignore[call-arg]

    def _privileged_value(self, obs: Any) -> torch.Tensor | float:
        head = getattr(self, PRIVILEGED_HEAD, None)
        return 0.0 if head is None else head(obs)

    def forward(self, obs: Any, deterministic: bool = False) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
        """Actions, values and log-probabilities, as SB3's (the values with the privileged head)."""
        actions, values, log_prob = super().forward(obs, deterministic)
        return actions, values + self._privileged_value(obs), log_prob

    def evaluate_actions(
        self, obs: Any, actions: torch.Tensor
    ) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor | None]:
        """Values, log-probabilities and entropy of ``actions``, as SB3's (values with the head)."""
        values, log_prob, entropy = super().evaluate_actions(obs, actions)
        return values + self._privileged_value(obs), log_prob, entropy

    def predict_values(self, obs: Any) -> torch.Tensor:
        """The critic's values, as SB3's (with the privileged head)."""
        return super().predict_values(obs) + self._privileged_value(obs)
