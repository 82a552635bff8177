"""Gymnasium environments for the thesis's models: weight (3, 4), point (1, 2), frontier choice (5),
and a weight from the frontier table (6); and the PettingZoo team environment (:mod:`frontier_rl.envs.team_env`).

Importing this package registers every id of :data:`frontier_rl.registration.ENV_IDS` with
Gymnasium (``gym.make("frontier_rl.envs:FrontierRL/WeightMap-v0")`` imports it on the way).
"""

import gymnasium as gym

from frontier_rl.envs.base import EnvConfig, ExplorationEnv
from frontier_rl.envs.frontier_env import FrontierChoiceEnv, FrontierTableEnv
from frontier_rl.envs.point_env import PointEnv
from frontier_rl.envs.rewards import REWARD_PRESETS, RewardConfig, reward_preset
from frontier_rl.envs.weight_env import WeightEnv, WeightTableEnv
from frontier_rl.envs.world_source import TRAIN_SEED_LOW, WorldSource
from frontier_rl.registration import MODELS, OBSERVATION_SIZES, env_id
from frontier_rl.world_spec import parse_world_list

__all__ = [
    "REWARD_PRESETS",
    "TRAIN_SEED_LOW",
    "EnvConfig",
    "ExplorationEnv",
    "FrontierChoiceEnv",
    "FrontierTableEnv",
    "PointEnv",
    "RewardConfig",
    "WeightEnv",
    "WeightTableEnv",
    "WorldSource",
    "parse_world_list",
    "register_envs",
    "reward_preset",
]


def register_envs() -> None:
    """Register every id (idempotent)."""
    for model, spec in MODELS.items():
        for size in OBSERVATION_SIZES:
            name = env_id(model, size)
            if name not in gym.registry:
                gym.register(
                    id=name,
                    entry_point=spec.entry_point,
                    kwargs={**spec.env_kwargs(), "observation_size": size},
                    disable_env_checker=True,
                )


register_envs()
