"""Learned policies (``learned:PATH.zip``) behind the same interface as the baselines.

The model kind follows from the network's spaces: a dict observation (the map and a frontier
table) with an action per row is the frontier-choice model (5, or 7 when the table has a tour
column), with 100 actions model 6 (a weight from the table; a table of 100 rows is told apart by
the file's metadata); an image with 100 actions is a weight model (3 with frontier and pose
channels, 4 without); otherwise a point model (1 or 2), whose chosen pixel becomes a goal to drive
to.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from frontier_rl.core.frontiers.ranking import rank, weighted_cost
from frontier_rl.core.navigation.costmap import Costmap
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import DecisionContext, Ranking
from frontier_rl.errors import ConfigError, model_file_label, short_repr
from frontier_rl.observation.frontier_table import frontier_observation, slot_order
from frontier_rl.observation.map_image import FRONTIER_FEATURES, MapEncoder
from frontier_rl.observation.weight_bins import WEIGHT_BINS, bin_to_weight
from frontier_rl.registration import MODELS, ModelKind

if TYPE_CHECKING:
    from frontier_rl.inference.interface import Actor


@dataclass
class LearnedPolicy:
    """A trained model file as an exploration policy.

    Args:
        path: a zip written by ``frontier-rl train``.
        trust: allow loading SB3 zips without frontier_rl metadata (this unpickles the file).
        sim: the navigation settings of the costmap the frontier-table models' (5 to 7) path costs
            are computed on, when the decision context brings none (the robot's radius is always
            the context's).

    Attributes:
        kind: what the file's network chooses (:class:`~frontier_rl.registration.ModelKind`), read from its shape.
    """

    path: Path
    trust: bool = False
    sim: SimConfig = field(default_factory=SimConfig)

    def __post_init__(self) -> None:
        try:  # torch is imported only for learned policies
            from frontier_rl.inference.actor import load_actor
        except ImportError as error:
            if error.name != "torch":
                raise
            raise ConfigError(
                f"{model_file_label(Path(self.path))} is a learned policy, which needs PyTorch: "
                "pip install 'frontier_rl[models]' (or [rl], to train as well)"
            ) from None

        self.path = Path(self.path)
        self._actor: Actor
        self._actor, info = load_actor(self.path, self.trust)
        where = model_file_label(self.path)
        shape = self._actor.shape
        n_actions, rows = shape.actions, shape.table_rows
        self._tour = False
        if rows == 0:
            self.kind = ModelKind.WEIGHT if n_actions == WEIGHT_BINS else ModelKind.POINT
        else:
            if n_actions not in (rows, WEIGHT_BINS):
                raise ConfigError(f"{where} has {n_actions} actions for a frontier table of {rows} rows")
            table_weight = (
                n_actions == WEIGHT_BINS if info is None else MODELS[info.model].kind is ModelKind.WEIGHT_TABLE
            )
            self.kind = ModelKind.WEIGHT_TABLE if table_weight else ModelKind.FRONTIER
            n_actions = rows
            columns = (len(FRONTIER_FEATURES), len(FRONTIER_FEATURES) + 1)  # model 7's table: the tour column
            if shape.table_length not in tuple(rows * c for c in columns):
                raise ConfigError(f"{where} has a frontier table of {shape.table_length} values for {rows} rows")
            self._tour = shape.table_length == rows * columns[1]
        channels, size, width = shape.image
        if size != width:
            raise ConfigError(f"{where} expects observations of shape {short_repr(shape.image)}, not a square map")
        extra = channels == 3
        try:
            self._encoder = MapEncoder(size, frontier_channel=extra, pose_channel=extra)
        except (ValueError, TypeError):
            raise ConfigError(f"{where} expects map images of shape {short_repr(shape.image)}") from None
        if self._encoder.shape != shape.image:
            raise ConfigError(f"{where} expects map images of shape {short_repr(shape.image)}")
        if self.kind is ModelKind.POINT and n_actions != size * size:
            raise ConfigError(f"{where} has {n_actions} actions, expected {WEIGHT_BINS} or {size}²")
        self._top_k = n_actions

    @property
    def name(self) -> str:
        """``learned:PATH``."""
        return f"learned:{self.path}"

    def _act(self, observation: Any) -> int:
        return self._actor.act(observation)

    def rank(self, context: DecisionContext, rng: np.random.Generator) -> Ranking:
        """The model's choice for this decision."""
        grid, pose, frontiers = context.grid, context.pose, context.frontiers
        if self.kind is ModelKind.POINT:
            row, col = divmod(self._act(self._encoder.encode(grid, pose, frontiers)), self._encoder.size)
            goal = self._encoder.pixel_to_world(grid, pose, row, col)
            return Ranking(np.zeros(0, np.int64), goal=goal)
        if self.kind is ModelKind.WEIGHT:
            action = self._act(self._encoder.encode(grid, pose, frontiers))
        else:  # the frontier table's models
            radius, sensor_range = context.robot_radius, context.sensor_range
            costmap = context.costmap or Costmap.build(
                grid, replace(self.sim.robot, radius=radius), self.sim.navigation
            )
            obs, slots = frontier_observation(
                self._encoder, self._top_k, costmap, pose, frontiers, radius, sensor_range, self._tour
            )
            action = self._act(obs)
            if self.kind is ModelKind.FRONTIER:
                return Ranking(slot_order(slots, action))
        weight = bin_to_weight(action)  # models 3, 4 and 6
        return Ranking(rank(weighted_cost(frontiers, weight)), weight)
