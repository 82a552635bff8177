"""``frontier-rl ros2 sim``: the simulator as a ROS 2 robot.

It publishes what a robot with slam_toolbox publishes (the map it builds on ``map``, transient
local; its pose on ``pose`` and ``odom``; a ``scan``), the simulated clock on ``/clock`` (for nodes
with ``use_sim_time``), and the share of the world's explorable space mapped on ``coverage``; and it
serves Nav2's ``navigate_to_pose`` action, driving with the engine's navigation. Time runs while the
robot drives for a goal, at ``rate`` times the wall clock (as fast as it can with no rate); a robot
without a goal stands still and its clock with it, so that a decision costs no simulated time, as
in an in-process episode.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

from builtin_interfaces.msg import Duration, Time
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav2_msgs.action import NavigateToPose
from nav_msgs.msg import OccupancyGrid as GridMessage
from nav_msgs.msg import Odometry
from rclpy.action.server import ActionServer, CancelResponse, GoalResponse, ServerGoalHandle
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.task import Future
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan
from std_msgs.msg import Float32

from frontier_rl.robot.sim_robot import GoalStatus, SimulatedRobot
from frontier_rl.ros2.messages import grid_message, laser_scan, odometry, pose_stamped, pose_with_covariance, robot_pose

MAP_QOS = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE)
"""The map's QoS, as map_server and slam_toolbox publish it: a late subscriber gets the last map."""
_STEP_PERIOD_S = 0.005
"""How often (wall s) the node looks whether the robot may drive on."""
_MAP_PERIOD_S = 0.1
"""The map is published at most this often (wall s) while the robot drives."""
_IDLE_PERIOD_S = 0.1
"""A robot without a goal publishes its pose and scan this often (wall s)."""


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
    """The goal under way: its handle, the future its end is set on, and when it began (sim s)."""

    handle: ServerGoalHandle[Any, Any, Any]
    done: Future[GoalStatus | str]
    started_s: float


class SimNode(Node):
    """One simulated robot as a ROS 2 node.

    Args:
        robot: the simulated robot.
        rate: simulated seconds per wall second; None for as fast as the node can step.
        namespace: the robot's namespace (its topics and action are relative to it).
    """

    def __init__(self, robot: SimulatedRobot, rate: float | None = 1.0, namespace: str = "") -> None:
        super().__init__("frontier_rl_sim", namespace=namespace)
        self.robot = robot
        self.rate = rate
        self._map_pub = self.create_publisher(GridMessage, "map", MAP_QOS)
        self._pose_pub = self.create_publisher(PoseWithCovarianceStamped, "pose", 10)
        self._odom_pub = self.create_publisher(Odometry, "odom", 10)
        self._scan_pub = self.create_publisher(LaserScan, "scan", 10)
        self._coverage_pub = self.create_publisher(Float32, "coverage", MAP_QOS)
        self._clock_pub = self.create_publisher(Clock, "/clock", 10)
        self._server = ActionServer(
            self, NavigateToPose, "navigate_to_pose", execute_callback=self._execute,
            goal_callback=self._check_goal, cancel_callback=lambda _: CancelResponse.ACCEPT,
        )  # fmt: skip
        self._active: _ActiveGoal | None = None
        self._anchor = (time.monotonic(), robot.sim_time)  # wall and sim time the drive is paced from
        self._map_sent_at = self._state_sent_at = -math.inf
        self.goals = 0
        self._publish_state(with_map=True)
        self._timer = self.create_timer(_STEP_PERIOD_S, self._drive)

    # --------------------------------------------------------------- the action
    def _check_goal(self, request: Any) -> GoalResponse:
        try:
            robot_pose(request.pose.pose)
        except ValueError as error:
            self.get_logger().warn(f"goal rejected: {error}")
            return GoalResponse.REJECT
        return GoalResponse.ACCEPT

    async def _execute(self, handle: ServerGoalHandle[Any, Any, Any]) -> Any:
        """Drive to the goal until it ends (the timer steps it); a newer goal preempts it."""
        goal = robot_pose(handle.request.pose.pose)
        self._end_active(GoalStatus.ABORTED)  # preempted
        done: Future[GoalStatus | str] = Future()
        self.robot.send_goal(goal.x, goal.y)
        self._active = _ActiveGoal(handle, done, self.robot.sim_time)
        self._anchor = (time.monotonic(), self.robot.sim_time)
        self.goals += 1
        status = await done
        result = NavigateToPose.Result()
        if status == "canceled":
            handle.canceled()
        elif status is GoalStatus.SUCCEEDED:
            handle.succeed()
        else:
            handle.abort()
        return result

    def _end_active(self, status: GoalStatus | str) -> None:
        if self._active is not None:
            self.robot.cancel()
            self._active.done.set_result(status)
            self._active = None

    # ----------------------------------------------------------------- driving
    def _drive(self) -> None:
        """Step the robot as far as the pace allows, publishing as it goes."""
        active = self._active
        if active is None:
            self._anchor = (time.monotonic(), self.robot.sim_time)
            if time.monotonic() - self._state_sent_at >= _IDLE_PERIOD_S:
                self._publish_state(with_map=False)  # for late subscribers: the map is transient local already
            return
        if active.handle.is_cancel_requested:
            self._end_active("canceled")
            self._publish_state(with_map=True)
            return
        wall0, sim0 = self._anchor
        target = math.inf if self.rate is None else sim0 + self.rate * (time.monotonic() - wall0)
        stepped = False
        while self._active is active and self.robot.sim_time < target:
            end = self.robot.step()
            stepped = True
            if end is not None:
                self._end_active(end.status)
                break
            if self.rate is None:
                break  # one step per timer tick: the executor serves the explorer in between
        if stepped:
            self._publish_state(with_map=self._active is None)
            if self._active is active:
                self._feedback(active)

    def _feedback(self, active: _ActiveGoal) -> None:
        feedback = NavigateToPose.Feedback()
        pose, goal = self.robot.pose, self.robot.goal
        feedback.current_pose = pose_stamped(pose, stamp_of(self.robot.sim_time))
        feedback.navigation_time = duration_of(self.robot.sim_time - active.started_s)
        if goal is not None:
            feedback.distance_remaining = math.hypot(goal[0] - pose.x, goal[1] - pose.y)
        active.handle.publish_feedback(feedback)

    def _publish_state(self, with_map: bool) -> None:
        """The clock, the pose, a scan, and the map (at most every ``_MAP_PERIOD_S``, or now)."""
        stamp = stamp_of(self.robot.sim_time)
        self._clock_pub.publish(Clock(clock=stamp))
        pose = self.robot.pose
        self._pose_pub.publish(pose_with_covariance(pose, stamp))
        self._odom_pub.publish(odometry(pose, stamp))
        lidar = self.robot.sim.config.lidar
        self._scan_pub.publish(laser_scan(self.robot.scan(), lidar.min_range, lidar.max_range, stamp))
        now = self._state_sent_at = time.monotonic()
        if with_map or now - self._map_sent_at >= _MAP_PERIOD_S:
            self._map_pub.publish(grid_message(self.robot.map(), stamp))
            self._coverage_pub.publish(Float32(data=float(self.robot.sim.coverage)))
            self._map_sent_at = now
