"""An explorer's parameter file read into its settings (:func:`explore_lite_parameters`):
explore_lite's own (m-explore-ros2's ``explore.yaml``), a ROS 2 parameter file with this
explorer's node in it, or a plain mapping of parameter names to values."""

from __future__ import annotations

import typing
from collections.abc import Mapping
from dataclasses import fields, replace
from pathlib import Path
from typing import Any

from frontier_rl.checked_values import coerce
from frontier_rl.errors import ConfigError, SettingError
from frontier_rl.robot.explorer_params import ExplorerParams, Nav2Plugins, time_cap_of_parameter
from frontier_rl.safe_yaml import load_yaml_file

_SETTING_TYPES: dict[str, type] = {
    setting.name: typing.get_type_hints(ExplorerParams)[setting.name] for setting in fields(ExplorerParams)
}
"""Each setting of :class:`ExplorerParams` and its type."""

FILE_PARAMETERS: dict[str, type] = {
    **_SETTING_TYPES,
    **dict.fromkeys(Nav2Plugins.names(), str),
    "visualize": bool,
    "robot_base_frame": str,
    "use_sim_time": bool,
}
"""The parameters a file may set here, and their types: the explorer's settings (explore_lite's
names where they mean the same, and the node's own ``time_cap``, ``progress_distance`` and
``recovery_paths``), the Nav2 plugins its goals name
(:class:`~frontier_rl.robot.explorer_params.Nav2Plugins`), its markers, with the pose from ``tf``
the robot's base frame, and ROS's ``use_sim_time`` (as ``--use-sim-time``)."""

EXPLORER_NODES = ("explore_node", "frontier_rl_explorer", "/**")
"""The nodes of a ROS 2 parameter file whose parameters are the explorer's: explore_lite's node,
this explorer's node (in any namespace) and every node."""


def explore_lite_parameters(path: str | Path) -> tuple[dict[str, Any], list[str]]:
    """The parameters of the file at ``path`` that mean something here (:data:`FILE_PARAMETERS`),
    each checked, and the names of those it sets that do not (``potential_scale``, ...). In ROS 2's
    layout (``NODE: {ros__parameters: {...}}``) a file of one node is read whole; in one of several
    nodes (a Nav2 ``params.yaml``), those of :data:`EXPLORER_NODES`, in the file's order (a later
    one wins).

    Raises:
        ConfigError: an unreadable or malformed file, several nodes none of them the explorer's, or
            a value of the wrong type or out of range, naming it and the file.
    """
    data = _explorer_section(load_yaml_file(path, ConfigError, "parameter file"), path)
    known = {
        str(name): coerce(FILE_PARAMETERS[name], value, f"{path}: {name}")
        for name, value in data.items()
        if name in FILE_PARAMETERS
    }
    settings = {name: value for name, value in known.items() if name in _SETTING_TYPES}
    if "time_cap" in settings:
        settings["time_cap"] = time_cap_of_parameter(settings["time_cap"])
    try:
        replace(ExplorerParams(), **settings)
        Nav2Plugins.of(known)
    except SettingError as error:
        raise ConfigError(f"{path}: {error.setting} {error.problem}") from None
    return known, sorted(str(name) for name in data if name not in FILE_PARAMETERS)


def _node_sections(data: Mapping[object, object], namespace: str = "") -> dict[str, object] | None:
    """The ``ros__parameters`` of each node of a file in ROS 2's layout, by the node's name with its
    namespace (``tb3_0: {frontier_rl_explorer: {ros__parameters: ...}}`` is
    ``tb3_0/frontier_rl_explorer``, as ``/tb3_0/frontier_rl_explorer:`` would be); None for a file of
    another layout (a plain mapping of parameters)."""
    nodes: dict[str, object] = {}
    for name, value in data.items():
        key = f"{namespace}/{name}" if namespace else str(name)
        if isinstance(value, Mapping) and "ros__parameters" in value:
            nodes[key] = value["ros__parameters"]
        elif isinstance(value, Mapping) and value and (inner := _node_sections(value, key)) is not None:
            nodes |= inner
        else:
            return None
    return nodes or None


def _explorer_section(data: object, path: str | Path) -> Mapping[object, object]:
    """The parameters of a file's explorer (see :func:`explore_lite_parameters`)."""
    nodes = _node_sections(data) if isinstance(data, Mapping) else None
    if nodes is not None:
        chosen = (
            list(nodes.values())
            if len(nodes) == 1
            else [
                params for name, params in nodes.items() if name == "/**" or name.rsplit("/", 1)[-1] in EXPLORER_NODES
            ]
        )
        if not chosen:
            raise ConfigError(
                f"parameter file {path} sets the parameters of {', '.join(nodes)}, none of them the explorer "
                f"({', '.join(EXPLORER_NODES)})"
            )
        sections = [params for params in chosen if isinstance(params, Mapping)]
        if len(sections) < len(chosen):
            raise ConfigError(f"parameter file {path}: ros__parameters must map parameter names to values")
        data = {name: value for params in sections for name, value in params.items()}
    if not isinstance(data, Mapping):
        raise ConfigError(f"parameter file {path} must map parameter names to values")
    return data
