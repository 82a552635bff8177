"""Training callbacks: evaluation on held-out validation worlds."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
from stable_baselines3.common.callbacks import BaseCallback

from frontier_rl.envs.world_source import VALIDATION_SEED_LOW
from frontier_rl.inference.model_file import ModelInfo, checkpoint_name
from frontier_rl.rl.model_file import save_model
from frontier_rl.rl.validation_log import Validation, append_validation, read_validations


def run_validation(env: gym.Env[Any, Any], predict: Any, episodes: int) -> list[float]:
    """Exploration time (s) of ``episodes`` deterministic episodes on validation worlds
    ``VALIDATION_SEED_LOW + k``; ``predict(obs) -> action``."""
    times = []
    for k in range(episodes):
        obs, info = env.reset(seed=k, options={"world_seed": VALIDATION_SEED_LOW + k})
        terminated = truncated = False
        while not (terminated or truncated):
            obs, _, terminated, truncated, info = env.step(predict(obs))
        times.append(float(info["sim_time_s"]))
    return times


class ValidationCallback(BaseCallback):
    """Every ``every`` decisions, explore ``episodes`` validation worlds with the deterministic
    policy; log the mean time to TensorBoard and ``csv_path``, and save the best model.

    Args:
        env: an environment like the training ones (not vectorised).
        every: decisions between validations.
        episodes: validation worlds per validation.
        csv_path: where rows ``timesteps, mean_time_s, times`` are appended.
        best_path: where the model with the lowest mean time is saved.
        info: the run's model-file metadata, saved with it (its ``timesteps`` the decisions the best
            weights learnt from), so that the best model is a model file even if the run never finishes.
    """

    def __init__(
        self, env: gym.Env[Any, Any], every: int, episodes: int, csv_path: Path, best_path: Path, info: ModelInfo
    ) -> None:
        super().__init__()
        self.info = info
        self.env = env
        self.every = every
        self.episodes = episodes
        self.csv_path = csv_path
        self.best_path = best_path
        self.best = float("inf")
        self._next = 0
        self._trained = 0  # the decisions the weights have learnt from

    def _on_training_start(self) -> None:
        self._trained = self.num_timesteps  # a resumed run's checkpoint
        last = 0  # the decisions of the last validation written
        if validations := read_validations(self.csv_path):  # a resumed run: keep the best so far
            self.best = min(v.mean_time_s for v in validations)
            last = max(v.timesteps for v in validations)
        # The next validation due; a resumed run's first step makes up for one that an interrupt cut
        # short after the checkpoint it resumes from was written.
        self._next = min(self.num_timesteps // self.every + 1, last // self.every + 1) * self.every

    def _on_step(self) -> bool:
        if self.num_timesteps < self._next:
            return True
        self._next = (self.num_timesteps // self.every + 1) * self.every  # one make-up validation, not a burst
        times = run_validation(self.env, lambda obs: self.model.predict(obs, deterministic=True)[0], self.episodes)
        mean = float(np.mean(times))
        self.logger.record("eval/mean_time_s", mean)
        append_validation(self.csv_path, Validation(self.num_timesteps, mean, tuple(times)))
        if mean < self.best:
            self.best = mean
            save_model(self.model, self.best_path, replace(self.info, timesteps=self._trained_decisions()))
        return True

    def _on_rollout_start(self) -> None:
        """The weights were just updated (SB3 starts a rollout after each update; DAgger calls this
        after each fit) on the decisions made so far."""
        self._trained = self.num_timesteps

    def _trained_decisions(self) -> int:
        """The decisions the policy's weights have learnt from: a validation inside an A2C or PPO
        rollout runs the weights of the last update, before the rollout's own decisions (the final
        model, saved after that update, has learnt from them; both said the same count)."""
        return self._trained


class AtomicCheckpoint(BaseCallback):
    """SB3's ``CheckpointCallback`` (``model_<steps>_steps.zip`` in ``folder`` every ``every``
    calls), each file written whole or not at all: a checkpoint cut short by a full disk would be
    the newest, the one ``train --resume`` continues from."""

    def __init__(self, every: int, folder: Path) -> None:
        super().__init__()
        self.every = every
        self.folder = folder

    def _init_callback(self) -> None:
        self.folder.mkdir(parents=True, exist_ok=True)

    def _on_step(self) -> bool:
        if self.n_calls % self.every == 0:
            save_model(self.model, self.folder / checkpoint_name(self.num_timesteps))
        return True
