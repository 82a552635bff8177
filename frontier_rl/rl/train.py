"""``frontier-rl train``: Stable-Baselines3 A2C (or PPO, or DAgger for model 5) on a frontier_rl env, resumable.

A run directory holds ``model.zip`` (the final model), ``best_model.zip`` (best on the validation
worlds), ``monitor_<start>.monitor.csv`` (one per started segment), ``validation.csv``, ``tb/``
(TensorBoard) and ``learning_curve.png``, beside what :mod:`frontier_rl.rl.run_folder` keeps (the
configuration, the map files, the checkpoints).
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable, Sequence
from dataclasses import replace
from functools import partial
from pathlib import Path
from typing import Any

import gymnasium as gym
import torch
from stable_baselines3.common.base_class import BaseAlgorithm
from stable_baselines3.common.callbacks import BaseCallback
from stable_baselines3.common.logger import configure as configure_logger
from stable_baselines3.common.policies import ActorCriticPolicy
from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv, VecEnv, VecMonitor

import frontier_rl.envs
from frontier_rl.envs.world_source import check_world_files
from frontier_rl.errors import ConfigError, short_path
from frontier_rl.inference.model_file import ModelInfo, read_metadata
from frontier_rl.registration import Algorithm
from frontier_rl.rl.callbacks import AtomicCheckpoint, ValidationCallback
from frontier_rl.rl.config import TrainConfig
from frontier_rl.rl.curves import MONITOR_KEYWORDS, monitor_prefix, plot_learning_curve
from frontier_rl.rl.imitation import dagger
from frontier_rl.rl.model_file import (
    SB3_ALGORITHMS,
    check_finite_weights,
    check_model_zip,
    load_policy,
    policy_setup,
    save_model,
)
from frontier_rl.rl.networks import PRIVILEGED_HEAD
from frontier_rl.rl.run_folder import (
    FINAL_MODEL_NAME,
    keep_final_checkpoint,
    latest_checkpoint,
    prepare_run_folder,
    record_timesteps,
)
from frontier_rl.rl.teacher import TeacherLabels
from frontier_rl.rl.validation_log import VALIDATION_FILE
from frontier_rl.worker_signals import ignore_interrupts, spawning_workers
from frontier_rl.world_spec import world_entries


def make_env(env_id: str, **kwargs: Any) -> gym.Env[Any, Any]:
    """``gymnasium.make`` after registering the frontier_rl ids: picklable by reference, so that
    subprocess environments can build it in a fresh interpreter."""
    frontier_rl.envs.register_envs()
    return gym.make(env_id, **kwargs)


def make_labelled_env(env_id: str, **kwargs: Any) -> gym.Env[Any, Any]:
    """:func:`make_env` with its teacher's labels (:class:`~frontier_rl.rl.teacher.TeacherLabels`), for DAgger."""
    return TeacherLabels(make_env(env_id, **kwargs))


def build_model(config: TrainConfig, env: object, out: Path) -> BaseAlgorithm:
    """The SB3 algorithm for ``config`` on vectorised ``env``."""
    policy_cls, policy_kwargs = policy_setup(config.model, config.features_dim)
    common = {
        "learning_rate": config.learning_rate,
        "n_steps": config.n_steps,
        "gamma": config.gamma,
        "vf_coef": config.vf_coef,
        "ent_coef": config.ent_coef,
        "policy_kwargs": policy_kwargs,
        "tensorboard_log": str(out / "tb"),
        "seed": config.seed,
        "device": "cpu",
        "verbose": 0,
    }
    if config.algo is Algorithm.PPO:
        common["batch_size"] = min(64, config.n_steps * config.n_envs)
    return SB3_ALGORITHMS[config.algo](policy_cls, env, **common)  # type: ignore[arg-type]


WORKER_END_S = 5.0
"""How long an ended training worker is waited for (s)."""


def _worker_env(factory: Callable[..., gym.Env[Any, Any]], env_id: str, **kwargs: Any) -> gym.Env[Any, Any]:
    """A training env in a worker process, which leaves Ctrl-C to the run (a terminal sends it to
    every process of the group: a worker interrupted in a kernel printed a traceback, and the run
    ended with "aborted" on the broken pipe, not with its checkpoint's line)."""
    ignore_interrupts()
    return factory(env_id, **kwargs)


def _end_workers(venv: VecEnv) -> None:
    """End the training envs' worker processes at once, after an interrupt or an error: a Ctrl-C
    that cut a step's answer mid-message leaves the pipe out of step, and SB3's close waited on it
    for good (a run interrupted at the wrong moment hung)."""
    envs = venv.unwrapped
    if not isinstance(envs, SubprocVecEnv) or envs.closed:
        return
    for process in envs.processes:
        process.terminate()
    for process in envs.processes:
        process.join(WORKER_END_S)
    for remote in envs.remotes:
        remote.close()
    envs.closed = True


def _training_envs(config: TrainConfig, out: Path, start: int, env_kwargs: dict[str, Any]) -> VecMonitor:
    """``config.n_envs`` training envs (spawned worker processes when more than one), logged to ``out``."""
    factory = make_labelled_env if config.algo is Algorithm.DAGGER else make_env
    if config.n_envs == 1:
        envs: VecEnv = DummyVecEnv([partial(factory, config.env_id, **env_kwargs)])
    else:
        # worlds none of whose draws can start: one line from here, not a worker's traceback and a broken pipe
        with contextlib.closing(make_env(config.env_id, **env_kwargs)) as probe:
            probe.reset(seed=config.seed)
        with spawning_workers():  # started with Ctrl-C held, which each ignores once it runs
            envs = SubprocVecEnv(
                [partial(_worker_env, factory, config.env_id, **env_kwargs) for _ in range(config.n_envs)],
                start_method="spawn",
            )
    return VecMonitor(envs, str(out / monitor_prefix(start)), info_keywords=MONITOR_KEYWORDS)


def _restore_checkpoint(model: BaseAlgorithm, config: TrainConfig, out: Path, start: int) -> None:
    """Load the last checkpoint of ``out`` (``start`` steps) into ``model``: weights and optimizer,
    no unpickling, the file's size bounded before SB3 reads it.

    The random generators (the envs', torch's, numpy's) are seeded with ``config.seed + start``
    (modulo 2³²): the model, built with ``config.seed``, seeds the envs as the run's start did, and a
    resumed run replayed the worlds and starts of its opening episodes."""
    checkpoint = latest_checkpoint(out)
    assert checkpoint is not None
    check_model_zip(checkpoint[0])
    model.set_parameters(str(checkpoint[0]), device="cpu")
    model.num_timesteps = start
    model.set_random_seed((config.seed + start) % 2**32)  # NumPy's seeds stop at 2**32 - 1


def _initial_policy(config: TrainConfig) -> ActorCriticPolicy:
    """The policy of model file ``config.init`` (read without unpickling,
    :func:`~frontier_rl.rl.model_file.load_policy`), checked to be the kind this run trains."""
    where = f"init {short_path(config.init)}"
    if read_metadata(config.init) is None:
        raise ConfigError(f"{where} was not written by 'frontier-rl train'; only such files start a run")
    policy, info = load_policy(config.init)
    assert info is not None
    ours = (config.model, config.env_id, config.features_dim)
    theirs = (info.model, info.env_id, info.features_dim)
    if theirs != ours:
        raise ConfigError(
            f"{where} holds model {info.model} on {info.env_id} with features_dim "
            f"{info.features_dim}; this run trains model {config.model} on {config.env_id} with {config.features_dim}"
        )
    return policy


def _load_initial(policy: torch.nn.Module, initial: torch.nn.Module) -> None:
    """Start ``policy`` from ``initial``'s weights; a model file has no privileged value head, so
    a privileged critic's head (alone) keeps its fresh weights."""
    result = policy.load_state_dict(initial.state_dict(), strict=False)
    fresh = [key for key in result.missing_keys if not key.startswith(f"{PRIVILEGED_HEAD}.")]
    if fresh or result.unexpected_keys:  # _initial_policy checked the kind, so this is a bug
        raise RuntimeError(f"--init does not fit: missing {fresh}, unexpected {result.unexpected_keys}")


def _start(config: TrainConfig, out: Path, resume: bool) -> tuple[int, ActorCriticPolicy | None]:
    """The step to start from and the ``--init`` policy to start with, if any; a bad map file or
    ``--init`` fails before the run directory is written or a subprocess started, and a resumed
    run that has a checkpoint never reads ``--init``."""
    maps = check_world_files(world_entries(config.worlds), config.resolution)
    initial = _initial_policy(config) if config.init and not resume else None
    start = prepare_run_folder(config, out, resume, maps)
    if config.init and resume and not start:
        initial = _initial_policy(config)
    return start, initial


def _learn(
    model: BaseAlgorithm,
    venv: VecEnv,
    config: TrainConfig,
    out: Path,
    start: int,
    callbacks: list[BaseCallback],
    progress: bool,
) -> None:
    """Run the configured algorithm from step ``start`` to ``config.timesteps``; a run whose
    weights stop being finite ends with :class:`~frontier_rl.errors.TrainingDivergedError` (the
    distribution of its next decision refuses their NaN logits with a ValueError)."""
    try:
        _run_algorithm(model, venv, config, out, start, callbacks, progress)
    except ValueError:
        check_finite_weights(model)
        raise


def _run_algorithm(
    model: BaseAlgorithm,
    venv: VecEnv,
    config: TrainConfig,
    out: Path,
    start: int,
    callbacks: list[BaseCallback],
    progress: bool,
) -> None:
    """Run the configured algorithm from step ``start`` to ``config.timesteps``."""
    if config.algo is Algorithm.DAGGER:
        model.set_logger(configure_logger(str(out / "tb" / "dagger"), ["tensorboard"]))
        labels = out / "labels.npz"
        dagger(model, venv, config.timesteps, config.learning_rate, callbacks, config.seed, progress, labels)
        return
    model.learn(
        total_timesteps=max(config.timesteps - start, 0),
        callback=callbacks,
        progress_bar=progress,
        reset_num_timesteps=start == 0,
        tb_log_name=config.algo.value,
    )


def _env_kwargs(config: TrainConfig) -> dict[str, Any]:
    """The keyword arguments of every env the run makes, training and validation."""
    env_kwargs: dict[str, Any] = {"worlds": config.worlds, "reward": config.reward}
    env_kwargs["max_decisions"] = config.max_decisions
    env_kwargs["sim"] = config.sim
    if config.resolution is not None:
        env_kwargs["resolution"] = config.resolution
    if config.privileged_critic:
        env_kwargs["privileged"] = True
    if config.privileged_map:
        env_kwargs["privileged_map"] = True
    return env_kwargs


def _callbacks(
    config: TrainConfig, out: Path, env_kwargs: dict[str, Any], info: ModelInfo
) -> tuple[list[BaseCallback], gym.Env[Any, Any] | None]:
    """The run's checkpoints and validations (with ``info``, the metadata of its best model), and the
    validation env to close at the end (None without validations)."""
    callbacks: list[BaseCallback] = []
    if config.checkpoint_every:
        every = max(config.checkpoint_every // config.n_envs, 1)
        callbacks.append(AtomicCheckpoint(every, out / "checkpoints"))
    if not config.eval_every:
        return callbacks, None
    eval_env = gym.make(config.env_id, **env_kwargs, world_split="validation")
    csv_path, best_path = out / VALIDATION_FILE, out / "best_model.zip"
    callbacks.append(ValidationCallback(eval_env, config.eval_every, config.eval_episodes, csv_path, best_path, info))
    return callbacks, eval_env


def train(
    config: TrainConfig,
    out: Path,
    resume: bool = False,
    progress: bool = True,
    extra_callbacks: Sequence[BaseCallback] = (),
) -> Path:
    """Train as ``config`` says into run directory ``out``; returns the final model's path.

    With ``resume``, a run in ``out`` continues from its last checkpoint (weights, optimizer state
    and step count); its configuration and map files must be the same, but for ``timesteps``
    (:func:`~frontier_rl.rl.run_folder.prepare_run_folder`). ``extra_callbacks`` run after the
    checkpoint and validation callbacks.
    """
    if resume and config.algo is Algorithm.DAGGER:
        raise ConfigError("a dagger run cannot be resumed: its labelled decisions are not checkpointed")
    start, initial = _start(config, out, resume)
    final = out / FINAL_MODEL_NAME
    finished = read_metadata(final) if resume and final.is_file() else None
    if finished is not None and finished.timesteps >= config.timesteps:
        return final  # nothing left to train: the model file, and the evaluations that hash it, stay as they are
    frontier_rl.envs.register_envs()
    env_kwargs = _env_kwargs(config)
    venv = _training_envs(config, out, start, env_kwargs)
    model = build_model(config, venv, out)
    if start:
        _restore_checkpoint(model, config, out, start)
    elif initial is not None:
        _load_initial(model.policy, initial)
    info = ModelInfo(config.model, config.env_id, config.observation_size, config.algo, config.features_dim, 0)
    callbacks, eval_env = _callbacks(config, out, env_kwargs, info)
    callbacks.extend(extra_callbacks)
    torch.set_num_threads(1 if config.n_envs > 1 else torch.get_num_threads())
    started = time.perf_counter()
    try:
        _learn(model, venv, config, out, start, callbacks, progress)
    except BaseException:
        _end_workers(venv)
        raise
    finally:
        venv.close()
        if eval_env is not None:
            eval_env.close()
        with (out / "training_time.txt").open("a") as sink:  # every segment, an interrupted one too
            sink.write(f"steps {start}..{model.num_timesteps}: {time.perf_counter() - started:.1f} s wall\n")
    save_model(model, final, replace(info, timesteps=int(model.num_timesteps)))
    record_timesteps(config, out)
    if config.checkpoint_every and config.algo is not Algorithm.DAGGER:
        keep_final_checkpoint(model, out)
    plot_learning_curve(out, title=f"model {config.model} ({config.algo.value}, {config.worlds})")
    return final
