"""The explorer's settings (:class:`ExplorerParams`), each with what it means and its unit, in one
place: the command line's help and the ROS 2 node's parameter descriptions are these. Checkable
without loading the engine (or YAML: explore_lite's parameter file is read in
:mod:`frontier_rl.robot.explore_lite_file`)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field, fields, replace
from typing import Any

from frontier_rl.errors import SettingError, short_repr

DEFAULT_MIN_FRONTIER_SIZE_M = 0.2
"""The engine's frontier drop size (``SimConfig.min_frontier_cells``, 4 cells of 0.05 m)."""

VISUALIZE_HELP = "Publish RViz markers on explore/frontiers."
"""What the node's ``visualize`` parameter (and ``--visualize``) does; a setting of the node that
draws, not of the explorer."""


def _setting(default: Any, help_text: str) -> Any:
    """A setting's field (of :class:`ExplorerParams`, :class:`Nav2Plugins`) with its default and
    what it means (its ``help``)."""
    return field(default=default, metadata={"help": help_text})


@dataclass(frozen=True)
class ExplorerParams:
    """The explorer's settings, with explore_lite's names where they mean the same; what each means,
    with its unit, is its field's ``help`` (:func:`setting_help`). No time cap is ``math.inf`` here,
    where the command line and the node's parameter write 0."""

    planner_frequency: float = _setting(1.0, "Planner ticks per second (Hz).")
    progress_timeout: float = _setting(
        30.0,
        "A goal the robot gets no nearer to (by progress_distance) for this long, in a straight line or along "
        "its costmap's way there, is given up (s).",
    )
    min_frontier_size: float = _setting(DEFAULT_MIN_FRONTIER_SIZE_M, "Frontiers this long or shorter are no goals (m).")
    return_to_init: bool = _setting(False, "Drive back to the start once explored.")
    time_cap: float = _setting(math.inf, "Stop exploring after this long (s; 0: never).")
    progress_distance: float = _setting(0.1, "The distance (m) nearer to the goal that counts as progress.")
    recovery_paths: bool = _setting(
        True,
        "Send a goal found with the map's walls thinned (where SLAM drew a doorway too narrow for the costmap) "
        "to Nav2's controller (follow_path) with the path planned on that map, not to navigate_to_pose.",
    )

    def __post_init__(self) -> None:
        for name in ("planner_frequency", "progress_timeout", "time_cap", "progress_distance"):
            value = getattr(self, name)
            if not (isinstance(value, int | float) and value > 0 and not math.isnan(value)):
                raise SettingError(name, f"must be a positive number, got {value!r}")
        if not (math.isfinite(self.min_frontier_size) and self.min_frontier_size >= 0):
            raise SettingError("min_frontier_size", f"must be a number of metres >= 0, got {self.min_frontier_size!r}")


@dataclass(frozen=True)
class Nav2Plugins:
    """Which of Nav2's plugins the explorer's goals ask for, by the names a Nav2 ``params.yaml``
    gives them; "" lets Nav2 choose: bt_navigator's default behaviour tree, the only controller,
    goal checker or progress checker the controller_server has (with several, Nav2 aborts a path
    goal that names none). What each means is its field's ``help`` (:func:`setting_help`)."""

    behavior_tree: str = _setting(
        "",
        "navigate_to_pose's behaviour tree, as bt_navigator takes it (an XML file on Nav2's machine; '': its default).",
    )
    controller_id: str = _setting("", "follow_path's controller plugin ('': the controller_server's only one).")
    goal_checker_id: str = _setting("", "follow_path's goal checker plugin ('': the only one).")
    progress_checker_id: str = _setting("", "follow_path's progress checker plugin ('': the only one).")

    @classmethod
    def names(cls) -> tuple[str, ...]:
        """The plugins' parameter names (the fields')."""
        return tuple(setting.name for setting in fields(cls))

    @classmethod
    def of(cls, values: Mapping[str, Any], base: Nav2Plugins | None = None) -> Nav2Plugins:
        """The plugins named among ``values`` (parameter name -> value; other names ignored), the
        others ``base``'s (by default Nav2's own choice).

        Raises:
            SettingError: a value that is no plugin's name, named.
        """
        return replace(base or cls(), **{name: values[name] for name in cls.names() if name in values})

    def values(self) -> dict[str, str]:
        """Each plugin's parameter name and value."""
        return asdict(self)

    def __post_init__(self) -> None:
        for name in self.names():
            value = getattr(self, name)
            if not isinstance(value, str) or not value.isprintable() or value != value.strip():
                raise SettingError(name, f"must be a plugin's name or '' (Nav2's own), got {short_repr(value)}")


def setting_help(name: str) -> str:
    """What the explorer's setting ``name`` means, with its unit (``visualize``: the node's markers).

    Raises:
        KeyError: ``name`` is no setting.
    """
    if name == "visualize":
        return VISUALIZE_HELP
    for setting in (*fields(ExplorerParams), *fields(Nav2Plugins)):
        if setting.name == name:
            return str(setting.metadata["help"])
    raise KeyError(name)


def time_cap_of_parameter(value: float) -> float:
    """A time cap (s) as the command line and the node's parameter write it: 0 means none (``inf``)."""
    return math.inf if value == 0 else value


def time_cap_parameter(time_cap: float) -> float:
    """A time cap (s) as the command line and the node's parameter write it: 0 for none."""
    return 0.0 if math.isinf(time_cap) else float(time_cap)
