"""ROS's arguments (``--ros-args ...``) checked as ``rclpy.init`` parses them, before anything slow
starts: a command that loads a model or starts ranking workers first reported a bad one seconds
later."""

from __future__ import annotations

from collections.abc import Sequence

from rclpy.impl.implementation_singleton import rclpy_implementation
from rclpy.utilities import remove_ros_args

from frontier_rl.errors import ConfigError


def ros_args_error(error: Exception) -> ConfigError | None:
    """The one-line error for rclpy's refusal of ROS's arguments (a rule rcl cannot parse, an
    argument ROS does not know); any other rcl error while ROS starts is said under
    ``--ros-args`` too (``rclpy.init`` raises a plain ``RCLError`` for what it cannot parse), and
    None is for errors not rcl's."""
    if isinstance(error, rclpy_implementation.UnknownROSArgsError):
        return ConfigError(f"--ros-args: arguments ROS does not know: {error}")
    if isinstance(error, rclpy_implementation.RCLError):
        return ConfigError(f"--ros-args: {str(error).split(', at /')[0]}")
    return None


def check_ros_args(ros_args: Sequence[str]) -> None:
    """Parse ``ros_args`` as ``rclpy.init`` will, without starting ROS (no context, no network).

    Raises:
        ConfigError: one line naming what rcl cannot parse, or the arguments ROS does not know.
    """
    try:
        remove_ros_args(["frontier-rl", *ros_args])
    except (rclpy_implementation.UnknownROSArgsError, rclpy_implementation.RCLError) as error:
        problem = ros_args_error(error)
        assert problem is not None
        raise problem from None
