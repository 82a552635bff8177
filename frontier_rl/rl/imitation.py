"""Imitation of a privileged lookahead teacher (DAgger) for models 5 and 7: ``train --algo dagger``.

DAgger (Ross et al., AISTATS 2011) in rounds of :data:`ROUND_DECISIONS` decisions: the env's
teacher (:func:`~frontier_rl.rl.teacher.expert_action`, asked through
:class:`~frontier_rl.rl.teacher.TeacherLabels`; it tries frontiers on copies of the simulator:
model 5's the cheapest ones, finished greedily; model 7's the stops of the ``tour`` policy,
finished with it) labels every decision, naming another frontier than its base policy's only when
that saves more than its margin; in round r the teacher's own choice is driven with probability
``0.5 ** r`` and the learner's otherwise, so later rounds label the states the learner
reaches. After each round the policy's frontier scores are fitted to all labels so far by
cross-entropy (:data:`EPOCHS` passes, minibatches of :data:`BATCH`, Adam at the run's learning rate).
The data set lives in memory, so a DAgger run cannot be resumed from a checkpoint.
"""

from __future__ import annotations

import io
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import torch
from numpy.typing import NDArray
from rich.console import Console
from rich.progress import Progress
from stable_baselines3.common.base_class import BaseAlgorithm
from stable_baselines3.common.callbacks import BaseCallback, CallbackList
from stable_baselines3.common.distributions import CategoricalDistribution
from stable_baselines3.common.policies import ActorCriticPolicy
from stable_baselines3.common.vec_env import VecEnv

from frontier_rl.atomic_write import write_bytes_atomic

ROUND_DECISIONS = 512
"""Decisions labelled between two fits of the policy."""

EPOCHS = 50
"""Passes over the whole data set after each round: the pointer network's scores move slowly, and
10 passes at 10⁻³ left it far from even a constant label (cross-entropy 1.7 nats on 512 decisions
all labelled "cheapest"; 50 passes at 3·10⁻³: 0.21). Fitting is cheap beside labelling (13 s
per 512 decisions here)."""

BATCH = 64
"""Minibatch size of a fit (decisions)."""

TEACHER_DECAY = 0.5
"""The teacher drives round r's decisions with probability TEACHER_DECAY ** r."""


class LabelledDecisions:
    """The decisions seen so far (observations, one dict of arrays) and the teacher's actions."""

    def __init__(self) -> None:
        self._obs: dict[str, list[NDArray[Any]]] = {}
        self._labels: list[NDArray[np.int64]] = []

    def __len__(self) -> int:
        return int(sum(len(labels) for labels in self._labels))

    def add(self, obs: dict[str, NDArray[Any]], labels: NDArray[np.int64]) -> None:
        """Append a vectorised step: ``obs`` of the envs and the teacher's ``labels``."""
        for key, value in obs.items():
            self._obs.setdefault(key, []).append(np.array(value, copy=True))
        self._labels.append(np.asarray(labels, np.int64).copy())

    def not_cheapest(self) -> float:
        """Share of the labels that name another frontier than the cheapest (slot 0)."""
        return float(np.mean(np.concatenate(self._labels) != 0)) if self._labels else 0.0

    def save(self, path: Path) -> None:
        """Write every decision to ``path``, an uncompressed ``.npz`` (``labels`` and ``obs_KEY``
        per observation key), whole or not at all; ``numpy.load`` reads it without unpickling."""
        obs, labels = self.arrays()
        buffer = io.BytesIO()
        arrays: dict[str, Any] = {"labels": labels, **{f"obs_{key}": value for key, value in obs.items()}}
        np.savez(buffer, **arrays)
        write_bytes_atomic(path, buffer.getvalue())

    def arrays(self) -> tuple[dict[str, NDArray[Any]], NDArray[np.int64]]:
        """All observations (stacked per key) and labels."""
        return {k: np.concatenate(v) for k, v in self._obs.items()}, np.concatenate(self._labels)


def fit(
    model: BaseAlgorithm, data: LabelledDecisions, rng: np.random.Generator, optimizer: torch.optim.Optimizer
) -> float:
    """:data:`EPOCHS` passes of cross-entropy between the policy's action logits and the labels,
    with ``optimizer`` (over the policy's parameters); returns the last pass's mean loss."""
    policy = model.policy
    assert isinstance(policy, ActorCriticPolicy)
    obs, labels = data.arrays()
    policy.set_training_mode(True)
    loss_sum, count = 0.0, 0
    for _ in range(EPOCHS):
        loss_sum, count = 0.0, 0
        order = rng.permutation(len(labels))
        for start in range(0, len(order), BATCH):
            pick = order[start : start + BATCH]
            batch, _ = policy.obs_to_tensor({k: v[pick] for k, v in obs.items()})
            distribution = policy.get_distribution(batch)
            assert isinstance(distribution, CategoricalDistribution)
            logits = distribution.distribution.logits
            loss = torch.nn.functional.cross_entropy(logits, torch.as_tensor(labels[pick]))
            optimizer.zero_grad()
            loss.backward()  # type: ignore[no-untyped-call]
            torch.nn.utils.clip_grad_norm_(policy.parameters(), 0.5)
            optimizer.step()
            loss_sum += float(loss.detach()) * len(pick)
            count += len(pick)
    policy.set_training_mode(False)
    return loss_sum / max(count, 1)


def _fit_round(
    model: BaseAlgorithm, data: LabelledDecisions, rng: np.random.Generator, optimizer: torch.optim.Optimizer
) -> float:
    """Fit the policy to every label so far (:func:`fit`) and record the round for the logger."""
    loss = fit(model, data, rng, optimizer)
    model.logger.record("dagger/loss", loss)
    model.logger.record("dagger/decisions", len(data))
    model.logger.record("dagger/not_cheapest", data.not_cheapest())
    return loss


def dagger(
    model: BaseAlgorithm,
    venv: VecEnv,
    timesteps: int,
    learning_rate: float,
    callbacks: Sequence[BaseCallback] = (),
    seed: int = 0,
    progress: bool = True,
    labels_path: Path | None = None,
) -> list[float]:
    """Train ``model``'s policy by DAgger on ``venv`` (FrontierChoice envs in
    :class:`~frontier_rl.rl.teacher.TeacherLabels`, whose ``expert_action`` is the teacher) for
    ``timesteps`` labelled decisions, Adam at ``learning_rate``; returns each round's loss. The
    ``callbacks`` (checkpoints, validation) get SB3's training start, a step after every vectorised
    step (one that returns False stops the run, as in ``learn``) and training end;
    ``model.num_timesteps`` counts the decisions labelled. With ``labels_path``, every labelled
    decision is saved there after each round (:meth:`LabelledDecisions.save`), to fit other
    students to offline."""
    rng = np.random.default_rng(seed)
    optimizer = torch.optim.Adam(model.policy.parameters(), lr=learning_rate)
    data = LabelledDecisions()
    callback = CallbackList(list(callbacks))
    callback.init_callback(model)
    callback.on_training_start(locals(), globals())
    obs = venv.reset()
    losses: list[float] = []
    with Progress(console=Console(stderr=True), disable=not progress) as bar:
        task = bar.add_task("DAgger decisions", total=timesteps)
        while model.num_timesteps < timesteps:
            teacher_share = TEACHER_DECAY ** (model.num_timesteps // ROUND_DECISIONS)
            labels = np.asarray(venv.env_method("expert_action"), np.int64)
            data.add(obs, labels)  # type: ignore[arg-type]
            learner, _ = model.policy.predict(obs, deterministic=True)  # type: ignore[arg-type]
            teacher_drives = rng.random(venv.num_envs) < teacher_share
            obs, _, _, _ = venv.step(np.where(teacher_drives, labels, np.asarray(learner, np.int64)))
            before = model.num_timesteps
            model.num_timesteps += venv.num_envs
            if model.num_timesteps // ROUND_DECISIONS > before // ROUND_DECISIONS or model.num_timesteps >= timesteps:
                losses.append(_fit_round(model, data, rng, optimizer))
                callback.on_rollout_start()  # as SB3 after an update: the weights learnt from every decision so far
                if labels_path is not None:
                    data.save(labels_path)
            go_on = callback.on_step()
            if model.logger.name_to_value:  # the round's records, the callbacks' (validation)
                model.logger.dump(model.num_timesteps)
            bar.update(task, completed=model.num_timesteps)
            if not go_on:
                break
    callback.on_training_end()
    return losses
