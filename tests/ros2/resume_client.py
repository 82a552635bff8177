"""Pauses and resumes the explorer over ROS 2 as an operator would (``explore/resume``, as
explore_lite's), reading its status: prints one JSON object with the statuses seen."""

from __future__ import annotations

import json
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import rclpy
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile
from std_msgs.msg import Bool, String

PAUSE_S = 2.0
"""How long (wall s) the explorer is left paused."""


def main() -> None:
    rclpy.init()
    node = Node("resume_probe")
    seen: list[dict[str, Any]] = []
    every_status = QoSProfile(depth=1000, durability=DurabilityPolicy.TRANSIENT_LOCAL)  # none missed while busy
    node.create_subscription(
        String, "explore/status", lambda message: seen.append(json.loads(message.data)), every_status
    )
    switch = node.create_publisher(Bool, "explore/resume", 10)

    def spin_until(done: Callable[[], bool], timeout_s: float) -> None:
        deadline = time.monotonic() + timeout_s
        while not done() and time.monotonic() < deadline:
            rclpy.spin_once(node, timeout_sec=0.05)

    spin_until(lambda: any(s["state"] == "exploring" and s["goals"] >= 2 for s in seen), 60.0)
    spin_until(lambda: switch.get_subscription_count() > 0, 10.0)
    if not seen or seen[-1]["state"] != "exploring":
        sys.exit(f"the explorer never explored: {seen[-1:]}")
    switch.publish(Bool(data=False))
    spin_until(lambda: seen[-1]["state"] == "paused", 10.0)
    paused_at = len(seen) - 1
    spin_until(lambda: False, PAUSE_S)
    nav2_log = Path("nav2.log")  # the stand-in's, beside: what it did while the explorer was paused
    cancelled = nav2_log.exists() and "goal canceled" in nav2_log.read_text()
    switch.publish(Bool(data=True))
    spin_until(lambda: seen[-1]["state"] == "exploring" and seen[-1]["goals"] > seen[paused_at]["goals"], 10.0)
    print(json.dumps({"before": seen[:paused_at], "paused": seen[paused_at:], "cancelled_while_paused": cancelled}))
    node.destroy_node()
    rclpy.shutdown()


if __name__ == "__main__":
    main()
