"""The registered environments: API conformance, determinism, resets, actions, rendering."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env as gym_check_env
from PIL import Image
from stable_baselines3.common.env_checker import check_env as sb3_check_env

import frontier_rl
from frontier_rl.core.world.catalog import generate_world
from frontier_rl.envs import FrontierChoiceEnv, WeightEnv
from frontier_rl.envs.world_source import VALIDATION_SEED_LOW
from frontier_rl.errors import ConfigError, UnknownNameError
from frontier_rl.observation.frontier_table import FEATURE_BOUND, TOUR_STOPS
from frontier_rl.observation.map_image import MAP_FREE, MAP_UNKNOWN, MARK
from frontier_rl.observation.weight_bins import WEIGHT_BINS, bin_to_weight
from frontier_rl.registration import ENV_IDS, MODELS, ModelKind, env_id


def _obs_equal(a: Any, b: Any) -> bool:
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(np.array_equal(a[k], b[k]) for k in a)
    return bool(np.array_equal(a, b))


def test_every_model_and_size_is_registered() -> None:
    assert len(ENV_IDS) == 14
    assert all(i in gym.registry for i in ENV_IDS)
    assert env_id(4) == "FrontierRL/WeightMap-v0"
    assert env_id(4, 64) == "FrontierRL/WeightMap64-v0"
    assert env_id(6, 64) == "FrontierRL/WeightFrontierTable64-v0"
    assert env_id(7, 64) == "FrontierRL/FrontierChoiceTour64-v0"
    with pytest.raises(ConfigError, match="8"):
        env_id(8)
    with pytest.raises(ConfigError, match="100"):
        env_id(4, 100)


def test_each_models_kind_is_what_its_env_chooses() -> None:
    """The kind is typed on the model, where it was read from the env's class name."""
    envs = {
        ModelKind.POINT: "PointEnv",
        ModelKind.WEIGHT: "WeightEnv",
        ModelKind.WEIGHT_TABLE: "WeightTableEnv",
        ModelKind.FRONTIER: "FrontierChoiceEnv",
    }
    assert {m: spec.entry_point.rsplit(":", 1)[1] for m, spec in MODELS.items()} == {
        m: envs[spec.kind] for m, spec in MODELS.items()
    }


@pytest.mark.parametrize("env_name", ENV_IDS)
def test_passes_gymnasium_and_sb3_checkers(env_name: str) -> None:
    env = gym.make(env_name, render_mode="rgb_array")
    gym_check_env(env.unwrapped, skip_render_check=False)
    sb3_check_env(gym.make(env_name), warn=True)


def test_the_privileged_entry_passes_the_checkers_and_follows_the_coverage() -> None:
    env = gym.make(env_id(5, 64), privileged=True, render_mode="rgb_array")
    gym_check_env(env.unwrapped, skip_render_check=False)
    sb3_check_env(gym.make(env_id(5, 64), privileged=True), warn=True)
    obs, _ = env.reset(seed=0)
    shares = [float(obs["privileged"][0])]
    for _ in range(4):
        obs, *_ = env.step(0)
        shares.append(float(obs["privileged"][0]))
    assert 0.0 < shares[-1] < shares[0] < 1.0  # the unseen share falls as the robot maps
    assert np.isclose(shares[-1], 1.0 - env.unwrapped.sim.coverage)  # type: ignore[attr-defined]
    assert "privileged" not in gym.make(env_id(5, 64)).observation_space.spaces  # type: ignore[attr-defined]


def test_the_privileged_map_shows_the_unseen_explorable_space_under_the_map_window() -> None:
    env = gym.make(env_id(7, 64), privileged=True, privileged_map=True, worlds="rooms")
    sb3_check_env(env, warn=True)
    obs, _ = env.reset(seed=1)
    totals = []
    for _ in range(4):
        image, seen_map = obs["privileged_map"][0], obs["map"][0]
        assert image.shape == seen_map.shape and image.dtype == np.uint8
        assert np.all(image[seen_map == MAP_FREE] <= 128)  # a pixel is free when half its cells are known free
        assert np.any(image[seen_map == MAP_UNKNOWN] == MARK)  # unknown pixels wholly in the rooms
        totals.append(int(image.sum()))
        obs, *_ = env.step(0)
    assert totals[-1] < totals[0]  # it shrinks as the robot maps
    assert "privileged_map" not in gym.make(env_id(7, 64), privileged=True).observation_space.spaces  # type: ignore[attr-defined]


@pytest.mark.parametrize("model", [1, 3, 4, 5, 6, 7])
def test_same_seed_same_episode(model: int) -> None:
    def rollout() -> tuple[list[Any], list[float], list[dict[str, Any]]]:
        env = gym.make(env_id(model, 64))
        env.action_space.seed(3)
        obs, info = env.reset(seed=11)
        observations, rewards, infos = [obs], [], [info]
        for _ in range(6):
            obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
            observations.append(obs)
            rewards.append(reward)
            infos.append(info)
            if terminated or truncated:
                break
        return observations, rewards, infos

    first, second = rollout(), rollout()
    assert all(_obs_equal(a, b) for a, b in zip(first[0], second[0], strict=True))
    assert first[1] == second[1]
    assert first[2] == second[2]


def test_reset_rebuilds_everything() -> None:
    env = WeightEnv(observation_size=64)
    fresh, _ = env.reset(seed=5)
    for _ in range(5):
        env.step(90)
    assert env.sim.sim_time > 0
    again, info = env.reset(seed=5)
    assert np.array_equal(fresh, again)
    assert info["sim_time_s"] == 0.0 and info["decisions"] == 0
    assert not env.sim.blacklist.entries and env.sim.path_length == 0.0
    other, _ = env.reset(seed=6)
    assert not np.array_equal(fresh, other)


def test_world_seed_option_picks_an_evaluation_world() -> None:
    env = WeightEnv(observation_size=64)
    env.reset(seed=0, options={"world_seed": 3})
    expected = generate_world("office", 3)
    assert np.array_equal(env.sim.world.grid.data, expected.grid.data)
    assert env.sim.world.start == expected.start


def test_random_training_worlds_never_use_small_seeds() -> None:
    env = WeightEnv(observation_size=64)
    worlds = set()
    for seed in range(5):
        env.reset(seed=seed)
        worlds.add(env.sim.world.grid.data.tobytes())
        assert not any(np.array_equal(env.sim.world.grid.data, generate_world("office", k).grid.data) for k in range(3))
    assert len(worlds) == 5


@pytest.mark.parametrize(
    ("action", "match"),
    [(100, "outside the action space 0..99"), (-1, "outside"), (np.nan, "finite"), (1.5, "finite"),
     ([1, 2], "one integer"), ("3", "one integer"), (5 + 0j, r"one integer, got \(5\+0j\)"),
     (True, "one integer")],
)  # fmt: skip
def test_bad_actions_are_named(action: Any, match: str) -> None:
    env = WeightEnv(observation_size=64)
    env.reset(seed=0)
    with pytest.raises(ValueError, match=match):
        env.step(action)


def test_step_after_the_end_asks_for_reset() -> None:
    env = WeightEnv(observation_size=64, max_decisions=2)
    env.reset(seed=0)
    env.step(80)
    _, _, terminated, truncated, _ = env.step(80)
    assert truncated and not terminated
    with pytest.raises(RuntimeError, match="reset"):
        env.step(80)


def test_a_world_explored_from_its_start_is_drawn_again(tmp_path: Path) -> None:
    """A room the sensor sees whole ended its episode at reset, and the first step raised (a
    training run on a folder with such a map crashed)."""
    rooms = tmp_path / "rooms"
    rooms.mkdir()
    image = np.zeros((24, 24), np.uint8)  # 1.2 m across: seen whole from every start
    image[3:-3, 3:-3] = 255
    for name in ("a.png", "b.png"):
        Image.fromarray(image).save(rooms / name)
    with pytest.raises(ConfigError, match=r"each of 100 worlds drawn from .*rooms' had no frontier left at its start"):
        WeightEnv(worlds=str(rooms), observation_size=64).reset(seed=0)
    env = WeightEnv(worlds=f"{rooms}=10,office", observation_size=64)
    for seed in range(3):
        _, info = env.reset(seed=seed)
        assert info["world"] == "office" and info["frontiers"] > 0
        assert env.step(80)[4]["decisions"] == 1
    # a validation episode's family is kept: the rooms' world_seed never became a training world's
    validation = WeightEnv(worlds=f"{rooms},office", observation_size=64, world_split="validation")
    with pytest.raises(ConfigError, match="had no frontier left at its start"):
        validation.reset(seed=0, options={"world_seed": VALIDATION_SEED_LOW})
    assert validation.reset(seed=0, options={"world_seed": VALIDATION_SEED_LOW + 1})[1]["world"] == "office"


def test_step_before_reset_is_an_error() -> None:
    with pytest.raises(RuntimeError, match="reset"):
        WeightEnv(observation_size=64).step(1)


def test_bad_options_are_named() -> None:
    with pytest.raises(UnknownNameError, match="atlantis"):
        WeightEnv(worlds="office,atlantis")
    with pytest.raises(UnknownNameError, match="bonus"):
        WeightEnv(reward="bonus")
    with pytest.raises(ConfigError, match="colour"):
        WeightEnv(colour="red")
    with pytest.raises(ConfigError, match="render_mode"):
        WeightEnv(render_mode="human")


def test_runs_on_map_files(real_maps: Any) -> None:
    env = WeightEnv(worlds=str(real_maps / "turtlebot3_world"), observation_size=64, resolution=0.05)
    obs, info = env.reset(seed=0)
    assert obs.shape == (1, 64, 64)
    assert info["world"] == "map"
    info = env.step(75)[4]
    assert info["sim_time_s"] > 0


def test_render_rgb_array() -> None:
    env = gym.make(env_id(5, 64), render_mode="rgb_array")
    env.reset(seed=0)
    env.step(0)
    frame = env.render()
    assert isinstance(frame, np.ndarray) and frame.dtype == np.uint8
    assert frame.ndim == 3 and frame.shape[2] == 3 and frame.shape[0] > 100


def test_model_6_sees_model_5s_table_and_drives_by_its_weight() -> None:
    table, choice = gym.make(env_id(6, 64)), gym.make(env_id(5, 64))
    assert table.action_space == gym.spaces.Discrete(WEIGHT_BINS)
    assert table.observation_space == choice.observation_space
    obs6, _ = table.reset(seed=3)
    obs5, _ = choice.reset(seed=3)
    assert _obs_equal(obs6, obs5)
    for action in (0, 37, WEIGHT_BINS - 1):
        *_, info = table.step(action)
        assert info["weight"] == bin_to_weight(action)


def test_model_7_adds_the_tour_column_to_model_5s_table() -> None:
    tour, choice = gym.make(env_id(7, 64)), gym.make(env_id(5, 64))
    obs7, _ = tour.reset(seed=3)
    obs5, _ = choice.reset(seed=3)
    n = int(obs5["mask"].sum())
    table7, table5 = obs7["frontiers"].reshape(16, 7), obs5["frontiers"].reshape(16, 6)
    assert np.array_equal(table7[:, :6], table5) and np.array_equal(obs7["map"], obs5["map"])
    regret = table7[:n, 6]
    stops = min(n, TOUR_STOPS)
    assert np.isclose(regret[:stops].min(), 0.0) and np.all(regret[:stops] >= 0)  # the tour's first stop: 0
    assert np.all(regret[stops:] == FEATURE_BOUND) and np.all(table7[n:] == 0)
    assert n >= 2 and np.count_nonzero(regret[:stops] > 0) >= 1


def test_frontier_choice_mask_and_masked_actions() -> None:
    env = FrontierChoiceEnv(observation_size=64, top_k=16)
    obs, _ = env.reset(seed=2)
    mask = env.action_masks()
    assert np.array_equal(obs["mask"] > 0.5, mask)
    n = int(mask.sum())
    assert 1 <= n <= 16 and mask[:n].all() and not mask[n:].any()
    table = obs["frontiers"].reshape(16, -1)
    assert np.all(table[n:] == 0)
    assert np.all(np.diff(table[:n, 1]) >= 0)  # cheapest path first
    if n < 16:  # an empty slot is legal: it wraps onto a real frontier
        _, _, _, _, info = env.step(15)
        assert info["sim_time_s"] > 0


def _fresh_import(code: str) -> list[str]:
    import subprocess
    import sys

    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()


@pytest.mark.parametrize(
    "module", ["frontier_rl", "frontier_rl.core.sim.episode", "frontier_rl.policies", "frontier_rl.ros.node",
               "frontier_rl.observation.frontier_table", "frontier_rl.swarm"]
)  # fmt: skip
def test_the_engine_policies_and_ros_node_import_without_gymnasium_or_torch(module: str) -> None:
    loaded = _fresh_import(f"import sys, {module}; print('gymnasium' in sys.modules, 'torch' in sys.modules)")
    assert loaded == ["False", "False"]


def test_importing_the_envs_registers_every_id_without_torch() -> None:
    code = (
        "import sys, gymnasium as gym, frontier_rl.envs; from frontier_rl import ENV_IDS; "
        "print(all(i in gym.registry for i in ENV_IDS), 'torch' in sys.modules)"
    )
    assert _fresh_import(code) == ["True", "False"]
    assert frontier_rl.ENV_IDS == ENV_IDS


def test_make_with_the_module_prefix_registers_on_the_way() -> None:
    code = "import gymnasium as gym; print(gym.make('frontier_rl.envs:FrontierRL/WeightMap64-v0').spec.id)"
    assert _fresh_import(code) == ["FrontierRL/WeightMap64-v0"]
