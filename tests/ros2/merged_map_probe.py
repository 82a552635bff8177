"""Listens to a robot's own map and the merged map its explorer publishes (``NAMESPACE/map``,
``NAMESPACE/explore/merged_map``) until SIGINT, then prints one JSON object: how many merged maps
came, their frames, and the most cells a merged map knew beyond the robot's own map of the moment."""

from __future__ import annotations

import json
import signal
import sys

import numpy as np
import rclpy
from nav_msgs.msg import OccupancyGrid as GridMessage
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions

from frontier_rl.ros2.messages import MAP_QOS


class _Probe:
    def __init__(self, node: Node, namespace: str) -> None:
        self.merged_maps = 0
        self.frames: list[str] = []
        self.most_cells_beyond_own = 0
        self._own_known = 0
        node.create_subscription(GridMessage, f"/{namespace}/map", self._on_own, MAP_QOS)
        node.create_subscription(GridMessage, f"/{namespace}/explore/merged_map", self._on_merged, MAP_QOS)

    def _on_own(self, message: GridMessage) -> None:
        self._own_known = int(np.count_nonzero(np.asarray(message.data) != -1))

    def _on_merged(self, message: GridMessage) -> None:
        self.merged_maps += 1
        if message.header.frame_id not in self.frames:
            self.frames.append(message.header.frame_id)
        beyond = int(np.count_nonzero(np.asarray(message.data) != -1)) - self._own_known
        self.most_cells_beyond_own = max(self.most_cells_beyond_own, beyond)


def main() -> None:
    rclpy.init(signal_handler_options=SignalHandlerOptions.NO)
    node = Node("merged_map_probe")
    probe = _Probe(node, sys.argv[1])
    stopped = []
    signal.signal(signal.SIGINT, lambda *_: stopped.append(True))
    while not stopped:
        rclpy.spin_once(node, timeout_sec=0.1)
    fields = ("merged_maps", "frames", "most_cells_beyond_own")
    print(json.dumps({name: getattr(probe, name) for name in fields}))


if __name__ == "__main__":
    main()
