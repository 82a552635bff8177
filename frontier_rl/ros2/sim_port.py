"""One simulated robot's side of ROS 2: its topics and its ``navigate_to_pose`` and ``follow_path``
action servers (Nav2's: planning and driving to a pose, and following a path it is given)."""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from builtin_interfaces.msg import Duration, Time
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav2_msgs.action import FollowPath, NavigateToPose
from nav_msgs.msg import OccupancyGrid as GridMessage
from nav_msgs.msg import Odometry
from rclpy.action.server import ActionServer, CancelResponse, GoalResponse, ServerGoalHandle
from rclpy.node import Node
from rclpy.task import Future
from sensor_msgs.msg import LaserScan
from std_msgs.msg import Float32
from tf2_msgs.msg import TFMessage

from frontier_rl.robot.explorer_decision import GoalStatus
from frontier_rl.robot.sim_robot import SimulatedRobot
from frontier_rl.robot.transforms import IDENTITY, PlanarTransform
from frontier_rl.ros2.messages import (
    MAP_QOS,
    grid_message,
    laser_scan,
    odometry,
    path_points,
    pose_stamped,
    pose_with_covariance,
    robot_pose,
    transform_stamped,
)
from frontier_rl.ros2.nav2_goals import Nav2Action
from frontier_rl.ros2.pose_listener import TF_QOS, TF_STATIC_QOS

_MAP_PERIOD_S = 0.1
"""A robot's map is published at most this often (wall s) while it drives, and when a goal ends."""
_CANCELED = "canceled"
_STATIC_FRAMES = (("base_footprint", "base_link"), ("base_link", "base_scan"))
"""The robot's fixed frames on ``tf_static`` (parent, child), each where its parent is; ``tf`` has
``map`` → ``odom`` (the start pose) → ``base_footprint`` (the robot's pose from its start)."""


def stamp_of(seconds: float) -> Time:
    """A ``builtin_interfaces/Time`` of ``seconds`` (s)."""
    whole = math.floor(seconds)
    return Time(sec=int(whole), nanosec=int((seconds - whole) * 1e9))


def duration_of(seconds: float) -> Duration:
    """A ``builtin_interfaces/Duration`` of ``seconds`` (s)."""
    whole = math.floor(seconds)
    return Duration(sec=int(whole), nanosec=int((seconds - whole) * 1e9))


@dataclass
class _ActiveGoal:
    """The goal under way: its handle, the future its end is set on, when it began (sim s), and
    whether it is a path to follow (``follow_path``) rather than a pose (``navigate_to_pose``)."""

    handle: ServerGoalHandle[Any, Any, Any]
    done: Future[GoalStatus | str]
    started_s: float
    follows_path: bool


class RobotPort:
    """A simulated robot's publishers and action server, in ``namespace`` ("" for none), on ``node``."""

    def __init__(self, node: Node, namespace: str, robot: SimulatedRobot) -> None:
        self.robot = robot
        self.namespace = namespace.strip("/")
        prefix = f"{self.namespace}/" if self.namespace else ""
        self._node = node
        self._map_pub = node.create_publisher(GridMessage, f"{prefix}map", MAP_QOS)
        self._pose_pub = node.create_publisher(PoseWithCovarianceStamped, f"{prefix}pose", 10)
        self._odom_pub = node.create_publisher(Odometry, f"{prefix}odom", 10)
        self._scan_pub = node.create_publisher(LaserScan, f"{prefix}scan", 10)
        self._coverage_pub = node.create_publisher(Float32, f"{prefix}coverage", MAP_QOS)
        self._tf_pub = node.create_publisher(TFMessage, f"{prefix}tf", TF_QOS)
        start = robot.sim.world.start
        self._odom_origin = PlanarTransform(start.x, start.y, start.theta)  # odometry starts where the robot does
        static = [transform_stamped(parent, child, IDENTITY, stamp_of(0.0)) for parent, child in _STATIC_FRAMES]
        self._tf_static_pub = node.create_publisher(TFMessage, f"{prefix}tf_static", TF_STATIC_QOS)
        self._tf_static_pub.publish(TFMessage(transforms=static))
        self._servers = [
            ActionServer(
                node,
                action,
                f"{prefix}{name}",
                execute_callback=execute,
                goal_callback=check,
                cancel_callback=lambda _: CancelResponse.ACCEPT,
            )
            for action, name, execute, check in (
                (NavigateToPose, Nav2Action.NAVIGATE, self._navigate, self._check_goal),
                (FollowPath, Nav2Action.FOLLOW, self._follow, self._check_path),
            )
        ]
        self._active: _ActiveGoal | None = None
        self._map_sent_at = -math.inf
        self._scan_at = (-math.inf, -math.inf)  # simulated and wall time of the last scan published (s)
        self.goals = 0

    @property
    def busy(self) -> bool:
        """Whether a goal is under way."""
        return self._active is not None

    # -------------------------------------------------------------- the actions
    def _check_goal(self, request: Any) -> GoalResponse:
        return self._check(lambda: robot_pose(request.pose.pose))

    def _check_path(self, request: Any) -> GoalResponse:
        return self._check(lambda: path_points(request.path))

    def _check(self, read: Callable[[], object]) -> GoalResponse:
        """Accept a goal that ``read`` reads without a ``ValueError``; reject it with a warning."""
        try:
            read()
        except ValueError as error:
            self._node.get_logger().warn(f"{self.namespace or 'robot'}: goal rejected: {error}")
            return GoalResponse.REJECT
        return GoalResponse.ACCEPT

    async def _navigate(self, handle: ServerGoalHandle[Any, Any, Any]) -> Any:
        """Drive to the goal's pose until it ends."""
        goal = robot_pose(handle.request.pose.pose)
        await self._run(handle, lambda: self.robot.send_goal(goal.x, goal.y), follows_path=False)
        return NavigateToPose.Result()

    async def _follow(self, handle: ServerGoalHandle[Any, Any, Any]) -> Any:
        """Follow the goal's path until it ends."""
        points = path_points(handle.request.path)
        await self._run(handle, lambda: self.robot.follow_path(points), follows_path=True)
        return FollowPath.Result()

    async def _run(
        self, handle: ServerGoalHandle[Any, Any, Any], start: Callable[[], None], follows_path: bool
    ) -> None:
        """Run a goal ``start`` sets the robot off on until it ends (the node's timer steps it),
        and end its handle as it ended; a newer goal, of either action, preempts it."""
        self._end(GoalStatus.ABORTED, stop=not follows_path)  # preempted (a path to follow may go on: start)
        done: Future[GoalStatus | str] = Future()
        start()
        self._active = _ActiveGoal(handle, done, self.robot.sim_time, follows_path)
        self.goals += 1
        status = await done
        if status == _CANCELED:
            handle.canceled()
        elif status is GoalStatus.SUCCEEDED:
            handle.succeed()
        else:
            handle.abort()

    def _end(self, status: GoalStatus | str, stop: bool = True) -> None:
        if self._active is not None:
            if stop:
                self.robot.cancel()
            self._active.done.set_result(status)
            self._active = None
            self._map_sent_at = -math.inf  # the map as the goal ended, before its result

    def check_cancel(self) -> None:
        """End the goal under way if its client asked to cancel it."""
        if self._active is not None and self._active.handle.is_cancel_requested:
            self._end(_CANCELED)

    # ----------------------------------------------------------------- driving
    def step(self, until: float) -> None:
        """Drive the goal under way on by one map update; without one, stand still until ``until`` (sim s)."""
        active = self._active
        if active is None:
            self.robot.stand(until)
            return
        end = self.robot.step()
        if end is not None:
            self._end(end.status)
            return
        pose, goal = self.robot.pose, self.robot.goal
        distance = 0.0 if goal is None else math.hypot(goal[0] - pose.x, goal[1] - pose.y)
        if active.follows_path:
            active.handle.publish_feedback(FollowPath.Feedback(distance_to_goal=distance))
            return
        feedback = NavigateToPose.Feedback()
        feedback.current_pose = pose_stamped(pose, stamp_of(self.robot.sim_time))
        feedback.navigation_time = duration_of(self.robot.sim_time - active.started_s)
        feedback.distance_remaining = distance
        active.handle.publish_feedback(feedback)

    def publish_state(self, with_map: bool) -> None:
        """The pose, a scan (at the LiDAR's rate, when subscribed), and the map (at most every
        ``_MAP_PERIOD_S``, or now)."""
        stamp = stamp_of(self.robot.sim_time)
        pose = self.robot.pose
        self._pose_pub.publish(pose_with_covariance(pose, stamp))
        self._odom_pub.publish(odometry(pose, stamp))
        in_odom = self._odom_origin.inverse().then(PlanarTransform(pose.x, pose.y, pose.theta))
        self._tf_pub.publish(
            TFMessage(
                transforms=[
                    transform_stamped("map", "odom", self._odom_origin, stamp),
                    transform_stamped("odom", "base_footprint", in_odom, stamp),
                ]
            )
        )
        lidar = self.robot.sim.config.lidar
        now = time.monotonic()
        sim_s, wall_s = self._scan_at
        due = abs(self.robot.sim_time - sim_s) >= lidar.period or now - wall_s >= lidar.period
        if due and self._scan_pub.get_subscription_count():  # at the LiDAR's rate (simulated or wall), for someone
            self._scan_pub.publish(laser_scan(self.robot.scan(), lidar.min_range, lidar.max_range, stamp))
            self._scan_at = (self.robot.sim_time, now)
        if with_map or now - self._map_sent_at >= _MAP_PERIOD_S:
            self._map_pub.publish(grid_message(self.robot.map(), stamp))
            self._coverage_pub.publish(Float32(data=float(self.robot.sim.coverage)))
            self._map_sent_at = now
