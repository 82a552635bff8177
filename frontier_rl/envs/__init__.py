"""Gymnasium environments for the thesis's models: weight (3, 4), point (1, 2), frontier choice (5);
and the PettingZoo team environment (:mod:`frontier_rl.envs.team_env`)."""

from frontier_rl.envs.base import EnvConfig, ExplorationEnv
from frontier_rl.envs.frontier_env import FrontierChoiceEnv
from frontier_rl.envs.observation import MapEncoder
from frontier_rl.envs.point_env import PointEnv
from frontier_rl.envs.rewards import REWARD_PRESETS, RewardConfig, reward_preset
from frontier_rl.envs.weight_env import WEIGHT_BINS, WeightEnv, bin_to_weight
from frontier_rl.envs.world_source import TRAIN_SEED_LOW, WorldSource, parse_world_list

__all__ = [
    "REWARD_PRESETS",
    "TRAIN_SEED_LOW",
    "WEIGHT_BINS",
    "EnvConfig",
    "ExplorationEnv",
    "FrontierChoiceEnv",
    "MapEncoder",
    "PointEnv",
    "RewardConfig",
    "WeightEnv",
    "WorldSource",
    "bin_to_weight",
    "parse_world_list",
    "reward_preset",
]
