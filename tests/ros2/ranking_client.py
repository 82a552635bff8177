"""Sends requests to ``/frontier_request`` and prints the status lines that answer them, as JSON.

python ranking_client.py ROBOT[,ROBOT...] REQUESTS_PER_ROBOT
"""

from __future__ import annotations

import json
import sys
import time

import rclpy
from geometry_msgs.msg import PoseArray
from std_msgs.msg import String


def main() -> None:
    robots, count = sys.argv[1].split(","), int(sys.argv[2])
    rclpy.init()
    node = rclpy.create_node("ranking_client")
    statuses: list[dict[str, object]] = []
    lists: list[int] = []
    node.create_subscription(String, "/frontier_status", lambda m: statuses.append(json.loads(m.data)), 100)
    node.create_subscription(PoseArray, "/frontier_list", lambda m: lists.append(len(m.poses)), 100)
    requests = node.create_publisher(String, "/frontier_request", 100)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and (requests.get_subscription_count() == 0 or node.count_publishers(
            "/frontier_status") == 0):  # fmt: skip
        rclpy.spin_once(node, timeout_sec=0.1)
    time.sleep(1.0)  # the maps and poses reach the service
    for i in range(count):
        for robot in robots:
            requests.publish(String(data=f"{robot} {robot}-{i}"))
        rclpy.spin_once(node, timeout_sec=0.05)
    expected = count * len(robots)
    while time.monotonic() < deadline and len(statuses) < expected:
        rclpy.spin_once(node, timeout_sec=0.1)
    print(json.dumps({"statuses": statuses, "lists": lists}))


if __name__ == "__main__":
    main()
