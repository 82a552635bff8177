"""The explorer's settings (:class:`ExplorerParams`), checkable without loading the engine."""

from __future__ import annotations

import math
from dataclasses import dataclass

DEFAULT_MIN_FRONTIER_SIZE_M = 0.2
"""The engine's frontier drop size (``SimConfig.min_frontier_cells``, 4 cells of 0.05 m)."""


@dataclass(frozen=True)
class ExplorerParams:
    """The explorer's settings, with explore_lite's names where they mean the same.

    Attributes:
        planner_frequency: how often the frontiers are found and ranked again (Hz).
        progress_timeout: a goal the robot gets no nearer to (by ``progress_distance``) for this
            long is given up and blacklisted (s).
        min_frontier_size: frontier clusters this long or shorter are no goals (m).
        return_to_init: drive back to the start once the map is explored.
        time_cap: stop exploring after this long (s); infinite by default.
        progress_distance: the distance (m) to the goal that counts as progress.
    """

    planner_frequency: float = 1.0
    progress_timeout: float = 30.0
    min_frontier_size: float = DEFAULT_MIN_FRONTIER_SIZE_M
    return_to_init: bool = False
    time_cap: float = math.inf
    progress_distance: float = 0.1

    def __post_init__(self) -> None:
        for name in ("planner_frequency", "progress_timeout", "time_cap", "progress_distance"):
            value = getattr(self, name)
            if not (isinstance(value, int | float) and value > 0 and not math.isnan(value)):
                raise ValueError(f"{name} must be a positive number, got {value!r}")
        if not (math.isfinite(self.min_frontier_size) and self.min_frontier_size >= 0):
            raise ValueError(f"min_frontier_size must be a number of metres >= 0, got {self.min_frontier_size!r}")
