"""Reward presets: each step's reward is the documented sum, and faster exploration earns more."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from frontier_rl.core.sim.leg_result import LegResult
from frontier_rl.core.world.grid import CellState
from frontier_rl.envs import REWARD_PRESETS, PointEnv, WeightEnv, reward_preset
from frontier_rl.envs.point_env import pixel_states
from frontier_rl.envs.rewards import THESIS_SECONDS_WEIGHT
from frontier_rl.errors import UnknownNameError


def _scripted_episode(env: WeightEnv, action: int, seed: int) -> tuple[list[float], list[LegResult], list[bool]]:
    """Run ``action`` until the end, recording every leg the simulator drove."""
    legs: list[LegResult] = []
    env.reset(seed=seed, options={"world_seed": seed})
    drive = env.sim.execute

    def recording_execute(*args: Any, **kwargs: Any) -> LegResult:
        leg = drive(*args, **kwargs)
        legs.append(leg)
        return leg

    env.sim.execute = recording_execute  # type: ignore[method-assign]
    rewards, ends = [], []
    terminated = truncated = False
    while not (terminated or truncated):
        _, reward, terminated, truncated, _ = env.step(action)
        rewards.append(reward)
        ends.append(terminated)
    return rewards, legs, ends


def test_thesis_preset_is_table_3_2() -> None:
    env = WeightEnv(observation_size=64, reward="thesis")
    rewards, legs, ends = _scripted_episode(env, 80, seed=1)
    assert ends[-1] and not any(ends[:-1])
    for reward, leg, end in zip(rewards, legs, ends, strict=True):
        expected = 50 * leg.new_free + 25 * leg.new_occupied - THESIS_SECONDS_WEIGHT * leg.duration_s + 500 * end
        assert reward == pytest.approx(expected)
    assert sum(leg.new_free for leg in legs) > 1000


def test_normalised_preset_returns_coverage_minus_time() -> None:
    env = WeightEnv(observation_size=64, reward="normalised")
    rewards, _, _ = _scripted_episode(env, 80, seed=1)
    start_coverage = env.sim.result(0.0).coverage_curve[0]
    expected = env.sim.coverage - start_coverage - 0.01 * env.sim.sim_time + 1.0
    assert sum(rewards) == pytest.approx(expected)


@pytest.mark.parametrize("preset", sorted(REWARD_PRESETS))
def test_time_dominates_the_return(preset: str) -> None:
    """Both presets rank a whole episode by its time: the faster weight earns the larger return."""
    env = WeightEnv(observation_size=64, reward=preset)
    returns, times = [], []
    for action in (0, 85):
        rewards, _, _ = _scripted_episode(env, action, seed=4)
        returns.append(sum(rewards))
        times.append(env.sim.sim_time)
    assert times[1] < times[0]
    assert returns[1] > returns[0]


def test_cell_rewards_are_table_3_1() -> None:
    cfg = reward_preset("thesis")
    wall, free, unknown = CellState.OCCUPIED, CellState.FREE, CellState.UNKNOWN
    state = np.array([[free, free, unknown], [free, wall, unknown], [free, free, free]], np.int8)
    assert cfg.cell_reward(state, 0, 0) == 400  # free, only diagonal to the wall
    assert cfg.cell_reward(state, 0, 2) == 500  # unknown
    assert cfg.cell_reward(state, 1, 1) == -500  # occupied
    assert cfg.cell_reward(state, 0, 1) == 400 - 50  # free, next to the wall
    assert cfg.cell_reward(state, 1, 2) == 500 - 50  # unknown, next to the wall


def test_point_env_adds_the_cell_reward() -> None:
    env = PointEnv(observation_size=64, reward="thesis")
    obs, _ = env.reset(seed=0)
    unknown = np.argwhere(obs[0] == 128)
    row, col = unknown[0]
    drive = env.sim.go_to
    legs: list[LegResult] = []
    env.sim.go_to = lambda *a, **k: legs.append(drive(*a, **k)) or legs[-1]  # type: ignore[method-assign]
    _, reward, terminated, _, _ = env.step(int(row * 64 + col))
    leg = legs[0]
    cell = env.rewards.cell_reward(pixel_states(obs[0]), int(row), int(col))
    assert cell in (500, 450)
    leg_part = 50 * leg.new_free + 25 * leg.new_occupied - THESIS_SECONDS_WEIGHT * leg.duration_s + 500 * terminated
    assert reward == pytest.approx(leg_part + cell)


@pytest.mark.parametrize("preset", sorted(REWARD_PRESETS))
def test_a_point_decision_that_explores_nothing_never_pays(preset: str) -> None:
    # choosing the robot's own cell (or any it cannot reach) costs a recovery turn and maps
    # nothing: if the chosen cell's reward outweighed that turn, a point model would learn to
    # stall (it did, with the normalised preset's cell terms 1,000 times the thesis's share)
    env = PointEnv(observation_size=64, reward=preset)
    env.reset(seed=0)
    cfg = env.rewards
    assert max(cfg.chosen_free, cfg.chosen_unknown) == pytest.approx(0.05 * cfg.per_second)  # 3.1 beside 3.2
    for _ in range(5):
        grid, pose = env.sim.map(), env.sim.pose
        row0, col0 = env.encoder.window_origin(grid, pose)
        row, col = grid.world_to_cell(pose.x, pose.y)
        factor = env.encoder.factor
        covered = env.sim.coverage
        _, reward, *_ = env.step(int((row - row0) // factor * 64 + (col - col0) // factor))
        assert env.sim.coverage - covered < 0.01 and reward < 0


def test_unknown_preset_is_named() -> None:
    with pytest.raises(UnknownNameError, match="fast"):
        reward_preset("fast")
