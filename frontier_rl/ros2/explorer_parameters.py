"""The explorer's settings as ROS 2 parameters of its node, with explore_lite's names.

The command line's options (or explore_lite's parameter file) give the parameters' values;
``--ros-args -p NAME:=VALUE`` or ``--ros-args --params-file FILE`` override them as for any ROS 2
node, and ``ros2 param set`` changes them while the robot explores. Every value is checked as the
command line checks it (:class:`~frontier_rl.robot.explorer_params.ExplorerParams`): a bad one is
refused with the reason, at start as a one-line error, at run time as the set's failure.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, fields, replace
from typing import Any

from rcl_interfaces.msg import ParameterDescriptor
from rclpy.exceptions import ParameterException
from rclpy.node import Node

from frontier_rl.checked_values import coerce
from frontier_rl.errors import ConfigError, SettingError
from frontier_rl.robot.explorer_params import (
    ExplorerParams,
    Nav2Plugins,
    setting_help,
    time_cap_of_parameter,
    time_cap_parameter,
)

PARAMETERS = (*(setting.name for setting in fields(ExplorerParams)), *Nav2Plugins.names(), "visualize")
"""The node's parameters that set the explorer, the Nav2 plugins its goals name and its markers
(what each means: :func:`setting_help`)."""


POLICY_PARAMETER = "policy"
"""A read-only parameter: the policy the explorer ranks with, as given."""


@dataclass(frozen=True)
class ExplorerSettings:
    """What the node's parameters set: the explorer's settings, whether it draws markers, and the
    Nav2 plugins its goals name."""

    params: ExplorerParams
    visualize: bool
    plugins: Nav2Plugins = field(default_factory=Nav2Plugins)

    def values(self) -> dict[str, Any]:
        """Each parameter's value (a time cap of 0: none)."""
        values: dict[str, Any] = {
            setting.name: getattr(self.params, setting.name) for setting in fields(ExplorerParams)
        }
        values["time_cap"] = time_cap_parameter(self.params.time_cap)
        return values | self.plugins.values() | {"visualize": self.visualize}

    def updated(self, changes: Mapping[str, Any]) -> ExplorerSettings:
        """These settings with ``changes`` (parameter name -> value; others ignored), checked.

        Raises:
            ConfigError: a value of the wrong type or out of range, named.
        """
        kinds = {name: type(now) if isinstance(now, bool | str) else float for name, now in self.values().items()}
        known = {
            name: coerce(kinds[name], value, f"parameter {name}")
            for name, value in changes.items()
            if name in PARAMETERS
        }
        visualize = bool(known.pop("visualize", self.visualize))
        settings = {setting.name: known[setting.name] for setting in fields(ExplorerParams) if setting.name in known}
        if "time_cap" in settings:
            settings["time_cap"] = time_cap_of_parameter(settings["time_cap"])
        try:
            return ExplorerSettings(replace(self.params, **settings), visualize, Nav2Plugins.of(known, self.plugins))
        except SettingError as error:
            raise ConfigError(f"parameter {error}") from None


def declare_explorer_parameters(node: Node, settings: ExplorerSettings, policy: str) -> ExplorerSettings:
    """Declare the explorer's parameters on ``node`` with ``settings``' values; the settings after
    the overrides of the node's ``--ros-args``, checked.

    Raises:
        ConfigError: an override of the wrong type or out of range, or of the read-only policy, named.
    """
    values = settings.values()
    try:
        for name, value in values.items():
            # dynamic typing: an integer given for a number is taken, and a wrong type is named here
            node.declare_parameter(
                name, value, ParameterDescriptor(description=setting_help(name), dynamic_typing=True)
            )
    except ParameterException as error:
        raise ConfigError(f"--ros-args: {error}") from None
    node.declare_parameter(
        POLICY_PARAMETER, policy, ParameterDescriptor(description="The policy ranking the frontiers.", read_only=True)
    )
    overridden = node.get_parameter(POLICY_PARAMETER).value
    if overridden != policy:  # an override names a policy the explorer would not rank with
        raise ConfigError(
            f"--ros-args: parameter {POLICY_PARAMETER} is read-only, got {overridden!r}: "
            "choose the policy with --policy"
        )
    return settings.updated({name: node.get_parameter(name).value for name in values})
