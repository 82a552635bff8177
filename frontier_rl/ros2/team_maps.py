"""A robot's teammates' maps, merged into its own before its frontiers are ranked
(:func:`~frontier_rl.robot.map_merge.merged_map`): the explorer does not send the robot where a
teammate has been. The merged map is published on ``explore/merged_map`` (latched, as
map_server's), for the robot's Nav2 to plan on."""

from __future__ import annotations

from collections.abc import Callable, Sequence

from builtin_interfaces.msg import Time
from nav_msgs.msg import OccupancyGrid as GridMessage
from rclpy.node import Node

from frontier_rl.core.world.grid import OccupancyGrid
from frontier_rl.errors import MapError
from frontier_rl.robot.map_merge import merged_map, misfit
from frontier_rl.ros2.messages import MAP_QOS, grid_message, grid_of


class TeamMaps:
    """The maps of ``teammates`` (namespaces: ``/NAMESPACE/map``, in this robot's map frame) on
    ``node``; ``warn(topic, message)`` logs a map ignored or not merged (throttled per topic)."""

    def __init__(self, node: Node, teammates: Sequence[str], warn: Callable[[str, str], None]) -> None:
        self._node = node
        self._warn = warn
        self._grids: dict[str, OccupancyGrid] = {}
        self._merged_pub = node.create_publisher(GridMessage, "explore/merged_map", MAP_QOS) if teammates else None
        for teammate in teammates:
            node.create_subscription(
                GridMessage,
                f"/{teammate}/map",
                lambda message, name=teammate: self._on_map(name, message),
                MAP_QOS,
            )

    def _on_map(self, teammate: str, message: GridMessage) -> None:
        try:
            grid = grid_of(message)
            if teammate not in self._grids:
                self._node.get_logger().info(f"merging the map of {teammate}")
            self._grids[teammate] = grid
        except MapError as error:
            self._warn(f"/{teammate}/map", f"map of {teammate} ignored: {error}")

    def merged(self, own: OccupancyGrid) -> OccupancyGrid:
        """The map to explore: this robot's, merged with its teammates' (a teammate's map that does
        not fit is left out, with a warning)."""
        fitting = []
        for teammate, grid in self._grids.items():
            problem = misfit(own, grid)
            if problem:
                self._warn(f"/{teammate}/map", f"map of {teammate} not merged: {problem}")
            else:
                fitting.append(grid)
        return merged_map(own, fitting)

    def publish(self, merged: OccupancyGrid, stamp: Time, frame: str) -> None:
        """Publish the ``merged`` map on ``explore/merged_map`` (a robot with teammates only)."""
        if self._merged_pub is not None:
            self._merged_pub.publish(grid_message(merged, stamp, frame))
