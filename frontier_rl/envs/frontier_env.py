"""Model 5, the thesis's future work: the policy chooses one of the top-K candidate frontiers; and
the observation it shares with model 6 (:class:`FrontierTableEnv`)."""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.sim.leg_result import LegResult
from frontier_rl.core.world.grid import OccupancyGrid
from frontier_rl.envs.base import EnvConfig, ExplorationEnv
from frontier_rl.errors import ConfigError
from frontier_rl.observation.frontier_table import FEATURE_BOUND, simulator_observation, slot_order
from frontier_rl.observation.map_image import FRONTIER_FEATURES, MapEncoder

PRIVILEGED_FEATURES = ("unseen_share", "unseen_area")
"""The privileged entry: the share of the explorable area not yet mapped, and that area over
:data:`PRIVILEGED_AREA_M2` (capped at 1). The time left is about proportional to it, which the
map image around the robot cannot tell a critic on a large floor."""

PRIVILEGED_AREA_M2 = 2500.0
"""The unseen area (m²) at which ``unseen_area`` reaches 1: a 50 m × 50 m floor."""


class FrontierTableEnv(ExplorationEnv[dict[str, NDArray[Any]]]):
    """Observation (a dict): ``map``, the map with frontier and pose channels; ``frontiers``, a
    (K, 6) table, flattened row by row, of per-frontier features (:data:`FRONTIER_FEATURES`) for
    the K candidates with the lowest path cost, cheapest first, and with ``tour`` (model 7) a
    seventh column, :data:`~frontier_rl.observation.frontier_table.TOUR_FEATURE`; ``mask``, 1 for
    the rows that hold a frontier. Subclasses give the action (:class:`FrontierChoiceEnv`: a row; model 6's
    :class:`~frontier_rl.envs.weight_env.WeightTableEnv`: a ranking weight).

    With ``privileged``, the observation also holds ``privileged``: what only the simulator knows,
    for a critic in training (:data:`PRIVILEGED_FEATURES`); with ``privileged_map``, also
    ``privileged_map``: the true map's explorable space not yet seen, as a ``(1, size, size)``
    image over the window of ``map`` (each pixel the share of its cells, 0..255). A policy must
    not act on either.

    Args:
        config: shared settings (:class:`EnvConfig`).
        top_k: number of candidate slots K.
        render_mode: None or "rgb_array".
        privileged: add the ``privileged`` entry.
        privileged_map: add the ``privileged_map`` entry.
        tour: add the tour column to the table (model 7).
        **overrides: fields of :class:`EnvConfig`.
    """

    def __init__(
        self,
        config: EnvConfig | None = None,
        top_k: int = 16,
        render_mode: str | None = None,
        privileged: bool = False,
        tour: bool = False,
        privileged_map: bool = False,
        **overrides: Any,
    ) -> None:
        super().__init__(config, render_mode, **overrides)
        if not 1 <= top_k <= 256:
            raise ConfigError(f"top_k must be between 1 and 256, got {top_k!r}")
        self.top_k = top_k
        self.encoder = MapEncoder(self.config.observation_size, frontier_channel=True, pose_channel=True)
        columns = len(FRONTIER_FEATURES) + tour
        spaces: dict[str, gym.Space[Any]] = {
            "map": gym.spaces.Box(0, 255, self.encoder.shape, np.uint8),
            "frontiers": gym.spaces.Box(-FEATURE_BOUND, FEATURE_BOUND, (top_k * columns,), np.float32),
            "mask": gym.spaces.Box(0.0, 1.0, (top_k,), np.float32),
        }
        if privileged:
            spaces["privileged"] = gym.spaces.Box(0.0, 1.0, (len(PRIVILEGED_FEATURES),), np.float32)
        if privileged_map:
            spaces["privileged_map"] = gym.spaces.Box(0, 255, (1, self.encoder.size, self.encoder.size), np.uint8)
        self.observation_space = gym.spaces.Dict(spaces)  # type: ignore[assignment]
        self.privileged = privileged
        self.privileged_map = privileged_map
        self.tour = tour
        self.action_space = self._make_action_space()
        self._slots = np.zeros(0, np.int64)  # slot -> index into the simulator's frontiers

    def _make_action_space(self) -> gym.spaces.Discrete:
        raise NotImplementedError

    def _observe(self) -> dict[str, NDArray[Any]]:
        sim = self.sim
        obs, self._slots = simulator_observation(self.encoder, self.top_k, sim, self.tour)
        if self.privileged:
            obs["privileged"] = self._privileged_features()
        if self.privileged_map:
            obs["privileged_map"] = self._unseen_image(sim.candidates().costmap.grid)
        return obs

    def _privileged_features(self) -> NDArray[np.float32]:
        """:data:`PRIVILEGED_FEATURES` of the current state, from the true world."""
        sim = self.sim
        unseen = max(sim.world.explorable_count - sim.mapper.explored_cells, 0)
        area = unseen * sim.world.grid.resolution**2
        return np.clip(np.array([1.0 - sim.coverage, area / PRIVILEGED_AREA_M2], np.float32), 0.0, 1.0)

    def _unseen_image(self, grid: OccupancyGrid) -> NDArray[np.uint8]:
        """The ``privileged_map`` entry over the window the ``map`` entry shows of ``grid`` (the
        robot's map, a crop of the world's cells)."""
        sim = self.sim
        unseen = sim.world.explorable & ~sim.mapper.seen
        return self.encoder.share_image(grid, sim.pose, unseen, grid.offset_in(sim.world.grid))


class FrontierChoiceEnv(FrontierTableEnv):
    """Model 5: the observation of :class:`FrontierTableEnv`; the action, a row of its table. A
    masked row (fewer than K frontiers) is taken modulo the number of frontiers, so every action in
    the space is legal; :meth:`action_masks` gives the mask for maskable algorithms. Arguments as
    :class:`FrontierTableEnv`.
    """

    def _make_action_space(self) -> gym.spaces.Discrete:
        return gym.spaces.Discrete(self.top_k)

    def action_masks(self) -> NDArray[np.bool_]:
        """Which actions point at a real frontier (for MaskablePPO and the like)."""
        mask = np.zeros(self.top_k, np.bool_)
        mask[: len(self._slots)] = True
        return mask

    def _act(self, action: int) -> tuple[LegResult, float]:
        return self.sim.execute(slot_order(self._slots, action)), 0.0
