"""The two Nav2 actions the explorer sends its goals to: ``navigate_to_pose`` (Nav2 plans on its
global costmap and drives), and ``follow_path`` (Nav2's controller follows a path the explorer
planned) for a goal found with the map's walls thinned: where SLAM drew a doorway too narrow for
the robot's costmap, Nav2's planner finds no way, while its controller checks the walls the LiDAR
sees now (a local costmap from live scans), as wide as the doorway is.

The two are served by different Nav2 servers (bt_navigator, controller_server): a goal sent to one
does not preempt the other's, so the node cancels a goal under way when the next goes to the other
action. ``follow_path`` goes without a controller, goal checker or progress checker id, which Nav2
takes when it has one of each (its default parameters)."""

from __future__ import annotations

from collections.abc import Callable
from enum import Enum
from typing import Any

from builtin_interfaces.msg import Time
from nav2_msgs.action import FollowPath, NavigateToPose
from rclpy.action.client import ActionClient, ClientGoalHandle
from rclpy.node import Node
from rclpy.task import Future

from frontier_rl.core.world.robot import Pose
from frontier_rl.robot.explorer_decision import Goal
from frontier_rl.ros2.messages import path_message, pose_stamped

NAVIGATE = "navigate_to_pose"
FOLLOW = "follow_path"
FOLLOW_WAIT_S = 5.0
"""How long (wall s) after ``navigate_to_pose`` is up the explorer waits for ``follow_path`` before
it starts without it (a stand-in for Nav2 that serves only the first)."""


class GoalEnd(Enum):
    """How Nav2 ended a goal the explorer sent."""

    REACHED = "reached"
    REJECTED = "rejected"
    ABORTED = "aborted"


class Nav2Goals:
    """The explorer's clients of Nav2's ``navigate_to_pose`` and ``follow_path`` actions on ``node``
    (names relative to its namespace)."""

    def __init__(self, node: Node) -> None:
        self._navigate: ActionClient[Any, Any, Any] = ActionClient(node, NavigateToPose, NAVIGATE)
        self._follow: ActionClient[Any, Any, Any] = ActionClient(node, FollowPath, FOLLOW)
        self._navigate_up_at: float | None = None  # wall s

    def ready(self, wants_follow: bool, wall_s: float) -> bool:
        """Whether goals may be sent at wall time ``wall_s`` (s): ``navigate_to_pose`` is up and,
        when the explorer ``wants_follow`` (``recovery_paths``), ``follow_path`` is up too or has
        not come within :data:`FOLLOW_WAIT_S` of it."""
        if not self._navigate.server_is_ready():
            self._navigate_up_at = None
            return False
        if self._navigate_up_at is None:
            self._navigate_up_at = wall_s
        waited = wall_s - self._navigate_up_at >= FOLLOW_WAIT_S
        return not wants_follow or waited or self._follow.server_is_ready()

    def action_for(self, goal: Goal) -> str:
        """The action ``goal`` goes to: ``follow_path`` for a goal with a path, while Nav2's
        controller serves it, else ``navigate_to_pose``."""
        return FOLLOW if goal.path is not None and self._follow.server_is_ready() else NAVIGATE

    def send(
        self, action: str, goal: Goal, frame: str, stamp: Time, on_feedback: Callable[[Any], None]
    ) -> Future[ClientGoalHandle[Any, Any, Any]]:
        """Send ``goal`` (in the map ``frame``, stamped ``stamp``) to ``action``
        (:meth:`action_for`'s): the future of Nav2's response."""
        if action == FOLLOW:
            assert goal.path is not None
            request = FollowPath.Goal(path=path_message(goal.path, stamp, frame))
            return self._follow.send_goal_async(request, feedback_callback=on_feedback)
        request = NavigateToPose.Goal(pose=pose_stamped(Pose(goal.x, goal.y, 0.0), stamp, frame))
        return self._navigate.send_goal_async(request, feedback_callback=on_feedback)


def error_text(result: Any) -> str:
    """Nav2's error in an action's result (``error_code``, ``error_msg``, as both actions' results
    have them): ``", error 101: ..."``, or "" for none."""
    code, message = getattr(result, "error_code", 0), str(getattr(result, "error_msg", "")).strip()
    if not code and not message:
        return ""
    return f", error {code}" + (f": {message}" if message else "")
