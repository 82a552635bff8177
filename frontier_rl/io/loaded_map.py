"""The result of loading a map file: the grid, the start pose if the file has one, and the file."""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass
from pathlib import Path

from frontier_rl.core.world.grid import OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.errors import MapError, short_repr

#: Largest coordinate (m, either sign) a map file may place its cells at: a building, not a
#: continent (at 10^16 m a float64 no longer tells 0.05 m cells apart).
MAX_COORDINATE_M = 1e6


@dataclass(frozen=True)
class LoadedMap:
    """A map read from a file.

    Attributes:
        grid: the ground-truth occupancy grid (world coordinates in m).
        start: the robot's start pose (m, rad) if the file defines one, else None.
        source: the file the map was read from.
    """

    grid: OccupancyGrid
    start: Pose | None
    source: Path


def positive_metres(value: object, name: str, source: object) -> float:
    """``value`` as a finite float > 0 (m); raises :class:`MapError` naming ``name`` and ``source``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise MapError(f"{source}: {name} must be a positive number of metres, got {short_repr(value)}")
    number = float(value)
    if not (math.isfinite(number) and number > 0):
        raise MapError(f"{source}: {name} must be a positive number of metres, got {short_repr(value)}")
    return number
