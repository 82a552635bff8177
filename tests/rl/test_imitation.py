"""DAgger for model 5 and its lookahead teacher."""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest
import torch

from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.core.world.worlds import World, make_world
from frontier_rl.envs.frontier_env import FrontierChoiceEnv
from frontier_rl.envs.lookahead import LOOKAHEAD_WIDTH, cheapest_slots, greedy_finish, lookahead_slot, take_slot
from frontier_rl.errors import ConfigError
from frontier_rl.io.ros_map import save_ros_map
from frontier_rl.policies import make_policy
from frontier_rl.rl.config import TrainConfig
from frontier_rl.rl.imitation import LabelledDecisions, fit
from frontier_rl.rl.model_file import read_metadata
from frontier_rl.rl.train import build_model, train

TOP_K = 16


def _rooms() -> OccupancyGrid:
    """A 4 m x 3 m floor: a corridor along the bottom and three rooms above it with doors."""
    data = np.full((60, 80), CellState.FREE, np.int8)
    data[[0, -1], :] = CellState.OCCUPIED
    data[:, [0, -1]] = CellState.OCCUPIED
    data[20, :] = CellState.OCCUPIED
    for wall in (27, 54):
        data[20:, wall] = CellState.OCCUPIED
    for door in (10, 40, 66):
        data[20, door : door + 8] = CellState.FREE
    return OccupancyGrid(data, 0.05)


def _world() -> World:
    return make_world(_rooms(), "rooms", start=Pose(0.5, 0.5, 0.0))


def test_teacher_leaves_the_simulator_as_it_was_and_is_never_slower_than_greedy() -> None:
    sim = ExplorationSimulator(_world(), rng=np.random.default_rng(3))
    checked = 0
    while not sim.finished and not sim.truncated and checked < 6:
        before = (sim.sim_time, sim.pose, sim.coverage)
        slot = lookahead_slot(sim, TOP_K)
        assert (sim.sim_time, sim.pose, sim.coverage) == before
        n = len(cheapest_slots(sim, TOP_K))
        assert 0 <= slot < max(n, 1)
        assert lookahead_slot(sim, TOP_K, width=1) == 0
        ends = []
        for choice in (0, slot):  # a copy replays the same noise: the teacher's pick finishes no later
            trial = copy.deepcopy(sim)
            take_slot(trial, choice, TOP_K)
            ends.append(greedy_finish(trial, TOP_K))
        assert ends[1] <= ends[0]
        take_slot(sim, slot, TOP_K)
        checked += 1
    assert checked == 6


def test_teacher_names_another_slot_only_past_its_margin() -> None:
    sim = ExplorationSimulator(_world(), rng=np.random.default_rng(5))
    for _ in range(4):
        ends = []
        for slot in range(min(LOOKAHEAD_WIDTH, len(cheapest_slots(sim, TOP_K)))):
            trial = copy.deepcopy(sim)
            take_slot(trial, slot, TOP_K)
            ends.append(greedy_finish(trial, TOP_K))
        for margin in (0.0, 0.02, 0.5):
            faster = [i for i in range(1, len(ends)) if ends[i] < ends[0] * (1 - margin)]
            want = min(faster, key=lambda i: (ends[i], i)) if faster else 0
            assert lookahead_slot(sim, TOP_K, margin=margin) == want
        take_slot(sim, 0, TOP_K)
    with pytest.raises(ValueError, match="margin"):
        lookahead_slot(sim, TOP_K, margin=1.0)


def test_greedy_finish_gives_up_past_its_bound() -> None:
    sim = ExplorationSimulator(_world(), rng=np.random.default_rng(0))
    assert greedy_finish(copy.deepcopy(sim), TOP_K, bound_s=1.0) == float("inf")
    end = greedy_finish(sim, TOP_K)
    assert np.isfinite(end) and end == sim.sim_time


def _config(map_file: Path, **changes: object) -> TrainConfig:
    values: dict[str, object] = {
        "model": 5, "algo": "dagger", "worlds": str(map_file), "timesteps": 24, "n_envs": 1,
        "observation_size": 64, "eval_every": 12, "eval_episodes": 1, "checkpoint_every": 12, "max_decisions": 24,
    }  # fmt: skip
    values.update(changes)
    return TrainConfig(**values)  # type: ignore[arg-type]


@pytest.fixture(scope="module")
def map_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return save_ros_map(_rooms(), tmp_path_factory.mktemp("map") / "rooms.yaml")


def test_fit_learns_the_labels(map_file: Path, tmp_path: Path) -> None:
    env = FrontierChoiceEnv(worlds=(str(map_file),), observation_size=64)
    model = build_model(_config(map_file), env, tmp_path)
    data = LabelledDecisions()
    obs, _ = env.reset(seed=0)
    for _ in range(8):  # label the last filled slot, which no untrained scorer prefers by chance everywhere
        n = int(obs["mask"].sum())
        data.add({k: v[None] for k, v in obs.items()}, np.array([n - 1]))
        obs, _, done, cut, _ = env.step(0)
        if done or cut:
            obs, _ = env.reset(seed=1)
    rng = np.random.default_rng(0)
    optimizer = torch.optim.Adam(model.policy.parameters(), lr=3e-3)
    first = fit(model, data, rng, optimizer)
    for _ in range(30):
        last = fit(model, data, rng, optimizer)
    assert last < 0.5 * first
    stacked, labels = data.arrays()
    assert data.not_cheapest() == pytest.approx(float(np.mean(labels != 0)))
    predicted, _ = model.policy.predict(stacked, deterministic=True)  # type: ignore[arg-type]
    assert (np.asarray(predicted) == labels).mean() >= 0.9


def test_dagger_run_writes_a_model_that_explores(map_file: Path, tmp_path: Path) -> None:
    run = tmp_path / "dagger"
    final = train(_config(map_file), run, progress=False)
    info = read_metadata(final)
    assert info is not None and info.algo == "dagger" and info.model == 5 and info.timesteps >= 24
    assert (run / "validation.csv").read_text().count("\n") == 3  # header + 2 validations
    assert (run / "best_model.zip").exists() and (run / "learning_curve.png").exists()
    from frontier_rl.core.sim.episode import run_episode

    result = run_episode(_world(), make_policy(f"learned:{final}"), seed=0)
    assert result.end_reason == "explored"
    with pytest.raises(ConfigError, match="cannot be resumed"):
        train(_config(map_file), run, resume=True, progress=False)


def test_dagger_is_for_model_5_only() -> None:
    with pytest.raises(ConfigError, match="model 5"):
        TrainConfig(model=4, algo="dagger")
