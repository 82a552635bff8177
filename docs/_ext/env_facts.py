"""What an environment's page states, read off a real instance: its spaces, the keys of its info,
and a picture of it after a few decisions."""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
from PIL import Image

import frontier_rl.envs  # noqa: F401  (registers the ids)
from frontier_rl.envs.team_env import TeamExplorationEnv
from frontier_rl.registration import MODELS, ModelSpec

PICTURE_WIDTH = 640
"""Width (px) of an environment's picture on its page."""
PICTURE_DECISIONS = 10
"""Decisions taken before the picture: the robot has driven and mapped a little."""
PICTURE_SEED = 0
"""Seed of the episode drawn (and of the actions sampled)."""


@dataclass(frozen=True)
class EnvFacts:
    """One environment as its page shows it."""

    name: str
    cls: type[Any]
    model: ModelSpec | None
    observation_space: gym.Space[Any]
    action_space: gym.Space[Any]
    info_keys: tuple[str, ...]


def gym_facts(env_id: str, picture: Path) -> EnvFacts:
    """The facts of the Gymnasium id ``env_id``, and its picture saved to ``picture``."""
    spec = gym.spec(env_id)
    module_name, _, class_name = str(spec.entry_point).partition(":")
    cls = getattr(importlib.import_module(module_name), class_name)
    model = next(m for m in MODELS.values() if _size_suffix(env_id, m))
    env = gym.make(env_id, render_mode="rgb_array")
    try:
        env.action_space.seed(PICTURE_SEED)
        env.reset(seed=PICTURE_SEED)
        info: dict[str, Any] = {}
        for _ in range(PICTURE_DECISIONS):
            _, _, terminated, truncated, info = env.step(env.action_space.sample())
            if terminated or truncated:
                break
        save_picture(env.render(), picture)  # type: ignore[arg-type]
        return EnvFacts(env_id, cls, model, env.observation_space, env.action_space, tuple(info))
    finally:
        env.close()


def _size_suffix(env_id: str, model: ModelSpec) -> bool:
    """Whether ``env_id`` is ``model``'s id at one of the observation sizes."""
    name = env_id.split("/")[1].removesuffix("-v0")
    return name in (model.name, model.name + "64")


def team_facts(picture: Path) -> EnvFacts:
    """The facts of the PettingZoo team environment (two robots, weight actions), its picture saved
    to ``picture``."""
    env = TeamExplorationEnv(render_mode="rgb_array")
    try:
        env.reset(seed=PICTURE_SEED)
        agent = env.possible_agents[0]
        space = env.action_space(agent)
        space.seed(PICTURE_SEED)
        infos: dict[str, Any] = {}
        for _ in range(PICTURE_DECISIONS):
            *_, infos = env.step({a: space.sample() for a in env.agents})
            if not env.agents:
                break
        save_picture(env.render(), picture)  # type: ignore[arg-type]
        keys = tuple(next(iter(infos.values()), {}))
        return EnvFacts(str(env.metadata["name"]), TeamExplorationEnv, None, env.observation_space(agent), space, keys)
    finally:
        env.close()


def save_picture(frame: np.ndarray[Any, Any], path: Path) -> None:
    """``frame`` (RGB) scaled to :data:`PICTURE_WIDTH` and saved as an optimised PNG."""
    image = Image.fromarray(frame)
    height = round(image.height * PICTURE_WIDTH / image.width)
    image.resize((PICTURE_WIDTH, height), Image.Resampling.LANCZOS).save(path, optimize=True)
