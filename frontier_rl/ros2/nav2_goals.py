"""The two Nav2 actions the explorer sends its goals to: ``navigate_to_pose`` (Nav2 plans on its
global costmap and drives), and ``follow_path`` (Nav2's controller follows a path the explorer
planned) for a goal found with the map's walls thinned: where SLAM drew a doorway too narrow for
the robot's costmap, Nav2's planner finds no way, while its controller checks the walls the LiDAR
sees now (a local costmap from live scans), as wide as the doorway is.

The two are served by different Nav2 servers (bt_navigator, controller_server): a goal sent to one
does not preempt the other's, so a goal under way is cancelled when the next goes to the other
action. Each goal names the Nav2 plugins the node's parameters give (:class:`Nav2Plugins`): a
behaviour tree for ``navigate_to_pose``, a controller, goal checker and progress checker for
``follow_path``; none ("") lets Nav2 choose, which it does when it has one of each (its default
parameters).

Goals are numbered as they are sent (a path goal on ``follow_path`` again at every planner tick): the response,
feedback or result of an older one (or of one dropped or cancelled) is ignored, and such a goal a
server accepted is cancelled, so that it does not drive on."""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from enum import StrEnum
from functools import partial
from typing import Any

from action_msgs.msg import GoalStatus as ActionStatus
from builtin_interfaces.msg import Time
from nav2_msgs.action import FollowPath, NavigateToPose
from rclpy.action.client import ActionClient, ClientGoalHandle
from rclpy.node import Node
from rclpy.task import Future

from frontier_rl.core.world.robot import Pose
from frontier_rl.robot.explorer_decision import Goal, GoalStatus
from frontier_rl.robot.explorer_params import Nav2Plugins
from frontier_rl.ros2.messages import path_message, pose_stamped


class Nav2Action(StrEnum):
    """Nav2's actions the explorer sends goals to, by their names (the action clients' and servers')."""

    NAVIGATE = "navigate_to_pose"
    """bt_navigator's: a pose, which Nav2 plans its own way to and replans."""
    FOLLOW = "follow_path"
    """controller_server's: a path, which its controller follows as given."""


FOLLOW_WAIT_S = 5.0
"""How long (wall s) after ``navigate_to_pose`` is up the explorer waits for ``follow_path`` before
it starts without it (a stand-in for Nav2 that serves only the first)."""


@dataclass(frozen=True)
class GoalOutcome:
    """How Nav2 ended the goal in flight.

    Attributes:
        status: succeeded, aborted, rejected, or cancelled by another node.
        code: the action's status number (``action_msgs/GoalStatus``), 0 for a rejection.
        error: Nav2's own reason in the result (:func:`error_text`), "" for none.
        error_code: Nav2's error code in the result (``FollowPath.Result.INVALID_CONTROLLER``, ...),
            0 for none.
    """

    status: GoalStatus
    code: int = 0
    error: str = ""
    error_code: int = 0

    def sentence(self, label: str) -> str:
        """How the goal named ``label`` ("goal 3", "the way home") ended, for the log and the status."""
        return {
            GoalStatus.SUCCEEDED: f"{label} reached",
            GoalStatus.REJECTED: f"{label} rejected by Nav2",
            GoalStatus.CANCELED: f"{label} cancelled by another node",
            GoalStatus.ABORTED: f"{label} aborted by Nav2 (status {self.code}{self.error})",
        }[self.status]


def goal_request(goal: Goal, action: Nav2Action, frame: str, stamp: Time, plugins: Nav2Plugins) -> Any:
    """The request that sends ``goal`` to ``action`` (:attr:`Nav2Action.FOLLOW`: its path, else its point) in
    the map ``frame``, stamped ``stamp``, naming ``plugins``."""
    if action is Nav2Action.FOLLOW:
        assert goal.path is not None
        return FollowPath.Goal(
            path=path_message(goal.path, stamp, frame),
            controller_id=plugins.controller_id,
            goal_checker_id=plugins.goal_checker_id,
            progress_checker_id=plugins.progress_checker_id,
        )
    pose = pose_stamped(Pose(goal.x, goal.y, 0.0), stamp, frame)
    return NavigateToPose.Goal(pose=pose, behavior_tree=plugins.behavior_tree)


class Nav2Goals:
    """The explorer's goal in flight with Nav2's ``navigate_to_pose`` or ``follow_path`` action on
    ``node`` (names relative to its namespace), and how it ended (``on_end``).

    Attributes:
        action: the action of the goal in flight (or of the last one).
        plugins: the Nav2 plugins each goal names from now on.
    """

    def __init__(self, node: Node, on_end: Callable[[GoalOutcome], None], plugins: Nav2Plugins | None = None) -> None:
        self.plugins = plugins or Nav2Plugins()
        self._navigate: ActionClient[Any, Any, Any] = ActionClient(node, NavigateToPose, Nav2Action.NAVIGATE)
        self._follow: ActionClient[Any, Any, Any] = ActionClient(node, FollowPath, Nav2Action.FOLLOW)
        self._navigate_up_at: float | None = None  # wall s
        self._on_end = on_end
        self.action = Nav2Action.NAVIGATE
        self._sent = 0  # goals sent; a response, feedback or result of an older one is ignored
        self._handle: ClientGoalHandle[Any, Any, Any] | None = None
        self._unanswered: set[int] = set()  # goals sent whose response has not come
        self._cancels: list[Future[Any]] = []  # cancel requests sent, their answers awaited at stop
        self._stop: Future[bool] | None = None  # the stop's: set once the two above are settled
        self._cancelling = False  # Nav2 said it cancels a goal, since the last call to cancel()
        self._heard_at = math.inf  # when Nav2 last said something of the goal in flight (wall s)

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

    def action_for(self, goal: Goal) -> Nav2Action:
        """The action ``goal`` goes to: ``follow_path`` for a goal with a path, while Nav2's
        controller serves it, else ``navigate_to_pose``."""
        return Nav2Action.FOLLOW if goal.path is not None and self._follow.server_is_ready() else Nav2Action.NAVIGATE

    def send(self, goal: Goal, frame: str, stamp: Time) -> Nav2Action:
        """Send ``goal`` (in the map ``frame``, stamped ``stamp``) to the action :meth:`action_for`
        gives, which it returns; a goal under way on the other action is cancelled first."""
        self._sent += 1
        number = self._sent
        if self._heard_at == math.inf:  # a goal sent again (its path renewed) does not reset Nav2's silence
            self._heard()
        action = self.action_for(goal)
        if self._handle is not None and action is not self.action:  # two servers: the other's goal would drive on
            self._cancel(self._handle)
            self._handle = None
        self.action = action
        client = self._follow if action is Nav2Action.FOLLOW else self._navigate
        request = goal_request(goal, action, frame, stamp, self.plugins)
        future = client.send_goal_async(request, feedback_callback=partial(self._feedback, number))
        self._unanswered.add(number)
        future.add_done_callback(lambda f: self._on_response(number, f))
        return action

    def silent_for(self, wall_s: float) -> float:
        """How long (wall s) Nav2 has said nothing of the goal in flight at wall time ``wall_s``;
        0 while none is awaited (none sent, or it ended, was dropped or cancelled)."""
        return max(wall_s - self._heard_at, 0.0)

    def drop(self) -> None:
        """Forget the goal in flight (its server went away): whatever the old server says later is
        ignored, and a stop waits neither for its answer nor for a cancel request sent to it."""
        self._forget()
        self._unanswered.clear()
        self._cancels.clear()
        self._settle()

    def cancel(self) -> Future[bool] | None:
        """Ask Nav2 to cancel the goal under way, and ignore whatever Nav2 says of it later. A goal
        whose response has not come (a path sent again, the goal just sent) is cancelled when it
        comes, accepted: stopping, the robot must not drive on to a goal Nav2 accepts after the
        explorer has gone. A future set once every goal sent has been answered and every cancel
        request too: whether Nav2 said it cancels one; None when there is nothing to wait for."""
        handle = self._handle
        self._forget()
        self._cancelling = False
        if handle is not None:
            self._cancel(handle)
        if not self._awaiting():
            return None
        self._stop = Future()
        self._settle()
        return self._stop

    @property
    def unanswered(self) -> int:
        """How many goals sent Nav2 has not answered yet."""
        return len(self._unanswered)

    def _forget(self) -> None:
        self._sent += 1
        self._handle, self._heard_at = None, math.inf

    def _cancel(self, handle: ClientGoalHandle[Any, Any, Any]) -> None:
        """Ask Nav2 to cancel ``handle``'s goal; a stop waits for the answer."""
        self._cancels = [request for request in self._cancels if not request.done()]
        request = handle.cancel_goal_async()
        self._cancels.append(request)
        request.add_done_callback(self._cancel_answered)

    def _cancel_answered(self, request: Future[Any]) -> None:
        answer = request.result()
        self._cancelling = self._cancelling or (answer is not None and len(answer.goals_canceling) > 0)
        self._settle()

    def _settle(self) -> None:
        """Set the stop's future once every goal sent has been answered and every cancel request
        too: whether Nav2 said it cancels a goal."""
        if self._stop is not None and not self._stop.done() and not self._awaiting():
            self._stop.set_result(self._cancelling)

    def _awaiting(self) -> bool:
        """Whether a goal sent or a cancel request has not been answered yet."""
        return bool(self._unanswered) or not all(request.done() for request in self._cancels)

    def _heard(self) -> None:
        self._heard_at = time.monotonic()

    def _feedback(self, number: int, _message: Any) -> None:
        if number == self._sent:
            self._heard()

    def _on_response(self, number: int, future: Future[ClientGoalHandle[Any, Any, Any]]) -> None:
        handle = future.result()
        self._unanswered.discard(number)
        if handle is None or number != self._sent:
            # a newer goal went out (or this one was dropped or cancelled): this one must not drive
            # on; a server a newer goal went to has preempted it already, the other has not
            if handle is not None and handle.accepted:
                self._cancel(handle)
            self._settle()
            return
        self._heard()
        if not handle.accepted:
            self._heard_at = math.inf
            self._on_end(GoalOutcome(GoalStatus.REJECTED))
            return
        self._handle = handle
        handle.get_result_async().add_done_callback(lambda f: self._on_result(number, f))

    def _on_result(self, number: int, future: Future[Any]) -> None:
        result = future.result()
        if number != self._sent or result is None:
            return
        status = result.status
        self._handle, self._heard_at = None, math.inf
        if status == ActionStatus.STATUS_SUCCEEDED:
            self._on_end(GoalOutcome(GoalStatus.SUCCEEDED, status))
        elif status == ActionStatus.STATUS_CANCELED:  # not by the explorer, whose cancels drop the goal first
            self._on_end(GoalOutcome(GoalStatus.CANCELED, status))
        else:
            error_code = int(getattr(result.result, "error_code", 0))
            self._on_end(GoalOutcome(GoalStatus.ABORTED, status, error_text(result.result), error_code))


def error_text(result: Any) -> str:
    """Nav2's error in an action's result (``error_code``, ``error_msg``, as both actions' results
    have them): ``", error 101: ..."``, or "" for none."""
    code, message = getattr(result, "error_code", 0), str(getattr(result, "error_msg", "")).strip()
    if not code and not message:
        return ""
    return f", error {code}" + (f": {message}" if message else "")


def plugin_problem(action: Nav2Action, outcome: GoalOutcome, plugins: Nav2Plugins) -> str | None:
    """What to set when Nav2 ended a goal of ``action`` (:attr:`Nav2Action.FOLLOW` or :attr:`Nav2Action.NAVIGATE`) for a
    plugin ``plugins`` name that it has not: ``follow_path``'s ``INVALID_CONTROLLER`` (a controller,
    or in a path sent again a goal or progress checker, it has not; or none named where it has
    several), ``navigate_to_pose``'s ``FAILED_TO_LOAD_BEHAVIOR_TREE``. Every goal would end so; None
    for any other end."""
    if action is Nav2Action.FOLLOW and outcome.error_code == FollowPath.Result.INVALID_CONTROLLER:
        return (
            f"Nav2's controller_server has no controller {plugins.controller_id!r} (or goal checker "
            f"{plugins.goal_checker_id!r}, progress checker {plugins.progress_checker_id!r}){outcome.error}: set the "
            "explorer's controller_id, goal_checker_id and progress_checker_id to plugins of its controller_plugins, "
            "goal_checker_plugins and progress_checker_plugins"
        )
    if action is Nav2Action.NAVIGATE and outcome.error_code == NavigateToPose.Result.FAILED_TO_LOAD_BEHAVIOR_TREE:
        return (
            f"Nav2's bt_navigator cannot load the behaviour tree {plugins.behavior_tree!r}{outcome.error}: set the "
            "explorer's behavior_tree to one it can load ('' for its default)"
        )
    return None
