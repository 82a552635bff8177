"""explore_lite's parameter file (m-explore-ros2's ``explore.yaml``) read into the explorer's
settings (:func:`explore_lite_parameters`)."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from frontier_rl.checked_values import coerce
from frontier_rl.errors import ConfigError
from frontier_rl.safe_yaml import load_yaml_file

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
