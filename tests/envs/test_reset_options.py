"""``reset(options=...)``: ``world_seed`` is the only key; a typo or a value of the wrong kind is an
error naming it, in every registered env and in the team env, and changes nothing."""

from __future__ import annotations

from typing import Any, cast

import gymnasium as gym
import numpy as np
import pytest

import frontier_rl  # noqa: F401  (registers the ids)
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.envs.base import ExplorationEnv
from frontier_rl.envs.team_env import parallel_env
from frontier_rl.envs.world_source import RESET_OPTIONS, reset_world_seed
from frontier_rl.errors import ConfigError
from frontier_rl.registration import ENV_IDS, env_id
from frontier_rl.swarm import TeamConfig

SHORT = SimConfig(max_sim_time=30.0)


def _unwrapped(env: gym.Env[Any, Any]) -> ExplorationEnv[Any]:
    return cast(ExplorationEnv[Any], env.unwrapped)


BAD_OPTIONS: list[tuple[Any, str]] = [
    ({"world_sed": 1}, r"unknown reset option 'world_sed' \(did you mean 'world_seed'\?\); known: world_seed"),
    ({"World_Seed": 1}, r"unknown reset option 'World_Seed'"),
    ({"world_seed": 1, "seed": 2}, r"unknown reset option 'seed'"),
    ({1: 2}, r"unknown reset option 1;"),
    ({"x" * 500: 1}, r"unknown reset option 'xxxx.*…;"),  # a long key is cut
    ({"world_seed": "3"}, r"world_seed must be .*, got a str"),
    ({"world_seed": 3.0}, r"world_seed must be .*, got a float"),
    ({"world_seed": True}, r"world_seed must be .*, got a bool"),
    ({"world_seed": np.float64(2)}, r"world_seed must be .*, got a float64"),
    ({"world_seed": [1]}, r"world_seed must be .*, got a list"),
    ({"world_seed": -1}, r"world_seed must be .*, got -1"),
    ({"world_seed": 2**63}, r"world_seed must be .*, got 9223372036854775808"),
    ({"world_seed": 10**400}, r"got a number of more than 30 digits"),
    ({"world_seed": -(10**5000)}, r"got a number of more than 30 digits"),
    ("world_seed", r"reset options must be a dict or None, got str"),
    ([("world_seed", 1)], r"reset options must be a dict or None, got list"),
]


@pytest.mark.parametrize(("options", "message"), BAD_OPTIONS, ids=[str(i) for i in range(len(BAD_OPTIONS))])
def test_the_check_refuses(options: Any, message: str) -> None:
    with pytest.raises(ConfigError, match=message) as caught:
        reset_world_seed(options)
    assert "\n" not in str(caught.value) and len(str(caught.value)) < 200


@pytest.mark.parametrize(
    ("options", "seed"), [(None, None), ({}, None), ({"world_seed": None}, None), ({"world_seed": 7}, 7),
                          ({"world_seed": np.int64(7)}, 7), ({"world_seed": np.uint32(0)}, 0)],
)  # fmt: skip
def test_the_check_accepts(options: Any, seed: int | None) -> None:
    result = reset_world_seed(options)
    assert result == seed and (result is None or type(result) is int)
    assert list(RESET_OPTIONS) == ["world_seed"]


@pytest.mark.parametrize("env_name", ENV_IDS)
@pytest.mark.parametrize("options", [{"world_sed": 1}, {"world_seed": "1"}, {"world_seed": -3}, "world_seed"])
def test_every_registered_env_refuses_bad_options(env_name: str, options: Any) -> None:
    env = gym.make(env_name, sim=SHORT)
    with pytest.raises(ConfigError, match="reset option"):
        env.reset(seed=0, options=options)
    with pytest.raises(RuntimeError, match="call reset"):  # nothing was started
        _unwrapped(env).sim  # noqa: B018


@pytest.mark.parametrize(
    "options", [{"world_sed": 1}, {"world_seed": 2.5}, {"worldseed": 1}, {"WorldSeed": 1}, {"world-seed": 1}, [1]]
)
def test_the_team_env_refuses_bad_options(options: Any) -> None:
    env = parallel_env(team=TeamConfig(robots=2), observation_size=64, sim=SHORT)
    with pytest.raises(ConfigError, match="reset option"):
        env.reset(seed=0, options=options)
    assert env.agents == []


def test_the_team_env_lets_other_keys_pass_for_pettingzoo() -> None:
    """PettingZoo's ``parallel_api_test`` resets with ``options={"options": 1}``."""
    env = parallel_env(team=TeamConfig(robots=2), observation_size=64, sim=SHORT)
    env.reset(seed=0, options={"options": 1})
    assert env.agents == ["robot_0", "robot_1"]
    with pytest.raises(ConfigError, match=r"unknown reset option 'options'"):
        reset_world_seed({"options": 1})  # the Gym envs refuse it


def test_a_world_seed_still_picks_the_world() -> None:
    env = gym.make(env_id(4, 64), sim=SHORT)
    env.reset(seed=0, options={"world_seed": 3})
    world = _unwrapped(env).sim.world
    env.reset(seed=1, options={"world_seed": np.int64(3)})  # another env seed, the same world seed
    again = _unwrapped(env).sim.world
    assert world.start == again.start and np.array_equal(world.grid.data, again.grid.data)
    env.reset(seed=0, options={"world_seed": 4})
    assert not np.array_equal(world.grid.data, _unwrapped(env).sim.world.grid.data)
