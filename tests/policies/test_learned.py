"""A learned policy sees, at every decision, the observation its environment gives the network in
training, for the run's robot as well as the default one."""

from __future__ import annotations

import json
import zipfile
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import frontier_rl.envs  # noqa: F401 - registers the environments
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import decision_context
from frontier_rl.core.world.robot import RobotConfig
from frontier_rl.policies.learned import LearnedPolicy

REPO = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("model", ["model5", "model7"])
@pytest.mark.parametrize("radius", [RobotConfig().radius, 0.17])
def test_the_policy_sees_what_its_environment_shows(model: str, radius: float) -> None:
    """With ``--config`` giving another robot radius, the policy computed its path costs and tour
    for the default robot: its frontier table differed from the env's at every decision (by up to
    6.1 m of path cost), and model 7 took 345 s where it takes 417 s with its own robot."""
    path = REPO / "models" / f"{model}.zip"
    policy = LearnedPolicy(path)
    env_id = json.loads(zipfile.ZipFile(path).read("frontier_rl.json"))["env_id"]
    env = gym.make(env_id, worlds="office", sim=SimConfig(robot=RobotConfig(radius=radius)))
    observation, _ = env.reset(seed=5)
    seen: list[dict[str, np.ndarray]] = []
    policy._act = lambda obs: (seen.append(obs), policy._actor.act(obs))[1]  # type: ignore[method-assign]
    for _ in range(6):
        policy.rank(decision_context(env.unwrapped.sim), np.random.default_rng(0))  # type: ignore[attr-defined]
        for key, value in observation.items():
            np.testing.assert_array_equal(seen[-1][key], value, err_msg=key)
        observation, _, terminated, truncated, _ = env.step(policy._actor.act(observation))
        if terminated or truncated:
            break
    env.close()
