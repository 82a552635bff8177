"""Feature extractors for occupancy-grid images and frontier tables, and the pointer policy of the
frontier-choice model."""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import torch
from stable_baselines3.common.policies import ActorCriticPolicy
from stable_baselines3.common.torch_layers import BaseFeaturesExtractor
from torch import nn

MASKED_LOGIT = -1.0e4
"""Logit given to an empty frontier slot: its probability is exp(−10⁴) ≈ 0."""


GRID_CNN_FEATURES = 64 * 16
"""The length of :func:`_grid_cnn`'s output: its last convolution's 64 channels, pooled to 4 × 4."""


def _grid_cnn(channels: int) -> nn.Sequential:
    """Four stride-2 convolutions and a 4 × 4 average pool: 33 k weights and a 1,024-feature output
    whatever the image size (a 250 × 250 map would give NatureCNN's flatten layer 24 M weights),
    and walls a few cells thick survive the first layers."""
    return nn.Sequential(
        nn.Conv2d(channels, 16, kernel_size=5, stride=2, padding=2),
        nn.ReLU(),
        nn.Conv2d(16, 32, kernel_size=3, stride=2, padding=1),
        nn.ReLU(),
        nn.Conv2d(32, 32, kernel_size=3, stride=2, padding=1),
        nn.ReLU(),
        nn.Conv2d(32, 64, kernel_size=3, stride=2, padding=1),
        nn.ReLU(),
        nn.AdaptiveAvgPool2d(4),
        nn.Flatten(),
    )


class GridCNN(BaseFeaturesExtractor):
    """Map image (channels, H, W) uint8 → ``features_dim`` features.

    SB3 has already scaled the image to [0, 1] (``normalize_images``) when it reaches ``forward``.
    """

    def __init__(self, observation_space: gym.spaces.Box, features_dim: int = 128) -> None:
        super().__init__(observation_space, features_dim)
        self.cnn = _grid_cnn(int(observation_space.shape[0]))
        self.head = nn.Sequential(nn.Linear(GRID_CNN_FEATURES, features_dim), nn.ReLU())

    def forward(self, observations: torch.Tensor) -> torch.Tensor:
        """Features of a batch of map images."""
        return self.head(self.cnn(observations))  # type: ignore[no-any-return]


class _FrontierTableExtractor(BaseFeaturesExtractor):
    """The part models 5 and 6 share: the map image → a ``context_dim`` embedding, and each
    frontier's row of the table beside it."""

    def __init__(self, observation_space: gym.spaces.Dict, context_dim: int, features_dim: int) -> None:
        map_shape = observation_space["map"].shape
        mask_shape = observation_space["mask"].shape
        assert map_shape is not None and mask_shape is not None
        super().__init__(observation_space, features_dim)
        self.top_k = int(mask_shape[0])
        table_shape = observation_space["frontiers"].shape
        assert table_shape is not None
        self.columns = int(table_shape[0]) // self.top_k  # model 5's features, and model 7's tour column
        self.cnn = _grid_cnn(int(map_shape[0]))
        self.context = nn.Sequential(nn.Linear(GRID_CNN_FEATURES, context_dim), nn.ReLU())

    def _pairs(self, observations: dict[str, torch.Tensor]) -> tuple[torch.Tensor, torch.Tensor]:
        """(batch, K, features + context) rows, and the (batch, context) map embedding."""
        context = self.context(self.cnn(observations["map"]))
        table = observations["frontiers"].reshape(context.shape[0], self.top_k, self.columns)
        return torch.cat((table, context[:, None, :].expand(-1, self.top_k, -1)), dim=2), context


class FrontierScorer(_FrontierTableExtractor):
    """Frontier-choice observation → [K masked frontier scores | ``context_dim`` map features].

    Every frontier is scored by one shared MLP over its features and the map embedding, so the
    scores do not depend on the order of the slots (a pointer network over the candidates).
    """

    def __init__(self, observation_space: gym.spaces.Dict, context_dim: int = 128) -> None:
        mask_shape = observation_space["mask"].shape
        assert mask_shape is not None
        super().__init__(observation_space, context_dim, int(mask_shape[0]) + context_dim)
        self.scorer = nn.Sequential(nn.Linear(self.columns + context_dim, 64), nn.ReLU(), nn.Linear(64, 1))

    def forward(self, observations: dict[str, torch.Tensor]) -> torch.Tensor:
        """Scores of the K slots (masked) followed by the map context."""
        pairs, context = self._pairs(observations)
        scores = self.scorer(pairs).squeeze(-1)
        mask = observations["mask"]
        scores = torch.where(mask > 0.5, scores, torch.full_like(scores, MASKED_LOGIT))
        return torch.cat((scores, context), dim=1)


FRONTIER_EMBEDDING = 64
"""Size of each frontier's embedding in :class:`FrontierPooling`."""


class FrontierPooling(_FrontierTableExtractor):
    """Frontier-table observation → [``context_dim`` map features | the frontiers' embeddings,
    max-pooled | mean-pooled], for a policy with one action per decision (model 6's weight).

    Each frontier is embedded by one shared MLP over its features and the map embedding, and the
    pools run over the rows the mask keeps (a Deep Sets encoder): the output does not depend on
    the order of the rows, and an empty table pools to zeros.
    """

    def __init__(self, observation_space: gym.spaces.Dict, context_dim: int = 128) -> None:
        super().__init__(observation_space, context_dim, context_dim + 2 * FRONTIER_EMBEDDING)
        n_in = self.columns + context_dim
        self.embed = nn.Sequential(
            nn.Linear(n_in, FRONTIER_EMBEDDING), nn.ReLU(), nn.Linear(FRONTIER_EMBEDDING, FRONTIER_EMBEDDING), nn.ReLU()
        )

    def forward(self, observations: dict[str, torch.Tensor]) -> torch.Tensor:
        """The map context, then the max and the mean of the kept rows' embeddings."""
        pairs, context = self._pairs(observations)
        keep = (observations["mask"] > 0.5).unsqueeze(-1)
        embedded = torch.where(keep, self.embed(pairs), torch.zeros((), dtype=pairs.dtype))  # >= 0 (ReLU)
        count = keep.sum(dim=1).clamp(min=1)
        return torch.cat((context, embedded.amax(dim=1), embedded.sum(dim=1) / count), dim=1)


class _FirstColumns(nn.Module):
    """Passes on the first ``n`` features: the frontier scores become the action logits."""

    def __init__(self, n: int) -> None:
        super().__init__()
        self.n = n

    def forward(self, latent: torch.Tensor) -> torch.Tensor:
        return latent[:, : self.n]


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
            self.cnn = _grid_cnn(int(spaces["privileged_map"].shape[0]))  # type: ignore[index]
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
        self.action_net = _FirstColumns(top_k)
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
