"""Where a robot's pose in the map comes from (ROS-free: the command line checks it before any ROS
import; :mod:`frontier_rl.ros2.pose_listener` listens)."""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

from frontier_rl.errors import SettingError


class PoseKind(StrEnum):
    """What carries the robot's pose."""

    POSE = "pose"
    """A ``geometry_msgs/PoseWithCovarianceStamped`` on a topic (slam_toolbox's ``pose``, AMCL's ``amcl_pose``)."""
    ODOM = "odom"
    """A ``nav_msgs/Odometry`` on a topic, in the map frame."""
    TF = "tf"
    """The transforms of ``tf`` and ``tf_static`` from the map's frame to the robot's base, as explore_lite reads it."""


@dataclass(frozen=True)
class PoseSource:
    """Where the robot's pose comes from: ``kind``, the ``topic`` of a pose or odometry (a relative
    name is in the node's namespace), and the robot's ``base_frame`` for ``tf`` (explore_lite's
    ``robot_base_frame``)."""

    kind: PoseKind = PoseKind.POSE
    topic: str = "pose"
    base_frame: str = "base_link"

    def __post_init__(self) -> None:
        if not self.base_frame.strip().lstrip("/"):
            raise SettingError("robot_base_frame", f"must name a frame, got {self.base_frame!r}")
