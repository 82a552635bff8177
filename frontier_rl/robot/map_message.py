"""A ROS map message (``nav_msgs/OccupancyGrid``: size, resolution, origin, occupancy values)
as a grid, without ROS: shared by the ROS 1 node and the ROS 2 nodes, which only convert messages."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.errors import MapError
from frontier_rl.io.ros_map import FREE_THRESH, OCCUPIED_THRESH


@dataclass(frozen=True)
class MapThresholds:
    """How occupancy values (0 to 100, -1 unknown) become cell states, as map_server reads them.

    Attributes:
        occupied_above: values above this are occupied (%).
        free_below: values below this are free (%); values in between are unknown.
    """

    occupied_above: float = 100 * OCCUPIED_THRESH
    free_below: float = 100 * FREE_THRESH


def check_map_message(width: int, height: int, resolution: float, values: int) -> None:
    """Raise :class:`MapError` for a ``nav_msgs/OccupancyGrid`` of zero size, a resolution (m) that
    is not a positive number, or ``values`` data values that are not width × height."""
    if width <= 0 or height <= 0:
        raise MapError(f"map of size {width} × {height} has no cells")
    if not (math.isfinite(resolution) and resolution > 0):
        raise MapError(f"map resolution must be a positive number of metres, got {resolution!r}")
    if values != width * height:
        raise MapError(f"map data has {values} values, expected width × height = {width * height}")


def grid_from_message(
    width: int,
    height: int,
    resolution: float,
    data: Sequence[int] | NDArray[np.integer[Any]],
    thresholds: MapThresholds | None = None,
    origin: tuple[float, float] = (0.0, 0.0),
) -> OccupancyGrid:
    """A grid with its lower-left corner at ``origin`` (m; by default 0, 0: the map's own cell
    frame) from a ``nav_msgs/OccupancyGrid``'s size, resolution (m) and row-major data;
    probabilities are thresholded, not rejected. A map of zero size, a resolution that is not
    positive, or data of the wrong length is a :class:`MapError`. The message's resolution is a
    float32 and is read as the decimal it was written as (0.05 m, not 0.0500000007 m), so that the
    grid's cells are those of the same map loaded from its YAML."""
    t = thresholds or MapThresholds()
    check_map_message(width, height, resolution, len(data))
    values = np.asarray(data, dtype=np.int16).reshape(height, width)
    cells = np.full(values.shape, CellState.UNKNOWN, np.int8)
    known = values >= 0
    cells[known & (values > t.occupied_above)] = CellState.OCCUPIED
    cells[known & (values < t.free_below)] = CellState.FREE
    return OccupancyGrid(cells, as_written(resolution), origin)


def yaw_of(q: Any) -> float:
    """The rotation about z (rad) of a ``geometry_msgs/Quaternion`` (ROS 1's or ROS 2's; its roll
    and pitch are ignored)."""
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def as_written(resolution: float) -> float:
    """A float32 ``resolution`` (m) as the decimal it was written as: 0.05 for 0.0500000007. A value
    a float32 cannot hold (a float64 from elsewhere) is kept as it is."""
    single = np.finfo(np.float32)
    if not (float(single.tiny) <= resolution <= float(single.max)):
        return float(resolution)
    return float(str(np.float32(resolution)))
