"""Sets and reads the explorer node's parameters over ROS 2, as ``ros2 param`` does: prints one
JSON object with what it read and what each set answered (with ``--get``, what it read, no set)."""

from __future__ import annotations

import json
import sys

import rclpy
from rclpy.node import Node
from rclpy.parameter import Parameter, parameter_value_to_python
from rclpy.parameter_client import AsyncParameterClient

NAMES = [
    "planner_frequency",
    "progress_timeout",
    "min_frontier_size",
    "time_cap",
    "progress_distance",
    "visualize",
    "policy",
    "use_sim_time",
    "behavior_tree",
    "controller_id",
]
SETS = [
    [Parameter("progress_timeout", Parameter.Type.INTEGER, 5)],
    [Parameter("planner_frequency", Parameter.Type.DOUBLE, -1.0)],
    [Parameter("visualize", Parameter.Type.STRING, "yes")],
    [Parameter("policy", Parameter.Type.STRING, "tour")],
    [Parameter("time_cap", Parameter.Type.DOUBLE, 600.0)],
    [Parameter("controller_id", Parameter.Type.STRING, "FollowPath")],
    [Parameter("goal_checker_id", Parameter.Type.INTEGER, 3)],
]


def _wait(node: Node, future: rclpy.task.Future) -> object:  # type: ignore[type-arg]
    rclpy.spin_until_future_complete(node, future, timeout_sec=10.0)
    if not future.done():
        sys.exit("no answer from the explorer's parameter services")
    return future.result()


def main() -> None:
    rclpy.init()
    node = Node("parameter_probe")
    client = AsyncParameterClient(node, "frontier_rl_explorer")
    if not client.wait_for_services(timeout_sec=30.0):
        sys.exit("the explorer's parameter services never came")
    before = _wait(node, client.get_parameters(NAMES))
    answers = []
    for change in [] if "--get" in sys.argv else SETS:
        result = _wait(node, client.set_parameters(change)).results[0]  # type: ignore[attr-defined]
        answers.append({"successful": result.successful, "reason": result.reason})
    after = _wait(node, client.get_parameters(NAMES))
    read = [dict(zip(NAMES, map(parameter_value_to_python, r.values), strict=True)) for r in (before, after)]  # type: ignore[attr-defined]
    print(json.dumps({"before": read[0], "after": read[1], "sets": answers}))
    node.destroy_node()
    rclpy.shutdown()


if __name__ == "__main__":
    main()
