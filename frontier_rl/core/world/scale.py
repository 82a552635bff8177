"""The scale of a world: the robot's size and sensor range that cell sizes are judged against, and the
cell sizes a world accepts. Plain numbers, so that the command line's help can quote the bounds
without loading the engine."""

from __future__ import annotations

import math
import numbers

from frontier_rl.errors import ConfigError, MapError, short_repr

ROBOT_RADIUS_M = 0.105  # TurtleBot3 Burger footprint radius (m)
# The range the robot's map learns cells within (m): the LDS-01's 3.5 m cropped at Gmapping's
# maxUrange 3.0 m (min of LidarConfig.max_range and MapperConfig.usable_range).
MAPPING_RANGE_M = 3.0
# The cell (m) of the robot's map when a map file is drawn on cells finer than RESAMPLE_BELOW_M:
# slam_gmapping's default `delta` (world_spec.read_map resamples the file). On much finer cells the
# LiDAR's beam spacing and range noise leave specks of unknown a 0.05 m map never holds (50-160 at
# once on Stage's 0.012 m uoa_robotics_lab), and "explored" waits on them. DungeonMaps' 0.04375 m
# pixels stay as drawn: ARiADNE's protocol counts in them.
MAPPING_CELL_M = 0.05
RESAMPLE_BELOW_M = 0.04
START_MARGIN_M = 0.05  # extra clearance (m) of a randomly drawn start over the robot radius
# Cell sizes a world accepts (make_world, check_resolution): a cell at most as wide as the robot's
# radius (coarser, the grid cannot say where the robot fits: 5 m cells ran and reported "done" at
# 0 %) and at most a tenth of the mapping range; the radius at most MAX_RADIUS_CELLS cells and the
# range at most MAX_RANGE_CELLS (the clearance disc, the line-of-sight fans and the memory grow
# with these: 1e-5 m cells took the machine's memory). For the TurtleBot3 Burger (radius 0.105 m,
# range 3 m): 0.0042 m to 0.105 m.
MAX_RADIUS_CELLS = 25
MIN_RANGE_CELLS = 10
MAX_RANGE_CELLS = 2000


def resolution_bounds(
    robot_radius: float = ROBOT_RADIUS_M, sensor_range: float = MAPPING_RANGE_M
) -> tuple[float, float]:
    """The smallest and largest cell size (m) a world accepts for a robot of ``robot_radius`` (m)
    mapping within ``sensor_range`` (m); see :data:`MAX_RADIUS_CELLS`."""
    lo = max(robot_radius / MAX_RADIUS_CELLS, sensor_range / MAX_RANGE_CELLS)
    return lo, min(robot_radius, sensor_range / MIN_RANGE_CELLS)


def check_resolution(
    resolution: object,
    what: str = "resolution",
    robot_radius: float = ROBOT_RADIUS_M,
    sensor_range: float = MAPPING_RANGE_M,
) -> float:
    """``resolution`` as a cell size (m) that suits a robot of ``robot_radius`` (m) mapping within
    ``sensor_range`` (m): finite and within :func:`resolution_bounds`.

    Raises:
        MapError: anything else, the message starting with ``what``.
    """
    if isinstance(resolution, bool) or not isinstance(resolution, numbers.Real):
        raise MapError(f"{what} must be a number of metres, got {short_repr(resolution)}")
    res = float(resolution)
    if not (math.isfinite(res) and res > 0):
        raise MapError(f"{what} must be a positive, finite number of metres, got {res!r}")
    lo, hi = resolution_bounds(robot_radius, sensor_range)
    if lo > hi:
        raise MapError(
            f"{what}: no cell size suits a robot of radius {robot_radius:g} m mapping within {sensor_range:g} m"
        )
    if not lo * (1 - 1e-9) <= res <= hi * (1 + 1e-9):  # admits the bounds as printed
        raise MapError(
            f"{what} {res:g} m does not suit a robot of radius {robot_radius:g} m mapping within "
            f"{sensor_range:g} m: use {lo:.3g} to {hi:.3g} m"
        )
    return res


def checked_resolution(resolution: float | None, what: str = "--resolution") -> float | None:
    """``resolution`` (m) if a world can use it (:func:`check_resolution` for the default robot:
    0.0042 to 0.105 m), None for None.

    Raises:
        ConfigError: any other value, named with ``what``.
    """
    if resolution is None:
        return None
    try:
        return check_resolution(resolution, what)
    except MapError as exc:
        raise ConfigError(str(exc)) from None
