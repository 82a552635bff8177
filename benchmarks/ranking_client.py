"""A client of the ranking service (``frontier-rl ros2 rank``): sends requests to
``/frontier_request`` and prints, as one JSON object, the status lines that answered them and each
request's round trip (from publishing it to receiving its status, in this process).

    python benchmarks/ranking_client.py ROBOT[,ROBOT...] --count N          # N requests per robot, at once
    python benchmarks/ranking_client.py ROBOT[,ROBOT...] --rate 10 --until-file F  # 10 per robot per s

Run it in the same (loopback-only) network namespace as the service.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import rclpy
from geometry_msgs.msg import PoseArray
from rclpy.node import Node
from std_msgs.msg import String

_WAIT_S = 60.0
"""How long the client waits for the service to appear, and for the last answers."""


class _Client:
    def __init__(self, node: Node) -> None:
        self.node = node
        self.sent: dict[tuple[str, str], float] = {}
        self.statuses: list[dict[str, object]] = []
        self.round_trips: list[float] = []
        self.lists = 0
        self.probes = 0  # requests sent before counting (wait_for_maps)
        node.create_subscription(String, "/frontier_status", self._on_status, 1000)
        node.create_subscription(PoseArray, "/frontier_list", self._on_list, 1000)
        self.requests = node.create_publisher(String, "/frontier_request", 1000)

    def _on_status(self, message: String) -> None:
        status = json.loads(message.data)
        self.statuses.append(status)
        sent = self.sent.get((str(status["robot"]), str(status["request"])))
        if sent is not None:
            self.round_trips.append(time.monotonic() - sent)

    def _on_list(self, message: PoseArray) -> None:
        self.lists += 1

    def send(self, robot: str, request: str) -> None:
        self.sent[(robot, request)] = time.monotonic()
        self.requests.publish(String(data=f"{robot} {request}"))

    def wait_for_service(self) -> None:
        deadline = time.monotonic() + _WAIT_S
        while time.monotonic() < deadline and (
            self.requests.get_subscription_count() == 0 or self.node.count_publishers("/frontier_status") == 0
        ):
            rclpy.spin_once(self.node, timeout_sec=0.1)
        if self.requests.get_subscription_count() == 0 or self.node.count_publishers("/frontier_status") == 0:
            sys.exit(f"ranking_client: no ranking service on /frontier_request within {_WAIT_S:g} s")
        time.sleep(1.0)  # the maps and poses reach the service

    def wait_for_maps(self, robots: list[str]) -> None:
        """Ask for ``robots`` until each is answered with frontiers (their maps and poses reached
        the service); these answers are not reported."""
        ready: set[str] = set()
        deadline = time.monotonic() + _WAIT_S
        while time.monotonic() < deadline and len(ready) < len(robots):
            for robot in robots:
                self.requests.publish(String(data=f"{robot} probe"))
                self.probes += 1
            self.spin_for(0.2)
            ready |= {str(s["robot"]) for s in self.statuses if s["request"] == "probe" and s["frontiers"]}
        if len(ready) < len(robots):
            waiting = sorted(set(robots) - ready)
            sys.exit(f"ranking_client: no answer with frontiers for {', '.join(waiting)} within {_WAIT_S:g} s")
        self.statuses = [s for s in self.statuses if s["request"] != "probe"]

    def spin_for(self, seconds: float) -> None:
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            rclpy.spin_once(self.node, timeout_sec=max(0.0, min(0.01, end - time.monotonic())))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("robots", help="namespaces, comma-separated")
    parser.add_argument("--count", type=int, default=0, help="requests per robot, sent at once")
    parser.add_argument("--rate", type=float, default=0.0, help="requests per robot per second")
    parser.add_argument("--until-file", type=Path, help="with --rate: send until this file exists")
    parser.add_argument("--ready", default="", help="robots whose answers must have frontiers before counting")
    args = parser.parse_args()
    robots = args.robots.split(",")
    rclpy.init()
    client = _Client(rclpy.create_node("ranking_client"))
    client.wait_for_service()
    if args.ready:
        client.wait_for_maps(args.ready.split(","))
    if args.count:
        for i in range(args.count):
            for robot in robots:
                client.send(robot, f"{robot}-{i}")
            client.spin_for(0.05)
    else:
        i = 0
        while args.until_file is None or not args.until_file.exists():
            for robot in robots:
                client.send(robot, f"{robot}-{i}")
            i += 1
            client.spin_for(1.0 / args.rate)
    deadline = time.monotonic() + _WAIT_S
    while time.monotonic() < deadline and len(client.statuses) < len(client.sent):
        client.spin_for(0.1)
    print(
        json.dumps(
            {
                "sent": len(client.sent),
                "probes": client.probes,
                "statuses": client.statuses,
                "lists": client.lists,
                "round_trips_s": client.round_trips,
            }
        )
    )


if __name__ == "__main__":
    main()
