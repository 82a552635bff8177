"""Gymnasium ids of the frontier_rl environments and the thesis models behind them, without
Gymnasium: ``import frontier_rl.envs`` registers them (:func:`frontier_rl.envs.register_envs`).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

from frontier_rl.errors import ConfigError, short_repr

NAMESPACE = "FrontierRL"


class ModelKind(StrEnum):
    """What a model's network chooses."""

    WEIGHT = "weight"  # a ranking weight from the map image (models 3 and 4)
    POINT = "point"  # a goal cell of the map image (models 1 and 2)
    WEIGHT_TABLE = "weight table"  # a ranking weight from the frontier table (model 6)
    FRONTIER = "frontier"  # a frontier of the table (models 5 and 7)


@dataclass(frozen=True)
class ModelSpec:
    """A thesis model: which env it runs in and with which channels, and what it chooses.

    Attributes:
        with_frontiers_and_pose: for a model of a map image (1-4), whether the frontiers and the
            robot's pose are channels beside the map; None for the env that takes no such choice.
        tour: for a model of the frontier table, whether the table has the tour column (model 7).
    """

    number: int
    name: str
    entry_point: str
    description: str
    kind: ModelKind
    with_frontiers_and_pose: bool | None = None
    tour: bool = False

    def env_kwargs(self) -> dict[str, bool]:
        """The keyword arguments its env is registered with (Gymnasium's ``gym.register``)."""
        channels = self.with_frontiers_and_pose
        kwargs = {} if channels is None else {"with_frontiers_and_pose": channels}
        return kwargs | ({"tour": True} if self.tour else {})


MODELS: dict[int, ModelSpec] = {
    1: ModelSpec(
        1,
        "PointMapFrontiersPose",
        "frontier_rl.envs.point_env:PointEnv",
        "map + frontiers + pose in, a map cell out",
        ModelKind.POINT,
        with_frontiers_and_pose=True,
    ),
    2: ModelSpec(
        2,
        "PointMap",
        "frontier_rl.envs.point_env:PointEnv",
        "map in, a map cell out",
        ModelKind.POINT,
        with_frontiers_and_pose=False,
    ),
    3: ModelSpec(
        3,
        "WeightMapFrontiersPose",
        "frontier_rl.envs.weight_env:WeightEnv",
        "map + frontiers + pose in, ranking weight out",
        ModelKind.WEIGHT,
        with_frontiers_and_pose=True,
    ),
    4: ModelSpec(
        4,
        "WeightMap",
        "frontier_rl.envs.weight_env:WeightEnv",
        "map in, ranking weight out",
        ModelKind.WEIGHT,
        with_frontiers_and_pose=False,
    ),
    5: ModelSpec(
        5,
        "FrontierChoice",
        "frontier_rl.envs.frontier_env:FrontierChoiceEnv",
        "map + per-frontier features in, one of the top-K frontiers out",
        ModelKind.FRONTIER,
    ),
    6: ModelSpec(
        6,
        "WeightFrontierTable",
        "frontier_rl.envs.weight_env:WeightTableEnv",
        "map + per-frontier features in, ranking weight out",
        ModelKind.WEIGHT_TABLE,
    ),
    7: ModelSpec(
        7,
        "FrontierChoiceTour",
        "frontier_rl.envs.frontier_env:FrontierChoiceEnv",
        "map + per-frontier features and tour costs in, one of the top-K frontiers out",
        ModelKind.FRONTIER,
        tour=True,
    ),
}
"""Models 1-4 are the thesis's, 5 its future work (a frontier chosen directly), 6 model 3 with
model 5's frontier table beside the image (a per-decision weight needs what the ranking trades off),
7 model 5 with a column that says how much a tour over the nearest frontiers loses by going to each
first (what ``tour`` ranks by)."""

FRONTIER_CHOICE_MODELS: tuple[int, ...] = tuple(m for m, spec in MODELS.items() if spec.kind is ModelKind.FRONTIER)
"""The models whose action is one of the candidate frontiers (5 and 7): the pointer policy's, and
the ones a lookahead teacher can label (``--algo dagger``)."""

TABLE_MODELS: tuple[int, ...] = tuple(
    m for m, spec in MODELS.items() if spec.kind in (ModelKind.FRONTIER, ModelKind.WEIGHT_TABLE)
)
"""The models that read a table of the cheapest frontiers beside the map image (5, 6 and 7)."""

POINT_MODELS: tuple[int, ...] = tuple(m for m, spec in MODELS.items() if spec.kind is ModelKind.POINT)
"""The models whose action is a pixel of the map image (1 and 2)."""


class Algorithm(StrEnum):
    """The training algorithms a model file may name (a DAgger policy is kept in an A2C container)."""

    A2C = "a2c"
    PPO = "ppo"
    DAGGER = "dagger"


TOP_K = 16
"""The frontier table's rows (candidate slots) in the registered envs of :data:`TABLE_MODELS`."""

OBSERVATION_SIZES = (250, 64)
"""The map image sizes with a registered id: the thesis's 250 × 250 and Niroui et al.'s 64 × 64."""


def env_id(model: int, observation_size: int = 250) -> str:
    """The registered id of model ``model`` (1-7) at ``observation_size`` (250 or 64)."""
    if model not in MODELS:
        raise ConfigError(f"unknown model {short_repr(model)}; choose one of {', '.join(map(str, MODELS))}")
    if observation_size not in OBSERVATION_SIZES:
        raise ConfigError(f"observation size must be one of {OBSERVATION_SIZES}, got {short_repr(observation_size)}")
    suffix = "" if observation_size == 250 else str(observation_size)
    return f"{NAMESPACE}/{MODELS[model].name}{suffix}-v0"


ENV_IDS: tuple[str, ...] = tuple(env_id(m, s) for m in MODELS for s in OBSERVATION_SIZES)
"""Every registered id."""
