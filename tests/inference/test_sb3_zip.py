"""A trusted SB3 policy's action is SB3's own deterministic ``predict`` (which the decision path does
not call, for its per-call overhead), for every shipped model built as SB3 builds it."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import torch
from stable_baselines3.common.preprocessing import preprocess_obs

from frontier_rl.inference.sb3_zip import network_input, predict_action
from frontier_rl.rl.model_file import load_policy

MODELS = sorted(Path(__file__).resolve().parents[2].joinpath("models").glob("model*.zip"))


@pytest.mark.parametrize("path", MODELS, ids=[p.stem for p in MODELS])
def test_the_chosen_action_is_sb3s_deterministic_prediction(path: Path) -> None:
    policy, _ = load_policy(path)
    assert not policy.training  # what predict_action relies on (SB3's predict sets it at every call)
    space = policy.observation_space
    space.seed(0)
    for _ in range(25):
        observation = space.sample()
        expected, _ = policy.predict(observation, deterministic=True)
        assert predict_action(policy, observation) == int(np.asarray(expected))


@pytest.mark.parametrize("path", MODELS, ids=[p.stem for p in MODELS])
def test_the_network_input_is_sb3s_bit_for_bit(path: Path) -> None:
    """The tensors the network is fed equal SB3's ``obs_to_tensor`` and ``preprocess_obs`` exactly
    (values, dtype and shape), also for a read-only observation."""
    policy, _ = load_policy(path)
    space = policy.observation_space
    space.seed(1)
    for _ in range(10):
        observation = space.sample()
        expected = preprocess_obs(policy.obs_to_tensor(observation)[0], space, normalize_images=policy.normalize_images)
        if isinstance(observation, dict):
            for value in observation.values():
                value.flags.writeable = False
        else:
            observation.flags.writeable = False
        got = network_input(policy, observation)
        pairs = [(got[k], expected[k]) for k in expected] if isinstance(expected, dict) else [(got, expected)]
        assert isinstance(got, dict) == isinstance(expected, dict)
        for ours, theirs in pairs:
            assert ours.dtype == theirs.dtype and ours.shape == theirs.shape
            assert torch.equal(ours, theirs)


def test_models_are_shipped() -> None:
    assert len(MODELS) >= 2, "the parametrized test above needs the shipped models"
