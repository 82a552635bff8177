"""The frontier-table feature extractors: order of the rows, the mask, and an empty table."""

from __future__ import annotations

import gymnasium as gym
import pytest
import torch

from frontier_rl.inference.networks import FRONTIER_EMBEDDING, MASKED_LOGIT
from frontier_rl.registration import env_id
from frontier_rl.rl.networks import FrontierPooling, FrontierScorer

TOP_K = 16
N_FEATURES = 6
CONTEXT = 32


def _space() -> gym.spaces.Dict:
    space = gym.make(env_id(6, 64)).observation_space
    assert isinstance(space, gym.spaces.Dict)
    return space


def _batch(rows: int, seed: int = 0) -> dict[str, torch.Tensor]:
    """Two observations whose first ``rows`` table rows hold frontiers; the rest are random too,
    so a row the mask drops would show if it leaked."""
    gen = torch.Generator().manual_seed(seed)
    mask = torch.zeros(2, TOP_K)
    mask[:, :rows] = 1.0
    return {
        "map": torch.rand(2, 3, 64, 64, generator=gen),
        "frontiers": torch.randn(2, TOP_K * N_FEATURES, generator=gen),
        "mask": mask,
    }


def _permuted(obs: dict[str, torch.Tensor], order: torch.Tensor) -> dict[str, torch.Tensor]:
    table = obs["frontiers"].reshape(2, TOP_K, N_FEATURES)[:, order].reshape(2, -1)
    return {**obs, "frontiers": table, "mask": obs["mask"][:, order]}


def test_pooling_ignores_the_order_and_the_masked_rows() -> None:
    torch.manual_seed(0)
    net = FrontierPooling(_space(), context_dim=CONTEXT)
    obs = _batch(rows=5)
    out = net(obs)
    assert out.shape == (2, CONTEXT + 2 * FRONTIER_EMBEDDING)
    order = torch.randperm(TOP_K, generator=torch.Generator().manual_seed(1))
    torch.testing.assert_close(net(_permuted(obs, order)), out)
    scrambled = obs["frontiers"].clone().reshape(2, TOP_K, N_FEATURES)
    scrambled[:, 5:] = 99.0  # the rows the mask drops
    assert torch.equal(net({**obs, "frontiers": scrambled.reshape(2, -1)}), out)
    kept = net({**obs, "mask": torch.ones(2, TOP_K)})
    assert not torch.allclose(kept[:, CONTEXT:], out[:, CONTEXT:])  # the mask is what hid them


def test_an_empty_table_pools_to_zeros() -> None:
    out = FrontierPooling(_space(), context_dim=CONTEXT)(_batch(rows=0))
    assert torch.isfinite(out).all()
    assert torch.equal(out[:, CONTEXT:], torch.zeros(2, 2 * FRONTIER_EMBEDDING))


@pytest.mark.parametrize("rows", [1, 9])
def test_the_scorer_masks_empty_slots_and_scores_rows_alike_in_any_order(rows: int) -> None:
    torch.manual_seed(0)
    net = FrontierScorer(_space(), context_dim=CONTEXT)
    obs = _batch(rows)
    scores = net(obs)[:, :TOP_K]
    assert (scores[:, rows:] == MASKED_LOGIT).all()
    order = torch.randperm(TOP_K, generator=torch.Generator().manual_seed(2))
    torch.testing.assert_close(net(_permuted(obs, order))[:, :TOP_K], scores[:, order])
