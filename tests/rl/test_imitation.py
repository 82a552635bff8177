"""DAgger for models 5 and 7 (``train --algo dagger``); the teachers are tested in tests/rl/test_teacher.py."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import torch
from stable_baselines3.common.callbacks import BaseCallback
from stable_baselines3.common.logger import Logger
from stable_baselines3.common.vec_env import DummyVecEnv, VecEnv, VecEnvWrapper
from stable_baselines3.common.vec_env.base_vec_env import VecEnvObs, VecEnvStepReturn

from frontier_rl.envs.frontier_env import FrontierChoiceEnv
from frontier_rl.errors import ConfigError
from frontier_rl.inference.model_file import read_metadata
from frontier_rl.io.ros_map import save_ros_map
from frontier_rl.policies import make_policy
from frontier_rl.rl import imitation
from frontier_rl.rl.config import TrainConfig
from frontier_rl.rl.imitation import LabelledDecisions, fit
from frontier_rl.rl.teacher import TeacherLabels
from frontier_rl.rl.train import build_model, train
from tests.rl.test_teacher import _rooms, _world

pytestmark = pytest.mark.slow  # training runs with a lookahead teacher


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


def test_fit_learns_the_labels(map_file: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(imitation, "EPOCHS", 10)
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
    data.save(tmp_path / "labels.npz")
    with np.load(tmp_path / "labels.npz", allow_pickle=False) as saved:
        assert sorted(saved.files) == sorted(["labels", *(f"obs_{k}" for k in stacked)])
        assert np.array_equal(saved["labels"], labels)
        assert all(np.array_equal(saved[f"obs_{k}"], v) for k, v in stacked.items())
    predicted, _ = model.policy.predict(stacked, deterministic=True)  # type: ignore[arg-type]
    assert (np.asarray(predicted) == labels).mean() >= 0.9


class _Stop(BaseCallback):
    """Asks the run to stop once ``at`` decisions are labelled; notes the training end."""

    def __init__(self, at: int) -> None:
        super().__init__()
        self.at = at
        self.ended = False

    def _on_step(self) -> bool:
        return self.num_timesteps < self.at

    def _on_training_end(self) -> None:
        self.ended = True


class _Spy(VecEnvWrapper):
    """Records the teacher's labels and the actions driven, per vectorised step."""

    def __init__(self, venv: VecEnv) -> None:
        super().__init__(venv)
        self.labels: list[list[int]] = []
        self.actions: list[list[int]] = []

    def env_method(self, name: str, *args: object, indices: object = None, **kwargs: object) -> list[object]:
        answer = self.venv.env_method(name, *args, indices=indices, **kwargs)  # type: ignore[arg-type]
        self.labels.append([int(a) for a in answer])  # type: ignore[call-overload]
        return answer

    def step_async(self, actions: np.ndarray) -> None:
        self.actions.append([int(a) for a in actions])
        self.venv.step_async(actions)

    def step_wait(self) -> VecEnvStepReturn:
        return self.venv.step_wait()

    def reset(self) -> VecEnvObs:
        return self.venv.reset()


def test_dagger_rounds_teacher_schedule_and_callbacks(
    map_file: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(imitation, "ROUND_DECISIONS", 8)
    monkeypatch.setattr(imitation, "TEACHER_DECAY", 0.0)  # the teacher drives round 0 only
    monkeypatch.setattr(imitation, "EPOCHS", 2)  # the rounds are tested here, not the fit (its own test)
    config = _config(map_file, n_envs=2)
    venv = _Spy(DummyVecEnv([lambda: TeacherLabels(FrontierChoiceEnv(worlds=(str(map_file),), max_decisions=24))] * 2))
    model = build_model(config, venv, tmp_path)
    model.set_logger(Logger(folder=None, output_formats=[]))  # configure(None) makes a folder in /tmp
    losses = imitation.dagger(model, venv, 32, 1e-3, progress=False)
    assert len(losses) == 4 and all(np.isfinite(losses)) and model.num_timesteps == 32
    assert venv.actions[:4] == venv.labels[:4]  # round 0: 4 steps of 2 envs, the teacher's labels
    model = build_model(config, venv, tmp_path)
    model.set_logger(Logger(folder=None, output_formats=[]))
    stop = _Stop(12)
    losses = imitation.dagger(model, venv, 32, 1e-3, callbacks=[stop], progress=False)
    assert model.num_timesteps == 12 and len(losses) == 1 and stop.ended


@pytest.mark.parametrize("model", [5, 7])
def test_dagger_run_writes_a_model_that_explores(map_file: Path, tmp_path: Path, model: int) -> None:
    run = tmp_path / "dagger"
    # subprocess envs: the teacher over pipes
    final = train(_config(map_file, n_envs=2, model=model), run, progress=False)
    info = read_metadata(final)
    assert info is not None and info.algo == "dagger" and info.model == model and info.timesteps >= 24
    assert (run / "validation.csv").read_text().count("\n") == 3  # header + 2 validations
    assert (run / "best_model.zip").exists() and (run / "learning_curve.png").exists()
    with np.load(run / "labels.npz", allow_pickle=False) as saved:
        assert len(saved["labels"]) == 24
    from frontier_rl.core.sim.episode import run_episode

    result = run_episode(_world(), make_policy(f"learned:{final}"), seed=0)
    assert result.end_reason == "explored"
    with pytest.raises(ConfigError, match="cannot be resumed"):
        train(_config(map_file), run, resume=True, progress=False)


@pytest.mark.parametrize("model", [1, 4, 6])
def test_dagger_is_for_the_frontier_choice_models_only(model: int) -> None:
    with pytest.raises(ConfigError, match="models 5 and 7"):
        TrainConfig(model=model, algo="dagger")
