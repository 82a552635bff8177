"""``frontier-rl ros2 explore``: an explorer that drives the robot through Nav2.

It reads the map (``map``, transient local, as slam_toolbox and map_server publish it) and the
robot's pose (``pose``: a ``PoseWithCovarianceStamped`` as slam_toolbox's; an ``Odometry`` in the
map frame; or ``tf``: :mod:`frontier_rl.ros2.pose_listener`), decides with a
:class:`~frontier_rl.robot.explorer.FrontierExplorer` and sends the goal to Nav2's
``navigate_to_pose`` action, as explore_lite does (a goal found with the map's walls thinned, with
the path planned there, to ``follow_path``: :mod:`frontier_rl.ros2.nav2_goals`). A goal Nav2 rejects
or aborts, or that brings the robot no nearer within ``progress_timeout``, is blacklisted, and so is
a goal reached whose frontier a map from after it still shows (:mod:`frontier_rl.robot.map_watch`:
an aborted goal too is judged on such a map); a goal whose frontier the map has since seen is
replaced. It stops when the map is explored, with its end reason on ``explore/status`` and in the
log, and optionally drives back to the start. ``explore/resume`` (``std_msgs/Bool``, as
explore_lite's) pauses the run and resumes it.
"""

from __future__ import annotations

import math
import time
from typing import Any

from rcl_interfaces.msg import SetParametersResult
from rclpy.clock import Clock
from rclpy.clock_type import ClockType
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.task import Future
from std_msgs.msg import Bool, String
from visualization_msgs.msg import MarkerArray

from frontier_rl.core.world.grid import OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.errors import ConfigError
from frontier_rl.robot.explored_time import ExploredTime
from frontier_rl.robot.explorer import FrontierExplorer
from frontier_rl.robot.explorer_decision import Finished, Goal, GoalStatus, Renewal
from frontier_rl.robot.home_trip import HomeTrip
from frontier_rl.robot.pose_source import PoseSource
from frontier_rl.robot.way_home import HOME_TRIES
from frontier_rl.ros2.explorer_inputs import ExplorerInputs
from frontier_rl.ros2.explorer_options import ExplorerNodeOptions
from frontier_rl.ros2.explorer_parameters import ExplorerSettings, declare_explorer_parameters
from frontier_rl.ros2.explorer_status import ExplorerState, ExplorerStatus
from frontier_rl.ros2.messages import MAP_QOS, frontier_markers
from frontier_rl.ros2.nav2_goals import GoalOutcome, Nav2Action, Nav2Goals, plugin_problem

_POLL_PERIOD_S = 0.02
"""How often (wall s) the node looks whether a planner tick is due."""


class ExplorerNode(Node):
    """The explorer as a ROS 2 node.

    Args:
        explorer: the decisions (its policy and settings).
        options: its names, pose source, markers and goal timeout
            (:class:`~frontier_rl.ros2.explorer_options.ExplorerNodeOptions`; ``use_sim_time``,
            ``seed`` and ``ros_args`` are :func:`~frontier_rl.ros2.run.run_explorer`'s to apply).

    The explorer's settings, ``visualize`` and the Nav2 plugins its goals name are the node's parameters
    (:mod:`frontier_rl.ros2.explorer_parameters`): ``--ros-args`` overrides them, ``ros2 param set``
    changes them while it explores.

    Raises:
        ConfigError: a parameter overridden with a bad value.
    """

    def __init__(self, explorer: FrontierExplorer, options: ExplorerNodeOptions | None = None) -> None:
        options = options or ExplorerNodeOptions()
        super().__init__("frontier_rl_explorer", namespace=options.namespace)
        self.explorer = explorer
        given = ExplorerSettings(explorer.params, options.visualize, options.nav2_plugins)
        self._settings = declare_explorer_parameters(self, given, options.policy_name or explorer.policy.name)
        explorer.params, self.visualize = self._settings.params, self._settings.visualize
        self.add_on_set_parameters_callback(self._on_parameters)
        self.goal_silence_timeout = options.goal_silence_timeout
        self._in = ExplorerInputs(self, options.pose_source or PoseSource(), options.teammates)
        self.create_subscription(Bool, "explore/resume", self._on_resume, 10)
        self._paused = False  # explore/resume false came, and no true since
        self._status_pub = self.create_publisher(String, "explore/status", MAP_QOS)
        self._marker_pub = self.create_publisher(MarkerArray, "explore/frontiers", 10)
        self._nav = Nav2Goals(self, self._goal_end, self._settings.plugins)
        self._label = "goal 0"  # the goal in flight, as the log and the status name it: the decision's number
        self._explored = ExploredTime()  # on the node's clock (simulated with use_sim_time)
        self._last_tick_s = -math.inf
        self.finished: Finished | None = None
        self.done: Future[Finished | None] = Future()  # set once exploration (and the way home) is over
        self._home = HomeTrip(explorer)  # the way home, once exploration is over (return_to_init)
        self._stopping = False  # the goal under way is being cancelled: nothing more is sent
        self.plugin_error: str | None = None  # Nav2 has not a plugin the goals name: what to set
        self._finished_s: float | None = None  # the time explored when exploration ended (s)
        self._goal_ended = False  # Nav2 ended the goal under way: the next poll ticks at once
        self._publish(ExplorerState.WAITING, "waiting for a map, a pose and Nav2's navigate_to_pose")
        self._timer = self.create_timer(_POLL_PERIOD_S, self._poll, clock=Clock(clock_type=ClockType.STEADY_TIME))

    # -------------------------------------------------------------- inputs

    def _on_parameters(self, changes: list[Parameter[Any]]) -> SetParametersResult:
        """Take the explorer's parameters set while it runs (``ros2 param set``), or refuse them
        with the reason; other parameters (``use_sim_time``) are ROS's."""
        try:
            settings = self._settings.updated({change.name: change.value for change in changes})
        except ConfigError as error:
            return SetParametersResult(successful=False, reason=str(error))
        if settings != self._settings:
            self._settings = settings
            self.explorer.params, self.visualize = settings.params, settings.visualize
            self._nav.plugins = settings.plugins
            self.get_logger().info(f"settings now {settings.values()}")
        return SetParametersResult(successful=True)

    def _on_resume(self, message: Bool) -> None:
        """explore_lite's ``explore/resume``: false pauses the run (the goal under way cancelled, not
        held against its frontier; the time paused not counted as explored), true goes on."""
        resume = bool(message.data)
        if resume != self._paused or self._stopping or (self.finished is not None and not self._home.under_way):
            return  # no change, or the run is over
        self._paused = not resume
        if resume:
            self._goal_ended = True  # a tick at once (the way home: sent again at once)
            self._publish(ExplorerState.RETURNING if self._home.under_way else ExplorerState.EXPLORING, "resumed")
        else:
            self._nav.cancel()
            if not self._home.under_way:
                self.explorer.goal_lost()
            self._publish(ExplorerState.PAUSED, f"paused on {self.resolve_topic_name('explore/resume')}")
        self.get_logger().info("resumed" if resume else "paused: the goal under way cancelled")

    # --------------------------------------------------------------- ticks
    def _poll(self) -> None:
        """A planner tick when one is due: every ``1 / planner_frequency`` s of the node's clock,
        and at once when no goal is under way."""
        if self._stopping or (self.finished is not None and not self._home.under_way):
            return
        if self._paused:  # the robot may be driven by hand meanwhile: its trail still grows
            self._explored.held(self._in.clock_now_s())
            if (pose := self._in.pose()) is not None:
                self.explorer.passed(pose)
            return
        inputs = self._ready()
        if inputs is None:
            return
        grid, pose = inputs
        self.explorer.passed(pose)  # the trail: every pose the node reads, one per poll
        now = self._explored.advanced(self._in.clock_now_s())
        if self._nav.silent_for(time.monotonic()) > self.goal_silence_timeout:
            self._lost()
            return
        if self.finished is not None:  # on the way home: sent again after a pause, its path kept to the map
            self._homeward(grid, pose, now)
            return
        if now >= self.explorer.params.time_cap:
            self._in.maps.forget_goal()  # the run ends now: on the map at hand
        elif not self._in.map_for_judging(self._label):
            return
        period = 1.0 / self.explorer.params.planner_frequency
        if self.explorer.goal is not None and now - self._last_tick_s < period and not self._goal_ended:
            return
        self._tick(grid, pose, now)

    def _tick(self, grid: OccupancyGrid, pose: Pose, now: float) -> None:
        """A planner tick at ``pose`` on the robot's map ``grid``, ``now`` s explored."""
        self._last_tick_s = now
        self._goal_ended = False
        explored = self._in.team.merged(grid)
        self._in.team.publish(explored, self.get_clock().now().to_msg(), self._in.map_frame)
        decision = self.explorer.tick(explored, pose, now)
        if isinstance(decision, Renewal):
            self._renew(decision)
        elif isinstance(decision, Goal):
            self._send(decision)
        elif isinstance(decision, Finished):
            self._finish(decision, explored, pose)

    def _ready(self) -> tuple[OccupancyGrid, Pose] | None:
        """The map and the robot's pose once they and Nav2 are there; None (saying on the log, in
        time, what it waits for) before."""
        inputs = self._in.map_and_pose()
        if inputs is not None and not self._nav.ready(self.explorer.params.recovery_paths, time.monotonic()):
            navigate = self.resolve_topic_name(Nav2Action.NAVIGATE)
            self._in.waiting(f"Nav2's {navigate} and {self.resolve_topic_name(Nav2Action.FOLLOW)} actions")
            return None
        return inputs

    def _send(self, goal: Goal) -> None:
        self._label = "the way home" if self._home.under_way else f"goal {self.explorer.decisions}"
        action = self._nav.send(goal, self._in.map_frame, self.get_clock().now().to_msg())
        along = action is Nav2Action.FOLLOW
        if goal.path is not None and not along:
            self._in.warn(
                Nav2Action.FOLLOW,
                f"Nav2's {self.resolve_topic_name(Nav2Action.FOLLOW)} action is not up: {self._label}, found with "
                "the map's walls thinned, goes to navigate_to_pose, whose planner may find no way there",
            )
        if self.visualize:
            candidates = [(float(x), float(y)) for x, y in self.explorer.candidate_goals]
            self._marker_pub.publish(frontier_markers(candidates, (goal.x, goal.y), self.get_clock().now().to_msg()))
        detail = f"{self._label} at ({goal.x:.2f}, {goal.y:.2f})" + (" along a path" if along else "")
        self.get_logger().debug(f"sent {detail}")  # --ros-args --log-level frontier_rl_explorer:=debug shows it
        self._publish(ExplorerState.RETURNING if self._home.under_way else ExplorerState.EXPLORING, detail)

    def _renew(self, renewal: Renewal) -> None:
        """Give ``follow_path`` the goal under way's path planned afresh; a goal on
        ``navigate_to_pose`` is replanned by Nav2 and not sent again
        (:class:`~frontier_rl.robot.explorer_decision.Renewal`). A goal on ``follow_path`` whose
        server went away goes to ``navigate_to_pose``, once."""
        if self._nav.action_for(renewal.goal) is Nav2Action.FOLLOW or self._nav.action is Nav2Action.FOLLOW:
            self._send(renewal.goal)

    def _lost(self) -> None:
        """Nav2 fell silent on the goal in flight: drop it (its server went away) and decide again
        once the server is back."""
        why = f"no word from {self._nav.action} on {self._label} for {self.goal_silence_timeout:g} s: dropped"
        self.get_logger().warn(why)
        self._nav.drop()
        if self._home.under_way:
            self._home.end()
            self._close(why)
            return
        self.explorer.goal_lost()
        self._goal_ended = True
        self._publish(ExplorerState.EXPLORING, why)

    def _goal_end(self, outcome: GoalOutcome) -> None:
        status, action = outcome.status, self._nav.action
        problem = plugin_problem(action, outcome, self._nav.plugins)
        if problem is not None:  # every goal would end so: the run ends, saying what to set
            self.get_logger().error(f"{self._label} aborted by {action}: {problem}")
            self.plugin_error, self._stopping = problem, True
            self._home.end()
            self._close(problem, ExplorerState.INTERRUPTED)
            return
        if status is GoalStatus.ABORTED and outcome.error:  # Nav2's own reason (a controller id it wants): on the log
            self._in.warn(f"{action} error", f"{self._label} aborted by {action}{outcome.error}")
        if status is GoalStatus.CANCELED:
            self.get_logger().info(f"{self._label} cancelled by another node on {action}")
        why = outcome.sentence(self._label)
        failed = status is not GoalStatus.SUCCEEDED
        # a way home rejected is not sent again (Nav2 would reject it again at once), nor one another
        # node cancelled; a goal another node cancelled is given up as one Nav2 aborted: not there
        if self._home.under_way:
            pose = self._in.pose()
            tries_left = self._home.tries_left and not self._stopping
            retried = status is GoalStatus.ABORTED and tries_left
            if retried and pose is not None and (explored := self._in.explored()) is not None:
                self.get_logger().warn(
                    f"{why}: planned again from ({pose.x:.2f}, {pose.y:.2f}), "
                    f"try {self._home.tries + 1} of {HOME_TRIES}"
                )
                if self._go_home(explored, pose):
                    return
            self._home.end()
            self._close(why)
            return
        explored = self._in.explored()  # merged with the teammates' maps
        if status is GoalStatus.REJECTED:  # the robot never drove for it: given up on the map at hand
            if explored is not None:
                self.explorer.goal_failed(explored)
        else:
            why = self._judged_later(explored, failed, why)
        self._goal_ended = True
        self._publish(ExplorerState.EXPLORING, why)

    def _judged_later(self, explored: OccupancyGrid | None, failed: bool, why: str) -> str:
        """The goal under way ended (``failed``: aborted, or cancelled by another node) with the
        map ``explored`` at hand: it is judged at the next tick, on a map from after its end where
        ``explored`` would judge it (:class:`~frontier_rl.robot.map_watch.MapWatch`); ``why``, with
        the wait if there is one."""
        judged = explored is not None and self.explorer.judged_on(explored)
        if judged and self._in.maps.goal_ended(time.monotonic(), self._in.clock_now_s()):
            why += f": waiting up to {self._in.maps.wait_bound_s():.1f} s for a newer map"  # on the status topic
            self.get_logger().debug(why)
        if failed:
            self.explorer.goal_aborted()
        else:
            self.explorer.goal_reached()
        return why

    # ---------------------------------------------------------------- the end
    def cancel_goal(self) -> Future[bool] | None:
        """Ask Nav2 to cancel the goal under way (the explorer is being stopped: the robot should
        not drive on to it); the cancel request's future, or None when no goal is under way."""
        self._stopping = True
        if (explored := self._in.explored()) is not None:  # no tick will judge an abort now
            self.explorer.judge_abort(explored)
        unanswered = self._nav.unanswered
        future = self._nav.cancel()  # also goals whose response is still awaited, once it comes
        if future is not None:  # ended or stopped
            waits = f" (once Nav2 answers it: {unanswered} unanswered)" if unanswered else ""
            self.get_logger().info(f"cancelling {self._label}: the explorer is stopping{waits}")
        return future

    def _finish(self, finished: Finished, explored: OccupancyGrid, pose: Pose) -> None:
        """The run is over: home from ``pose`` on the map ``explored``, or done (a goal still under
        way is cancelled by the runner, which waits for Nav2's answer before the node goes: a
        request sent as it went was lost, and the robot drove on)."""
        self.finished, self._finished_s = finished, self._explored.elapsed_s
        if not (self.explorer.params.return_to_init and self._go_home(explored, pose)):
            self._close("exploration over")

    def _go_home(self, explored: OccupancyGrid, pose: Pose, counted: bool = True) -> bool:
        """Send the way home from ``pose`` on the map ``explored`` (``counted`` among the tries:
        not when a pause cancelled the last); False when there is none (no start: the explorer
        never ticked)."""
        home = self._home.send(explored, pose, counted=counted)
        if home is None:
            return False
        self._nav.cancel()
        self._send(home)
        self._last_tick_s = self._explored.elapsed_s  # its path is first renewed a planner period on
        return True

    def _homeward(self, grid: OccupancyGrid, pose: Pose, now: float) -> None:
        """A poll on the way home at ``pose``, the robot's map ``grid``, ``now`` s explored: the way
        sent again after a pause, or its path planned afresh at each planner tick
        (:class:`~frontier_rl.robot.home_trip.HomeTrip`); on the map merged with the teammates'."""
        if self._goal_ended:
            self._goal_ended = False
            if not self._go_home(self._in.team.merged(grid), pose, counted=False):
                self._home.end()
                self._close("exploration over")
        elif now - self._last_tick_s >= 1.0 / self.explorer.params.planner_frequency:
            self._last_tick_s = now
            if (renewal := self._home.renew(self._in.team.merged(grid), pose)) is not None:
                self._renew(renewal)

    def _close(self, why: str, state: ExplorerState = ExplorerState.FINISHED) -> None:
        self._publish(state, why)
        if state is ExplorerState.FINISHED:
            self.get_logger().info(self.summary())
        if not self.done.done():
            self.done.set_result(self.finished)

    def summary(self) -> str:
        """One line: the end reason, the time, the goals and what was left."""
        return self.status(ExplorerState.FINISHED, "").summary()

    def status(self, state: ExplorerState, detail: str) -> ExplorerStatus:
        """The explorer's state now."""
        time_s = self._explored.elapsed_s if self._finished_s is None else self._finished_s
        explorer = self.explorer
        return ExplorerStatus.of(
            state, detail, time_s, explorer.decisions, explorer.goals_given_up, self.finished, self._in.coverage
        )

    def _publish(self, state: ExplorerState, detail: str) -> None:
        self._status_pub.publish(String(data=self.status(state, detail).to_json()))
