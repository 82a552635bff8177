"""``frontier-rl ros2 rank``: the thesis's ranking service on ROS 2, as the ROS 1 node serves it.

It subscribes to each robot's map (``/<ns>/map``, transient local) and pose: ``/<ns>/pose``, a
``PoseWithCovarianceStamped`` as slam_toolbox publishes it, an ``Odometry``, or the transforms of
``/<ns>/tf`` and ``/<ns>/tf_static`` (:class:`~frontier_rl.ros2.pose_listener.PoseListener`). A
``std_msgs/String`` on ``/frontier_request`` naming a namespace (optionally followed by a request
id) is answered on ``/frontier_list`` with that robot's top frontier centres as a
``geometry_msgs/PoseArray`` in its map frame, stamped with the stamp of the map they were ranked
on; then a JSON line on ``/frontier_status``, the weight on ``/frontier_weight`` and RViz markers on
``/frontier_markers``. Every request is answered, with a reason when the answer is empty
(:mod:`frontier_rl.robot.ranking_service`); each robot ranks in a worker process of its own.
"""

from __future__ import annotations

import functools
import math
import time

import numpy as np
from builtin_interfaces.msg import Time
from geometry_msgs.msg import Pose, PoseArray
from nav_msgs.msg import OccupancyGrid as GridMessage
from rclpy.node import Node
from std_msgs.msg import Float32, String
from visualization_msgs.msg import Marker, MarkerArray

from frontier_rl.robot.answers import MapInfo, map_cells, marker_style
from frontier_rl.robot.pose_source import PoseSource
from frontier_rl.robot.ranking_service import Answer, RankingService, RobotPose
from frontier_rl.robot.throttled_log import ThrottledLog
from frontier_rl.ros2.messages import MAP_QOS
from frontier_rl.ros2.pose_listener import PoseListener

_QUEUE = 100
"""Depth of the request and answer topics: a burst of requests is queued, not dropped."""
_WARN_PERIOD_S = 5.0
"""A robot's bad pose messages are logged at most this often."""


class RankingNode(Node):
    """The ranking service as a ROS 2 node.

    Args:
        service: the service, its workers started.
        pose_source: where each robot's pose comes from, in its namespace (a pose or odometry
            topic, or ``tf`` to the robot's base frame); a pose topic by default.
    """

    def __init__(self, service: RankingService, pose_source: PoseSource | None = None) -> None:
        super().__init__("frontier_rl_ranking")
        self.service = service
        settings = service.settings
        self._list_pub = self.create_publisher(PoseArray, "/frontier_list", _QUEUE)
        self._status_pub = self.create_publisher(String, "/frontier_status", _QUEUE)
        self._weight_pub = self.create_publisher(Float32, "/frontier_weight", MAP_QOS)
        self._marker_pub = self.create_publisher(MarkerArray, "/frontier_markers", 10)
        self._warnings = ThrottledLog(_WARN_PERIOD_S)
        self._poses: dict[str, PoseListener] = {}
        for ns in settings.robots:
            prefix = f"/{ns}" if ns else ""
            self.create_subscription(GridMessage, f"{prefix}/map", lambda m, ns=ns: self._on_map(ns, m), MAP_QOS)
            problem = functools.partial(self._pose_problem, ns)
            self._poses[ns] = PoseListener(self, pose_source or PoseSource(), problem, ns)
        self.create_subscription(String, "/frontier_request", self._on_request, _QUEUE)
        service.connect(self._publish, self._warn, self._now)
        fixed = service.fixed_weight
        self._weight_pub.publish(Float32(data=math.nan if fixed is None else fixed))

    def _warn(self, text: str) -> None:
        self.get_logger().warn(text)

    def _now(self) -> float:
        return self.get_clock().now().nanoseconds * 1e-9

    def _on_map(self, ns: str, message: GridMessage) -> None:
        stamp_ns = message.header.stamp.sec * 10**9 + message.header.stamp.nanosec or round(self._now() * 1e9)
        data = np.frombuffer(memoryview(message.data), np.int8) if len(message.data) else np.zeros(0, np.int8)
        self.service.on_map(
            ns, lambda sequence: map_cells(message.info, message.header.frame_id, data, stamp_ns, sequence)
        )

    def _pose_problem(self, ns: str, topic: str, text: str) -> None:
        if self._warnings.due(ns, topic, time.monotonic()):
            self.get_logger().warn(f"robot {ns!r}: {text}" if ns else text)

    def _pose_of(self, ns: str, info: MapInfo | None) -> RobotPose | None:
        """Robot ``ns``'s latest pose in its map's frame; None for an unknown robot, or before any."""
        listener = self._poses.get(ns)
        if listener is None or info is None:
            return None
        pose = listener.pose(info.frame.frame_id)
        return None if pose is None else (pose.x, pose.y, pose.theta)

    def _on_request(self, message: String) -> None:
        self.service.on_request(message.data, self._pose_of)

    def _publish(self, answer: Answer) -> None:
        """The answer, its markers, the weight and the status line (in that order)."""
        message = PoseArray()
        if answer.info is not None:
            message.header.frame_id = answer.info.frame.frame_id
            seconds, nanoseconds = divmod(answer.info.stamp_ns, 10**9)
            message.header.stamp = Time(sec=seconds, nanosec=nanoseconds)
        for x, y in answer.centres:
            pose = Pose()
            pose.position.x, pose.position.y = float(x), float(y)
            pose.orientation.w = 1.0
            message.poses.append(pose)
        self._list_pub.publish(message)
        self._marker_pub.publish(_markers(message))
        self._weight_pub.publish(Float32(data=math.nan if answer.weight is None else answer.weight))
        self._status_pub.publish(String(data=answer.status.to_json()))


def _markers(answer: PoseArray) -> MarkerArray:
    """The answer's poses as RViz spheres, green (best) to red, after a marker that clears the old ones."""
    markers = [Marker(action=Marker.DELETEALL)]
    n = len(answer.poses)
    for i, pose in enumerate(answer.poses):
        marker = Marker(header=answer.header, ns="frontiers", id=i, type=Marker.SPHERE, action=Marker.ADD, pose=pose)
        size, marker.color.g, marker.color.r = marker_style(i, n)
        marker.scale.x = marker.scale.y = marker.scale.z = size
        marker.color.a = 0.9
        markers.append(marker)
    return MarkerArray(markers=markers)
