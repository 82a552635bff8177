"""The explorer's settings (:class:`ExplorerParams`), checkable without loading the engine, and
explore_lite's parameter file read into them (:func:`explore_lite_parameters`)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from frontier_rl.checked_values import coerce
from frontier_rl.errors import ConfigError, SettingError
from frontier_rl.safe_yaml import load_yaml_file

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
                raise SettingError(name, f"must be a positive number, got {value!r}")
        if not (math.isfinite(self.min_frontier_size) and self.min_frontier_size >= 0):
            raise SettingError("min_frontier_size", f"must be a number of metres >= 0, got {self.min_frontier_size!r}")


EXPLORE_LITE_NAMES = {
    "planner_frequency": float,
    "progress_timeout": float,
    "min_frontier_size": float,
    "return_to_init": bool,
    "visualize": bool,
    "robot_base_frame": str,
}
"""explore_lite's parameters that mean the same here, and their types (``robot_base_frame``: with
the pose from ``tf``)."""


def explore_lite_parameters(path: str | Path) -> tuple[dict[str, Any], list[str]]:
    """The parameters of an explore_lite (m-explore-ros2) parameter file that mean the same here
    (:data:`EXPLORE_LITE_NAMES`), checked, and the names of those it sets that have no meaning
    here (``potential_scale``, ``transform_tolerance``, ...). The file is ROS 2's
    (``NODE: {ros__parameters: {...}}``, the first node's) or a plain mapping of names to values.

    Raises:
        ConfigError: an unreadable or malformed file, or a value of the wrong type, naming it.
    """
    data = load_yaml_file(path, ConfigError, "parameter file")
    if (
        isinstance(data, Mapping)
        and data
        and all(isinstance(v, Mapping) and "ros__parameters" in v for v in data.values())
    ):
        data = next(iter(data.values()))["ros__parameters"]
    if not isinstance(data, Mapping):
        raise ConfigError(f"parameter file {path} must map parameter names to values")
    known = {
        str(name): coerce(EXPLORE_LITE_NAMES[name], value, f"{path}: {name}")
        for name, value in data.items()
        if name in EXPLORE_LITE_NAMES
    }
    return known, sorted(str(name) for name in data if name not in EXPLORE_LITE_NAMES)
