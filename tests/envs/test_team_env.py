"""The PettingZoo team environment: the API test, determinism, who acts, failures, bad input."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from pettingzoo.test import parallel_api_test

from frontier_rl.core.sim.config import SimConfig
from frontier_rl.envs.team_env import TeamExplorationEnv, parallel_env
from frontier_rl.errors import ConfigError
from frontier_rl.swarm import Failure, Strategy, TeamConfig

SHORT = SimConfig(max_sim_time=60.0)


def _env(action: str = "weight", **team: Any) -> TeamExplorationEnv:
    config = TeamConfig(**{"robots": 3, "strategy": Strategy.COORDINATED, **team})
    return parallel_env(team=config, action=action, observation_size=64, sim=SHORT)


@pytest.mark.parametrize("action", ["weight", "frontier"])
def test_parallel_api(action: str) -> None:
    parallel_api_test(_env(action, failures=(Failure(2, 20.0),)), num_cycles=1000)


def _rollout(env: TeamExplorationEnv, seed: int, other_action: int = 0) -> list[tuple[Any, ...]]:
    obs, infos = env.reset(seed=seed)
    trace = []
    while env.agents:
        acting = [a for a in env.agents if infos[a]["acting"]]
        assert len(acting) == 1  # one robot decides per step
        actions = {a: (75 if a in acting else other_action) for a in env.agents}
        obs, rewards, terms, truncs, infos = env.step(actions)
        trace.append((acting[0], {a: o.tobytes() for a, o in obs.items()}, rewards, terms, truncs))
    return trace


def test_same_seed_same_episode_and_idle_agents_do_not_matter() -> None:
    first = _rollout(_env(), seed=4)
    assert first == _rollout(_env(), seed=4, other_action=99)
    terms, truncs = first[-1][3], first[-1][4]
    assert terms and all(terms[a] or truncs[a] for a in terms)  # the episode ended for everyone
    assert first != _rollout(_env(), seed=5)


def test_a_failed_robot_terminates_and_leaves() -> None:
    env = _env(failures=(Failure(1, 10.0),))
    env.reset(seed=0)
    while env.agents:
        _, _, terms, _, infos = env.step({a: 50 for a in env.agents})
        if terms.get("robot_1"):
            assert infos["robot_1"]["failed"]
            assert "robot_1" not in env.agents
            break
    else:
        pytest.fail("robot_1 never failed")
    assert {"robot_0", "robot_2"} <= set(env.agents)


def test_the_acting_robot_must_act_and_within_its_space() -> None:
    env = _env()
    _, infos = env.reset(seed=1)
    acting = next(a for a in env.agents if infos[a]["acting"])
    with pytest.raises(ValueError, match=acting):
        env.step({a: 0 for a in env.agents if a != acting})
    with pytest.raises(ValueError, match="outside"):
        env.step({acting: 100})
    with pytest.raises(ConfigError, match="points"):
        TeamExplorationEnv(action="points")


def test_render_draws_the_team() -> None:
    env = parallel_env(team=TeamConfig(robots=2), observation_size=64, sim=SHORT, render_mode="rgb_array")
    env.reset(seed=0)
    image = env.render()
    assert image is not None and image.ndim == 3 and image.shape[2] == 3
    assert np.asarray(image).std() > 0
