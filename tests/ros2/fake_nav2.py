"""A stand-in for slam_toolbox and Nav2 that misbehaves on purpose, for the explorer's fault tests.

It publishes a fixed map (a corridor whose east half is unknown: frontiers that no goal will ever
resolve, since nothing moves) and a pose, and serves ``navigate_to_pose`` (and ``follow_path``
alike) in one ``--mode``: ``reject`` every goal, ``abort`` it, ``stall`` (accept, send feedback,
never move), ``cancel`` it as another node would (through its cancel service), or ``succeed`` at
once (after ``--goal-time`` s of feedback); it prints the Nav2 plugins each goal names.
``--bad-inputs`` first sends a malformed map and a NaN pose; ``--die-after N`` ends the process
without a word once it has accepted N goals (a Nav2 that crashed). ``--map-period P`` publishes
the map every P s, as slam_toolbox does (else once); ``--reveal`` maps the unknown half as free
when a goal succeeds (published with the next map, as a SLAM map lags the robot);
``--map-stops-at-goal N`` publishes no map once N goals are accepted; ``--error-code N`` ends each
goal it aborts with Nav2's error code N; ``--response-delay S`` answers each goal S seconds after
it came. ``--door`` adds a room north of the corridor behind a door that only the narrow-passage
recovery's levels pass (its goals go to ``follow_path``); ``--carried-to X,Y`` puts the robot there
when a goal is accepted (carried, as nothing here drives); ``--no-follow`` serves no
``follow_path`` (a Nav2 whose controller server is elsewhere), ``--follow-gone-after N`` ends it
just after it accepted its Nth goal (a controller server that crashed). In ``stall`` mode a goal
of one action does not preempt the other's (two Nav2 servers), and a goal cancelled is named by
its action.
"""

from __future__ import annotations

import argparse
import array
import contextlib
import os
import threading
import time

import numpy as np
import rclpy
from action_msgs.srv import CancelGoal
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav2_msgs.action import FollowPath, NavigateToPose
from nav_msgs.msg import OccupancyGrid
from rclpy.action.server import ActionServer, CancelResponse, GoalResponse, ServerGoalHandle
from rclpy.executors import MultiThreadedExecutor
from rclpy.node import Node

from frontier_rl.ros2.messages import MAP_QOS


def _map(bad: bool, revealed: bool = False, door: bool = False) -> OccupancyGrid:
    data = np.full((40 if door else 20, 80), 100, np.int8)
    data[4:16, 1:40] = 0
    data[4:16, 40:79] = 0 if revealed else -1
    if door:  # a room north of the corridor through a door of 0.15 m: only the recovery's levels pass it
        data[16:20, 12:15] = 0
        data[20:36, 1:40] = -1
        data[20:23, 4:30] = 0
    message = OccupancyGrid()
    message.header.frame_id = "map"
    message.info.resolution, message.info.width, message.info.height = 0.05, 80, data.shape[0]
    message.info.origin.orientation.w = 1.0
    message.data = array.array("b", data.tobytes()[: 100 if bad else None])
    return message


def _pose(x: float, y: float = 0.5) -> PoseWithCovarianceStamped:
    message = PoseWithCovarianceStamped()
    message.header.frame_id = "map"
    message.pose.pose.position.x, message.pose.pose.position.y = x, y
    message.pose.pose.orientation.w = 1.0
    return message


_SAID = threading.Lock()


def _say(line: str) -> None:
    """Print ``line`` whole: the executor's threads print at once, and print() writes the line and
    its end apart (two lines came out as one, and a test missed the cancel it looked for)."""
    with _SAID:
        print(line, flush=True)


_FOLLOW_PLUGINS = ("controller_id", "goal_checker_id", "progress_checker_id")
_ACTIONS = {NavigateToPose: "navigate_to_pose", FollowPath: "follow_path"}


class FakeNav2(Node):
    def __init__(
        self,
        mode: str,
        die_after: int,
        goal_time: float = 0.0,
        reveal: bool = False,
        error_code: int = 0,
        response_delay: float = 0.0,
        carried_to: tuple[float, float] | None = None,
        follow: bool = True,
        follow_gone_after: int = 0,
    ) -> None:
        super().__init__("fake_nav2")
        self.error_code, self.response_delay = error_code, response_delay
        self.mode, self.die_after, self.accepted = mode, die_after, 0
        self.goal_time, self.reveal, self.revealed = goal_time, reveal, False
        self.map_pub = self.create_publisher(OccupancyGrid, "map", MAP_QOS)
        self.pose_pub = self.create_publisher(PoseWithCovarianceStamped, "pose", 10)
        self.pose_x, self.pose_y, self.carried_to = 0.5, 0.5, carried_to
        self.current: dict[type, ServerGoalHandle] = {}  # each action's goal under way
        served = {action: name for action, name in _ACTIONS.items() if follow or action is not FollowPath}
        self.follow_gone_after, self.follows, self.follow_gone = follow_gone_after, 0, False
        self.servers: dict[type, ActionServer] = {}
        # the actions' cancel services, as another node (an operator in RViz) calls them
        self.cancel_all = {
            action: self.create_client(CancelGoal, f"{name}/_action/cancel_goal") for action, name in served.items()
        }
        for action, name in served.items():
            self.servers[action] = ActionServer(
                self,
                action,
                name,
                lambda handle, action=action: self._execute(handle, action),
                goal_callback=self._goal,
                cancel_callback=lambda _: CancelResponse.ACCEPT,  # as Nav2's bt_navigator does
            )

    def _goal(self, request: object) -> GoalResponse:
        names = ("behavior_tree",) if isinstance(request, NavigateToPose.Goal) else _FOLLOW_PLUGINS
        _say("goal naming " + ", ".join(f"{name} {getattr(request, name)!r}" for name in names))
        time.sleep(self.response_delay)
        if self.mode == "reject":
            return GoalResponse.REJECT
        self.accepted += 1
        if isinstance(request, FollowPath.Goal):
            self.follows += 1
            if self.follows == self.follow_gone_after:
                self.gone_timer = self.create_timer(0.2, self._follow_ends)
        if self.carried_to is not None:
            self.pose_x, self.pose_y = self.carried_to
        if self.die_after and self.accepted >= self.die_after:
            threading.Timer(0.2, os._exit, (1,)).start()  # a crash: no result, no goodbye
        return GoalResponse.ACCEPT

    def _follow_ends(self) -> None:
        """follow_path's server goes away, its goal under way with it: no result, no word."""
        self.gone_timer.cancel()
        self.follow_gone = True
        time.sleep(0.3)  # its goal's loop has stopped
        self.servers.pop(FollowPath).destroy()
        _say("follow_path server gone")

    def _execute(self, handle: ServerGoalHandle, action: type) -> object:
        feedback = (
            NavigateToPose.Feedback(distance_remaining=1.0)
            if action is NavigateToPose
            else FollowPath.Feedback(distance_to_goal=1.0)
        )
        if self.mode == "stall":
            # a newer goal of the same action preempts this one, as Nav2's does; the other action's
            # goals are another server's, and drive on until cancelled
            self.current[action] = handle
            while (
                rclpy.ok()
                and not handle.is_cancel_requested
                and handle.is_active
                and self.current.get(action) is handle
            ):
                while action is FollowPath and self.follow_gone and rclpy.ok():
                    time.sleep(0.5)  # never answered: the server is gone (returning would abort the goal)
                handle.publish_feedback(feedback)
                time.sleep(0.1)
            if handle.is_cancel_requested:
                handle.canceled()
                _say(f"{_ACTIONS[action]} goal canceled")
            elif handle.is_active:
                handle.abort()
            return action.Result()
        if self.mode == "cancel":
            client = self.cancel_all[action]
            if client.wait_for_service(timeout_sec=5.0):
                client.call_async(CancelGoal.Request())  # no goal id, no stamp: every goal
            deadline = time.monotonic() + 5.0
            while time.monotonic() < deadline and not handle.is_cancel_requested:
                handle.publish_feedback(feedback)
                time.sleep(0.05)
            if handle.is_cancel_requested:
                handle.canceled()
                _say(f"{_ACTIONS[action]} goal canceled by another node")
            else:
                handle.abort()
            return action.Result()
        if self.mode == "succeed":
            deadline = time.monotonic() + self.goal_time
            while time.monotonic() < deadline and not handle.is_cancel_requested:
                handle.publish_feedback(feedback)
                time.sleep(0.05)
            self.revealed = self.revealed or self.reveal
            handle.succeed()
        else:
            deadline = time.monotonic() + self.goal_time  # driven a while before it aborts
            while time.monotonic() < deadline and not handle.is_cancel_requested:
                handle.publish_feedback(feedback)
                time.sleep(0.05)
            handle.abort()
            return action.Result(
                error_code=self.error_code, error_msg="the stand-in's error" if self.error_code else ""
            )
        return action.Result()


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--mode", choices=("reject", "abort", "stall", "succeed", "cancel"), required=True)
    parser.add_argument("--bad-inputs", action="store_true")
    parser.add_argument("--die-after", type=int, default=0)
    parser.add_argument("--goal-time", type=float, default=0.0)
    parser.add_argument("--map-period", type=float, default=0.0)
    parser.add_argument("--reveal", action="store_true")
    parser.add_argument("--map-stops-at-goal", type=int, default=0)
    parser.add_argument("--door", action="store_true")
    parser.add_argument("--error-code", type=int, default=0)
    parser.add_argument("--response-delay", type=float, default=0.0)
    parser.add_argument("--carried-to", type=lambda text: tuple(float(v) for v in text.split(",")), default=None)
    parser.add_argument("--no-follow", action="store_true")
    parser.add_argument("--follow-gone-after", type=int, default=0)
    args = parser.parse_args()
    rclpy.init()
    node = FakeNav2(
        args.mode,
        args.die_after,
        args.goal_time,
        args.reveal,
        args.error_code,
        args.response_delay,
        args.carried_to,
        follow=not args.no_follow,
        follow_gone_after=args.follow_gone_after,
    )
    # bad inputs until 2 s after the explorer has subscribed to the pose: its start (imports, numba)
    # took more than the 4 s fixed here before on a busy machine, and it never saw a NaN pose
    bad_until = None if args.bad_inputs else 0.0
    node.map_pub.publish(_map(bad=args.bad_inputs, door=args.door))
    published_good_map = not args.bad_inputs

    def tick() -> None:
        nonlocal published_good_map, bad_until
        if bad_until is None and node.pose_pub.get_subscription_count() > 0:
            bad_until = time.monotonic() + 2.0
        bad = bad_until is None or time.monotonic() < bad_until
        node.pose_pub.publish(_pose(float("nan") if bad else node.pose_x, node.pose_y))
        if bad:
            node.map_pub.publish(_map(bad=True, door=args.door))
        elif not published_good_map:
            node.map_pub.publish(_map(bad=False, door=args.door))
            published_good_map = True

    node.create_timer(0.1, tick)

    def map_tick() -> None:
        stopped = args.map_stops_at_goal and node.accepted >= args.map_stops_at_goal
        if published_good_map and not stopped:
            node.map_pub.publish(_map(bad=False, revealed=node.revealed, door=args.door))

    if args.map_period:
        node.create_timer(args.map_period, map_tick)
    executor = MultiThreadedExecutor(num_threads=4)
    executor.add_node(node)
    with contextlib.suppress(KeyboardInterrupt):
        executor.spin()


if __name__ == "__main__":
    main()
