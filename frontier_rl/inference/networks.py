"""The networks of the models, in plain torch: a CNN over occupancy-grid images and the frontier
table's scorer and pooling. Training wraps them as Stable-Baselines3 features extractors
(:mod:`frontier_rl.rl.networks`); running a model file needs only these
(:mod:`frontier_rl.inference.actor`). Their module names are the weights' names in a model file.
"""

from __future__ import annotations

import torch
from torch import nn

MASKED_LOGIT = -1.0e4
"""Logit given to an empty frontier slot: its probability is exp(−10⁴) ≈ 0."""

GRID_CNN_FEATURES = 64 * 16
"""The length of :func:`grid_cnn`'s output: its last convolution's 64 channels, pooled to 4 × 4."""

FRONTIER_EMBEDDING = 64
"""Size of each frontier's embedding in :class:`FrontierPool`."""


def grid_cnn(channels: int) -> nn.Sequential:
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


class GridFeatures(nn.Module):
    """Map image (channels, H, W), scaled to [0, 1] → ``features_dim`` features (models 1-4).

    Args:
        channels: the image's channels (1, or 3 with the frontier and pose channels).
        features_dim: the output's length.
    """

    def __init__(self, channels: int, features_dim: int = 128) -> None:
        super().__init__()
        self.features_dim = features_dim
        self.cnn = grid_cnn(channels)
        self.head = nn.Sequential(nn.Linear(GRID_CNN_FEATURES, features_dim), nn.ReLU())

    def forward(self, observations: torch.Tensor) -> torch.Tensor:
        """Features of a batch of map images."""
        return self.head(self.cnn(observations))  # type: ignore[no-any-return]


class _FrontierTableFeatures(nn.Module):
    """The part models 5-7 share: the map image → a ``context_dim`` embedding, and each frontier's
    row of the table (``columns`` values) beside it, for ``top_k`` rows."""

    def __init__(self, map_channels: int, top_k: int, columns: int, context_dim: int, features_dim: int) -> None:
        super().__init__()
        self.features_dim = features_dim
        self.top_k = top_k
        self.columns = columns  # model 5's features, and model 7's tour column
        self.cnn = grid_cnn(map_channels)
        self.context = nn.Sequential(nn.Linear(GRID_CNN_FEATURES, context_dim), nn.ReLU())

    def _pairs(self, observations: dict[str, torch.Tensor]) -> tuple[torch.Tensor, torch.Tensor]:
        """(batch, K, features + context) rows, and the (batch, context) map embedding."""
        context = self.context(self.cnn(observations["map"]))
        table = observations["frontiers"].reshape(context.shape[0], self.top_k, self.columns)
        return torch.cat((table, context[:, None, :].expand(-1, self.top_k, -1)), dim=2), context


class FrontierScores(_FrontierTableFeatures):
    """Frontier-table observation → [K masked frontier scores | ``context_dim`` map features]
    (models 5 and 7).

    Every frontier is scored by one shared MLP over its features and the map embedding, so the
    scores do not depend on the order of the slots (a pointer network over the candidates).
    """

    def __init__(self, map_channels: int, top_k: int, columns: int, context_dim: int = 128) -> None:
        super().__init__(map_channels, top_k, columns, context_dim, top_k + context_dim)
        self.scorer = nn.Sequential(nn.Linear(columns + context_dim, 64), nn.ReLU(), nn.Linear(64, 1))

    def forward(self, observations: dict[str, torch.Tensor]) -> torch.Tensor:
        """Scores of the K slots (masked) followed by the map context."""
        pairs, context = self._pairs(observations)
        scores = self.scorer(pairs).squeeze(-1)
        mask = observations["mask"]
        scores = torch.where(mask > 0.5, scores, torch.full_like(scores, MASKED_LOGIT))
        return torch.cat((scores, context), dim=1)


class FrontierPool(_FrontierTableFeatures):
    """Frontier-table observation → [``context_dim`` map features | the frontiers' embeddings,
    max-pooled | mean-pooled], for a policy with one action per decision (model 6's weight).

    Each frontier is embedded by one shared MLP over its features and the map embedding, and the
    pools run over the rows the mask keeps (a Deep Sets encoder): the output does not depend on
    the order of the rows, and an empty table pools to zeros.
    """

    def __init__(self, map_channels: int, top_k: int, columns: int, context_dim: int = 128) -> None:
        super().__init__(map_channels, top_k, columns, context_dim, context_dim + 2 * FRONTIER_EMBEDDING)
        self.embed = nn.Sequential(
            nn.Linear(columns + context_dim, FRONTIER_EMBEDDING),
            nn.ReLU(),
            nn.Linear(FRONTIER_EMBEDDING, FRONTIER_EMBEDDING),
            nn.ReLU(),
        )

    def forward(self, observations: dict[str, torch.Tensor]) -> torch.Tensor:
        """The map context, then the max and the mean of the kept rows' embeddings."""
        pairs, context = self._pairs(observations)
        keep = (observations["mask"] > 0.5).unsqueeze(-1)
        embedded = torch.where(keep, self.embed(pairs), torch.zeros((), dtype=pairs.dtype))  # >= 0 (ReLU)
        count = keep.sum(dim=1).clamp(min=1)
        return torch.cat((context, embedded.amax(dim=1), embedded.sum(dim=1) / count), dim=1)


class FirstColumns(nn.Module):
    """Passes on the first ``n`` features: :class:`FrontierScores`' scores become the action logits."""

    def __init__(self, n: int) -> None:
        super().__init__()
        self.n = n

    def forward(self, latent: torch.Tensor) -> torch.Tensor:
        """The first ``n`` columns of ``latent``."""
        return latent[:, : self.n]
