"""``frontier-rl train``: a model trained with Stable-Baselines3 (the ``rl`` extra: torch loads only here)."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Annotated

import typer

from frontier_rl.cli.options import ResolutionOption, SimConfigOption, checked_run_arguments, sim_config
from frontier_rl.cli.output import friendly_errors, print_line, print_note
from frontier_rl.errors import ConfigError
from frontier_rl.registration import Algorithm

TRAINING_PACKAGES = frozenset({"torch", "stable_baselines3"})
"""The packages of the ``rl`` extra that training imports."""

PrivilegedCriticOption = Annotated[
    bool, typer.Option(help="Models 5 and 7: the critic also reads the true map's unseen share (training only).")
]
PrivilegedMapOption = Annotated[
    bool, typer.Option(help="With --privileged-critic: it also sees the true map's unseen space as an image.")
]


@contextmanager
def _needs_rl_extra() -> Iterator[None]:
    """A one-line error naming the package of the ``rl`` extra that an import in it misses."""
    try:
        yield
    except ImportError as error:
        package = (error.name or "").split(".")[0]
        if package not in TRAINING_PACKAGES:
            raise
        raise ConfigError(f"training needs {package}, which is not installed: pip install 'frontier_rl[rl]'") from None


@friendly_errors
def train(
    out: Annotated[Path, typer.Option(help="Run directory: config, checkpoints, logs, model.zip, learning curve.")],
    model: Annotated[int, typer.Option(help="Model: 1, 2 (point), 3, 4, 6 (weight), 5, 7 (frontier).")] = 4,
    worlds: Annotated[str, typer.Option(help="Generators, files, folders, catalogue maps, each [=WEIGHT].")] = "office",
    timesteps: Annotated[int, typer.Option(help="Decisions to train for.")] = 100_000,
    n_envs: Annotated[int, typer.Option(help="Parallel environments (subprocesses).")] = 2,
    algo: Annotated[Algorithm, typer.Option(help="a2c (the thesis), ppo or dagger (models 5 and 7).")] = Algorithm.A2C,
    observation_size: Annotated[int, typer.Option(help="Map image edge: 64 or 250 pixels.")] = 64,
    reward: Annotated[str, typer.Option(help="Reward preset: normalised or thesis.")] = "normalised",
    learning_rate: Annotated[float, typer.Option(help="Optimizer step size.")] = 7e-4,
    n_steps: Annotated[int, typer.Option(help="Decisions per env between updates.")] = 8,
    gamma: Annotated[float, typer.Option(help="Discount per decision, in (0, 1].")] = 0.99,
    ent_coef: Annotated[float, typer.Option(help="Entropy bonus: keeps the policy trying other actions.")] = 0.001,
    seed: Annotated[int, typer.Option(help="Seeds the envs and the network.")] = 0,
    eval_every: Annotated[int, typer.Option(help="Decisions between validations (0: none).")] = 10_000,
    checkpoint_every: Annotated[int, typer.Option(help="Decisions between checkpoints (0: none).")] = 10_000,
    init: Annotated[str, typer.Option(help="Model file whose weights start the run (same model).")] = "",
    privileged_critic: PrivilegedCriticOption = False,
    privileged_map: PrivilegedMapOption = False,
    config: SimConfigOption = None,
    resolution: ResolutionOption = None,
    resume: Annotated[bool, typer.Option(help="Continue the run in --out from its last checkpoint.")] = False,
    progress: Annotated[bool, typer.Option(help="Show a progress bar.")] = True,
) -> None:
    """Train a model: 1-4 the thesis's, 5-7 ours.

    With Stable-Baselines3 (A2C as in the thesis, or PPO)."""
    resolution = checked_run_arguments(seed, out, resolution)
    with _needs_rl_extra():
        from frontier_rl.api import train as run_training
        from frontier_rl.rl.config import TrainConfig
        from frontier_rl.rl.run_folder import interruption_note

    settings = TrainConfig(
        model=model,
        worlds=worlds,
        timesteps=timesteps,
        n_envs=n_envs,
        algo=algo,
        observation_size=observation_size,
        reward=reward,
        learning_rate=learning_rate,
        n_steps=n_steps,
        gamma=gamma,
        ent_coef=ent_coef,
        seed=seed,
        eval_every=eval_every,
        checkpoint_every=checkpoint_every,
        init=init,
        privileged_critic=privileged_critic,
        privileged_map=privileged_map,
        sim=sim_config(config, None),
        resolution=resolution,
    )
    try:
        final = run_training(settings, out, resume=resume, progress=progress)
    except KeyboardInterrupt:
        print_note(interruption_note(settings, out))
        raise typer.Exit(130) from None
    print_line(f"model: {final}   learning curve: {out / 'learning_curve.png'}")
