"""Ground-truth worlds: the :class:`World` type and how one is made from a grid (its start pose and
explorable space); the named procedural worlds are in :mod:`frontier_rl.core.world.catalog`.

A world is an :class:`OccupancyGrid` holding only FREE and OCCUPIED cells (unknown cells of an input
map and free cells cut off from the start count as walls), a start pose and the *explorable* mask:
the free cells the robot's sensor could ever map, in line of sight and range of a pose the robot can
reach from its start (:mod:`frontier_rl.core.world.visibility`), which is what exploration coverage is
measured on.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import MAX_HEADING_RAD, Pose, checked_pose
from frontier_rl.core.world.scale import MAPPING_RANGE_M, ROBOT_RADIUS_M, START_MARGIN_M, check_resolution
from frontier_rl.core.world.visibility import visible_from
from frontier_rl.errors import ConfigError, MapError


@dataclass(frozen=True, eq=False)  # compared by identity: numpy fields have no boolean equality
class World:
    """A ground-truth world to explore.

    Attributes:
        name: world name (e.g. "office").
        grid: ground truth; only ``CellState.FREE`` and ``CellState.OCCUPIED`` cells, all free cells
            4-connected to the start. Its data array is read-only.
        start: robot start pose (m, m, rad), on a cell the robot fits on.
        explorable: read-only mask (grid shape) of the cells coverage is measured on: free cells in
            line of sight, within ``sensor_range``, of a cell the robot's centre can reach from the
            start (cells at least ``robot_radius`` from every wall, 4-connected to the start: the
            planner cuts no corners).
        robot_radius: the footprint radius (m) the mask was computed for.
        sensor_range: the mapping range (m) the mask was computed for.
    """

    name: str
    grid: OccupancyGrid
    start: Pose
    explorable: NDArray[np.bool_]
    robot_radius: float = ROBOT_RADIUS_M
    sensor_range: float = MAPPING_RANGE_M

    def __post_init__(self) -> None:
        if self.explorable.shape != self.grid.shape or self.explorable.dtype != np.bool_:
            raise MapError(
                f"explorable must be a bool mask of shape {self.grid.shape}, "
                f"got {self.explorable.dtype} {self.explorable.shape}"
            )

    @property
    def explorable_count(self) -> int:
        """Number of explorable cells."""
        return int(np.count_nonzero(self.explorable))


def dilate(mask: NDArray[np.bool_], radius: float, strict: bool = False) -> NDArray[np.bool_]:
    """Cells whose centre lies within ``radius`` cells (``< radius`` if strict) of a True cell.

    ORs of shifted copies over the disc offsets: exact, and for the small discs used here about
    10x faster than ``ndimage.binary_dilation`` or a distance transform."""
    k = math.floor(radius)
    dy, dx = np.mgrid[-k : k + 1, -k : k + 1]
    d2 = dy * dy + dx * dx
    keep = d2 < radius * radius - 1e-9 if strict else d2 <= radius * radius + 1e-9
    rows, cols = mask.shape
    padded = np.pad(mask, k)
    out = np.zeros_like(mask)
    for oy, ox in zip(dy[keep].tolist(), dx[keep].tolist(), strict=True):
        out |= padded[k + oy : k + oy + rows, k + ox : k + ox + cols]
    return out


def _clearance(free: NDArray[np.bool_], resolution: float) -> NDArray[np.float64]:
    """Distance (m) from each cell centre to the nearest non-free cell centre; ``free`` must have a
    non-free rim. Only for error messages: the hot path thresholds with :func:`dilate`."""
    return np.asarray(ndimage.distance_transform_edt(free) * resolution, dtype=np.float64)


def _roomy(free: NDArray[np.bool_], clearance_cells: float) -> NDArray[np.bool_]:
    """Free cells at least ``clearance_cells`` (centre to centre) from every non-free cell."""
    return np.asarray(free & ~dilate(~free, clearance_cells, strict=True))


def _short(text: str, limit: int = 80) -> str:
    """``text`` cut to ``limit`` characters (an ellipsis marks the cut)."""
    return text if len(text) <= limit else text[: limit - 1] + "…"


def _start_name(start: Pose) -> str:
    return f"start pose ({_metres(start.x)}, {_metres(start.y)})"


def _metres(value: float) -> str:
    """A coordinate (m) to the centimetre, or in powers of ten when that would take more than 12
    characters (1e300 m printed 300 digits)."""
    text = f"{value:.2f}"
    return text if len(text) <= 12 else f"{value:.3g}"


def _check_start(grid: OccupancyGrid, start: Pose) -> tuple[int, int]:
    """Cell of a given start pose, or MapError naming the pose if it is off the grid or not free."""
    if not all(math.isfinite(v) for v in start):
        raise MapError(f"{_start_name(start)} has a non-finite coordinate: {start}")
    if abs(start.theta) > MAX_HEADING_RAD:
        raise MapError(f"{_start_name(start)} has a heading beyond +-{MAX_HEADING_RAD:g} rad: {start.theta!r}")
    (x0, y0), res = grid.origin, grid.resolution
    far = not (math.isfinite((start.x - x0) / res) and math.isfinite((start.y - y0) / res))
    row, col = (-1, -1) if far else grid.world_to_cell(start.x, start.y)  # far: no cell index at all
    if not grid.in_bounds(row, col):
        w, h = grid.size_m
        raise MapError(
            f"{_start_name(start)} is outside the grid (x in [{x0:.2f}, {x0 + w:.2f}), y in [{y0:.2f}, {y0 + h:.2f}) m)"
        )
    if grid.data[row, col] != CellState.FREE:
        what = "inside a wall" if grid.data[row, col] == CellState.OCCUPIED else "on an unknown cell"
        raise MapError(f"{_start_name(start)} is {what}")
    return row, col


def _random_cell(rng: np.random.Generator, roomy: NDArray[np.bool_], parts: NDArray[np.int32]) -> tuple[int, int]:
    """Uniformly drawn ``roomy`` cell of the largest labelled part (of any part if that has none)."""
    sizes = np.bincount(parts.ravel())
    sizes[0] = 0
    candidates = np.flatnonzero(roomy & (parts == int(np.argmax(sizes))))
    if candidates.size == 0:
        candidates = np.flatnonzero(roomy)
    row, col = divmod(int(candidates[rng.integers(candidates.size)]), roomy.shape[1])
    return row, col


def make_world(
    grid: OccupancyGrid,
    name: str,
    *,
    start: Pose | None = None,
    rng: np.random.Generator | None = None,
    robot_radius: float = ROBOT_RADIUS_M,
    sensor_range: float = MAPPING_RANGE_M,
) -> World:
    """Build a :class:`World` from any occupancy grid (unknown cells count as walls).

    The robot's centre may stand on free cells at least ``robot_radius`` from every non-free cell
    (centre to centre; outside the grid counts as non-free); those 4-connected to the start are
    *reachable*. Explorable cells are the free cells in line of sight of a reachable one within
    ``sensor_range`` (a room behind a door narrower than the robot counts as far as the robot can
    see into it through the door).

    Args:
        grid: the map; its free cells 4-connected to the start stay free, all else becomes occupied.
        name: world name.
        start: start pose (m, m, rad), its heading wrapped into [-pi, pi); when ``None`` one is
            drawn with ``rng``: a uniform cell with clearance >= robot_radius + 0.05 m in the
            largest reachable region, heading uniform in [-pi, pi).
        rng: generator for the random start (required when ``start`` is ``None``).
        robot_radius: robot footprint radius (m).
        sensor_range: range (m) within which the robot's map learns cells.

    Raises:
        ConfigError: ``start`` and ``rng`` both missing, or a non-positive radius or range.
        MapError: a cell size that does not suit the robot (:func:`check_resolution`), no free
            cell with room for the robot, a start outside the grid, in a wall, too close to one or
            with a non-finite or absurd heading, or nothing to explore.
    """
    _check_arguments(name, start, rng, robot_radius, sensor_range)
    res = grid.resolution
    free, (top, left) = _free_window(grid)
    if start is not None:
        _check_start(grid, start)
    check_resolution(res, f"world {_short(repr(name))}: cell size", robot_radius, sensor_range)
    fits = _roomy(free, robot_radius / res)
    if not fits.any():
        raise MapError(
            f"map has no free cell with clearance for the robot (radius {robot_radius:.3f} m; "
            f"roomiest free cell {_clearance(free, res).max():.3f} m)"
        )
    parts, _ = ndimage.label(fits)
    local, start = _place_start(grid, free, (fits, parts), (top, left), start, rng, robot_radius)
    # A digital disc is 4-connected, so clearances inside the start's free component do not change
    # when the other components become walls: nothing needs recomputing.
    components, _ = ndimage.label(free)
    inside = components == components[local]
    explorable_local = visible_from(inside, parts == parts[local], sensor_range / res)
    data, explorable = _full_size(grid.shape, (top, left), inside, explorable_local)
    if not explorable.any():
        raise MapError(
            f"world {_short(repr(name))} has nothing to explore: no free cell is in line of sight "
            f"within {sensor_range:g} m of a place the robot can reach"
        )
    start = checked_pose(start, _start_name(start))
    return World(name, OccupancyGrid(data, res, grid.origin), start, explorable, robot_radius, sensor_range)


def _free_window(grid: OccupancyGrid) -> tuple[NDArray[np.bool_], tuple[int, int]]:
    """The free cells' bounding box with a one-cell non-free rim (cheap on big, mostly unknown
    maps), and the grid cell of its (0, 0) corner (which may lie one cell outside the grid)."""
    free_all = grid.data == CellState.FREE
    rows, cols = np.flatnonzero(free_all.any(axis=1)), np.flatnonzero(free_all.any(axis=0))
    if rows.size == 0:
        raise MapError("map has no free cell with clearance for the robot: it has no free cell at all")
    return np.pad(free_all[rows[0] : rows[-1] + 1, cols[0] : cols[-1] + 1], 1), (int(rows[0]) - 1, int(cols[0]) - 1)


def _check_arguments(
    name: str, start: Pose | None, rng: np.random.Generator | None, robot_radius: float, sensor_range: float
) -> None:
    if not (math.isfinite(robot_radius) and robot_radius > 0):
        raise ConfigError(f"robot_radius must be a positive number of metres, got {robot_radius!r}")
    if not (math.isfinite(sensor_range) and sensor_range > 0):
        raise ConfigError(f"sensor_range must be a positive number of metres, got {sensor_range!r}")
    if start is None and rng is None:
        raise ConfigError(f"world {name!r}: pass a start pose or an rng to draw one (got start=None, rng=None)")


def _full_size(
    shape: tuple[int, int], corner: tuple[int, int], inside: NDArray[np.bool_], explorable: NDArray[np.bool_]
) -> tuple[NDArray[np.int8], NDArray[np.bool_]]:
    """The world's grid (``inside`` free, all else occupied) and explorable cells at the map's
    full ``shape``, read-only, from the padded window whose (1, 1) is cell ``corner`` + (1, 1)."""
    top, left = corner
    window = (slice(top + 1, top + inside.shape[0] - 1), slice(left + 1, left + inside.shape[1] - 1))
    data = np.full(shape, CellState.OCCUPIED, dtype=np.int8)
    data[window][inside[1:-1, 1:-1]] = CellState.FREE
    full = np.zeros(shape, dtype=np.bool_)
    full[window] = explorable[1:-1, 1:-1]
    data.flags.writeable = False
    full.flags.writeable = False
    return data, full


def _place_start(
    grid: OccupancyGrid,
    free: NDArray[np.bool_],
    room: tuple[NDArray[np.bool_], NDArray[np.int32]],
    corner: tuple[int, int],
    start: Pose | None,
    rng: np.random.Generator | None,
    robot_radius: float,
) -> tuple[tuple[int, int], Pose]:
    """The start's cell in the padded window ``free`` whose (1, 1) is grid cell ``corner`` + (1, 1),
    and the start pose: ``start`` checked for room, or one drawn with ``rng`` on a roomy cell of
    the largest region. ``room`` holds the cells the robot fits on and their regions (labels)."""
    res, (top, left), (fits, parts) = grid.resolution, corner, room
    if start is None:
        assert rng is not None
        roomy = _roomy(free, (robot_radius + START_MARGIN_M) / res)
        if not roomy.any():
            raise MapError(
                "map has no free cell with clearance for the robot: a random start needs "
                f"{robot_radius + START_MARGIN_M:.3f} m, the roomiest free cell has "
                f"{_clearance(free, res).max():.3f} m"
            )
        local = _random_cell(rng, roomy, parts)
        x, y = grid.cell_to_world(local[0] + top, local[1] + left)
        return local, Pose(x, y, float(rng.uniform(-math.pi, math.pi)))
    row, col = grid.world_to_cell(start.x, start.y)
    local = (row - top, col - left)
    if not fits[local]:
        raise MapError(
            f"{_start_name(start)} is too close to a wall: clearance "
            f"{_clearance(free, res)[local]:.3f} m < robot radius {robot_radius:.3f} m"
        )
    return local, start
