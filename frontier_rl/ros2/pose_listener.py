"""A ROS 2 node's listener of the robot's pose in the map, from where a
:class:`~frontier_rl.robot.pose_source.PoseSource` says: a pose topic (slam_toolbox's ``pose``,
AMCL's ``amcl_pose``), an odometry topic in the map frame, or the transforms of ``tf`` and
``tf_static`` (``map`` → ``odom`` → the robot's base, as explore_lite reads it). ``tf2_ros`` has
no wheel; ``TFMessage`` is generated from geometry2's vendored ``.msg`` (``make setup``), and the
chain is composed by :class:`~frontier_rl.robot.transforms.TransformTree`."""

from __future__ import annotations

from collections.abc import Callable

from geometry_msgs.msg import PoseWithCovarianceStamped, Transform
from nav_msgs.msg import Odometry
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from tf2_msgs.msg import TFMessage

from frontier_rl.core.world.robot import Pose
from frontier_rl.robot.map_message import yaw_of
from frontier_rl.robot.pose_source import PoseKind, PoseSource
from frontier_rl.robot.transforms import PlanarTransform, TransformTree
from frontier_rl.ros2.messages import robot_pose

TF_QOS = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)
"""``tf``'s QoS, as tf2_ros's listener subscribes."""
TF_STATIC_QOS = QoSProfile(
    depth=100, durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE
)
"""``tf_static``'s QoS: a late subscriber gets the static transforms published before it came."""


class PoseListener:
    """The robot's latest pose in the map from ``source``, on ``node``; a message that cannot be
    read is reported to ``problem`` (topic, text) and the last good pose kept. With a
    ``namespace``, the robot's topics are in it (``/NS/tf``, ``/NS/pose``; a node serving several
    robots, as Nav2's multi-robot launch names them), else in the node's."""

    def __init__(
        self, node: Node, source: PoseSource, problem: Callable[[str, str], None], namespace: str = ""
    ) -> None:
        self.source = source
        self._problem = problem
        self._pose: Pose | None = None
        self._tree = TransformTree()
        prefix = f"{namespace.strip('/')}/" if namespace.strip("/") else ""
        if source.kind is PoseKind.TF:
            node.create_subscription(TFMessage, f"{prefix}tf", self._on_transforms, TF_QOS)
            node.create_subscription(TFMessage, f"{prefix}tf_static", self._on_transforms, TF_STATIC_QOS)
        else:
            kind = PoseWithCovarianceStamped if source.kind is PoseKind.POSE else Odometry
            topic = source.topic if source.topic.startswith("/") else prefix + source.topic
            node.create_subscription(kind, topic, self._on_pose, 10)

    def pose(self, map_frame: str) -> Pose | None:
        """The robot's pose in ``map_frame`` (the map's frame, for ``tf``), or None before any."""
        if self.source.kind is PoseKind.TF:
            try:
                found = self._tree.lookup(map_frame, self.source.base_frame)
            except LookupError as error:
                self._problem("tf", f"no pose from tf yet: {error}")
            else:
                self._pose = Pose(found.x, found.y, found.yaw)
        return self._pose

    def _on_pose(self, message: PoseWithCovarianceStamped | Odometry) -> None:
        try:
            self._pose = robot_pose(message.pose.pose)
        except ValueError as error:
            self._problem("pose", f"pose ignored: {error}")

    def _on_transforms(self, message: TFMessage) -> None:
        for stamped in message.transforms:
            try:
                self._tree.set(stamped.header.frame_id, stamped.child_frame_id, planar_transform(stamped.transform))
            except ValueError as error:
                self._problem("tf", f"transform ignored: {error}")


def planar_transform(transform: Transform) -> PlanarTransform:
    """The planar part of a ``geometry_msgs/Transform``: its translation's x, y (m) and the rotation
    about z (rad)."""
    return PlanarTransform(float(transform.translation.x), float(transform.translation.y), yaw_of(transform.rotation))
