"""What the ROS 2 explorer reads: the robot's map (and when maps came), its teammates' maps, its pose
and the coverage a simulator publishes; and what it says on the log while it waits for them, or
when they go bad or stop coming."""

from __future__ import annotations

import time
from collections.abc import Sequence

from nav_msgs.msg import OccupancyGrid as GridMessage
from rclpy.node import Node
from std_msgs.msg import Float32

from frontier_rl.core.world.grid import OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.errors import MapError
from frontier_rl.robot.map_watch import MapWait, MapWatch
from frontier_rl.robot.pose_source import PoseKind, PoseSource
from frontier_rl.robot.throttled_log import ThrottledLog
from frontier_rl.ros2.messages import MAP_QOS, grid_of
from frontier_rl.ros2.pose_listener import PoseListener
from frontier_rl.ros2.team_maps import TeamMaps

WARN_PERIOD_S = 5.0
"""Bad messages on one topic are logged at most this often (wall s)."""
WAIT_NOTICE_S = 5.0
"""A start waits this long (wall s) for its inputs before it says on the log what it waits for."""


class ExplorerInputs:
    """The explorer's inputs on ``node``: ``map`` (transient local, as slam_toolbox and map_server
    publish it), the ``teammates``' maps (:class:`~frontier_rl.ros2.team_maps.TeamMaps`), the pose
    from ``pose_source`` (:class:`~frontier_rl.ros2.pose_listener.PoseListener`) and ``coverage``."""

    def __init__(self, node: Node, pose_source: PoseSource, teammates: Sequence[str]) -> None:
        self._node = node
        self.grid: OccupancyGrid | None = None
        self.map_frame = "map"  # the robot's map's frame, which goals and the merged map are in
        self.maps = MapWatch()  # when the maps came: a goal ended is judged on a map from after it
        self.coverage: float | None = None  # until a simulator publishes it
        self._warnings = ThrottledLog(WARN_PERIOD_S)  # bad messages, per topic
        node.create_subscription(GridMessage, "map", self._on_map, MAP_QOS)
        self.team = TeamMaps(node, teammates, self.warn)
        self._poses = PoseListener(node, pose_source, self.warn)
        self._pose_from = (
            f"tf from the map to {pose_source.base_frame}"
            if pose_source.kind is PoseKind.TF
            else node.resolve_topic_name(pose_source.topic)
        )
        self._waiting_since = time.monotonic()
        node.create_subscription(Float32, "coverage", self._on_coverage, MAP_QOS)

    def _on_map(self, message: GridMessage) -> None:
        try:
            self.grid = grid_of(message)
            self.map_frame = message.header.frame_id or self.map_frame
            stamp_s = message.header.stamp.sec + message.header.stamp.nanosec * 1e-9
            self.maps.map_came(time.monotonic(), stamp_s, self.clock_now_s())
        except MapError as error:
            self.warn("map", f"map ignored: {error}")

    def _on_coverage(self, message: Float32) -> None:
        self.coverage = float(message.data)

    def clock_now_s(self) -> float:
        """The node's clock (s; simulated with ``use_sim_time``)."""
        return self._node.get_clock().now().nanoseconds * 1e-9

    def warn(self, topic: str, message: str) -> None:
        """Log ``message`` about ``topic`` at most every :data:`WARN_PERIOD_S` (rclpy's throttle
        shares one budget between the warnings of a node)."""
        if self._warnings.due("", topic, time.monotonic()):
            self._node.get_logger().warn(message)

    def waiting(self, what: str) -> None:
        """Say on the log what the explorer waits for, once it has waited :data:`WAIT_NOTICE_S`
        and then at most every :data:`WARN_PERIOD_S` (a namespace given to one and not the other, a
        pose on another topic, Nav2 not up: the status topic alone said so)."""
        if time.monotonic() - self._waiting_since >= WAIT_NOTICE_S and self._warnings.due(
            "", "waiting", time.monotonic()
        ):
            self._node.get_logger().info(f"waiting for {what}")

    def pose(self) -> Pose | None:
        """The robot's latest pose in the map's frame; None before one came."""
        return self._poses.pose(self.map_frame)

    def map_and_pose(self) -> tuple[OccupancyGrid, Pose] | None:
        """The map and the robot's pose once both are there; None (saying on the log, in time,
        which it waits for) before."""
        if self.grid is None:
            self.waiting(f"a map on {self._node.resolve_topic_name('map')}")
            return None
        pose = self.pose()
        if pose is None:
            self.waiting(f"a pose ({self._pose_from})")
            return None
        return self.grid, pose

    def explored(self) -> OccupancyGrid | None:
        """The map to explore: the robot's, merged with its teammates'; None before a map came."""
        return None if self.grid is None else self.team.merged(self.grid)

    def map_for_judging(self, label: str) -> bool:
        """Whether the map at hand may judge the goal just ended, ``label`` as the log names it
        (:class:`~frontier_rl.robot.map_watch.MapWatch`): False while a map from after its end may
        still come; a map that has stopped coming is said so."""
        wall_s = time.monotonic()  # every poll: the map's topic is named only when something is said
        wait = self.maps.judgement(wall_s)
        if wait is MapWait.STOPPED:
            self.warn(
                "map_stale",
                f"no map on {self._node.resolve_topic_name('map')} for {self.maps.age_s(wall_s):.1f} s (it came "
                f"every {self.maps.period_s or 0.0:.2f} s): {label} is judged on the last one",
            )
        elif wait is MapWait.QUIET and not self.maps.waits:
            self._node.get_logger().info(
                f"no map came on {self._node.resolve_topic_name('map')} while the robot stood after two goals (a "
                "mapper that maps as the robot moves): goals ended are judged on the map at hand from now on"
            )
        return wait is not MapWait.WAIT
