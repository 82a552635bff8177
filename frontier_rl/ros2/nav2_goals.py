"""The two Nav2 actions the explorer sends its goals to: ``navigate_to_pose`` (Nav2 plans on its
global costmap and drives), and ``follow_path`` (Nav2's controller follows a path the explorer
planned) for a goal found with the map's walls thinned: where SLAM drew a doorway too narrow for
the robot's costmap, Nav2's planner finds no way, while its controller checks the walls the LiDAR
sees now (a local costmap from live scans), as wide as the doorway is."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from builtin_interfaces.msg import Time
from nav2_msgs.action import FollowPath, NavigateToPose
from rclpy.action.client import ActionClient, ClientGoalHandle
from rclpy.node import Node
from rclpy.task import Future

from frontier_rl.core.world.robot import Pose
from frontier_rl.robot.explorer import Goal
from frontier_rl.ros2.messages import path_message, pose_stamped

NAVIGATE = "navigate_to_pose"
FOLLOW = "follow_path"


class Nav2Goals:
    """The explorer's clients of Nav2's ``navigate_to_pose`` and ``follow_path`` actions on ``node``
    (names relative to its namespace)."""

    def __init__(self, node: Node) -> None:
        self._node = node
        self._navigate: ActionClient[Any, Any, Any] = ActionClient(node, NavigateToPose, NAVIGATE)
        self._follow: ActionClient[Any, Any, Any] = ActionClient(node, FollowPath, FOLLOW)

    def ready(self) -> bool:
        """Whether Nav2's ``navigate_to_pose`` is up (``follow_path`` is used when it is up too)."""
        return self._navigate.server_is_ready()

    def action_for(self, goal: Goal) -> str:
        """The action ``goal`` goes to: ``follow_path`` for a goal with a path, while Nav2's
        controller serves it, else ``navigate_to_pose``."""
        return FOLLOW if goal.path is not None and self._follow.server_is_ready() else NAVIGATE

    def send(
        self, goal: Goal, frame: str, stamp: Time, on_feedback: Callable[[Any], None]
    ) -> tuple[str, Future[ClientGoalHandle[Any, Any, Any]]]:
        """Send ``goal`` (in the map ``frame``, stamped ``stamp``) to its action
        (:meth:`action_for`): the action's name and the future of Nav2's response."""
        action = self.action_for(goal)
        if action == FOLLOW:
            assert goal.path is not None
            request = FollowPath.Goal(path=path_message(goal.path, stamp, frame))
            return action, self._follow.send_goal_async(request, feedback_callback=on_feedback)
        request = NavigateToPose.Goal(pose=pose_stamped(Pose(goal.x, goal.y, 0.0), stamp, frame))
        return action, self._navigate.send_goal_async(request, feedback_callback=on_feedback)
