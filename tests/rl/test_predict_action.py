"""The action a loaded model chooses is SB3's own deterministic ``predict`` (which the decision path
no longer calls, for its per-call overhead), for every shipped model."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from frontier_rl.rl.inference import predict_action
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


def test_models_are_shipped() -> None:
    assert len(MODELS) >= 2, "the parametrized test above needs the shipped models"
