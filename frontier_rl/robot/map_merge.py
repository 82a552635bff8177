"""A robot's map merged with its teammates' maps, without ROS, as m-explore's ``map_merge`` does with
known start poses: the maps of a team share one frame, so a cell that a teammate has mapped and the
robot has not is known to it too, and its explorer does not send it where a teammate has been.

The robot's own map is kept wherever it knows a cell (what its own sensor saw is the best it has of
the cells it must drive through); the teammates' maps fill the cells it does not know, a wall in
one teammate's map winning over free space in another's.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.errors import MapError

_ALIGNMENT_CELLS = 1e-3
"""How far (in cells) a teammate's map may lie off the robot's cell lattice and still be merged."""


def misfit(own: OccupancyGrid, other: OccupancyGrid) -> str:
    """Why ``other`` cannot be merged into ``own`` (another resolution, or off ``own``'s cell
    lattice), or "" if it can."""
    if not math.isclose(other.resolution, own.resolution, rel_tol=1e-9):
        return f"its cells are {other.resolution!r} m, this robot's {own.resolution!r} m"
    rows, cols = _offset(own, other)
    if abs(rows - round(rows)) > _ALIGNMENT_CELLS or abs(cols - round(cols)) > _ALIGNMENT_CELLS:
        return f"it lies off this robot's cells (its origin {other.origin!r})"
    return ""


def _offset(own: OccupancyGrid, other: OccupancyGrid) -> tuple[float, float]:
    """(rows, cols) from ``own``'s origin to ``other``'s, in ``own``'s cells."""
    res = own.resolution
    return (other.origin[1] - own.origin[1]) / res, (other.origin[0] - own.origin[0]) / res


def merged_map(own: OccupancyGrid, teammates: Sequence[OccupancyGrid]) -> OccupancyGrid:
    """``own`` grown to the teammates' maps and filled with what they know where it knows nothing.

    Raises:
        MapError: a teammate's map of another resolution, or off ``own``'s cell lattice.
    """
    if not teammates:
        return own
    for other in teammates:
        problem = misfit(own, other)
        if problem:
            raise MapError(f"a teammate's map cannot be merged: {problem}")
    offsets = [(0, 0), *((round(r), round(c)) for r, c in (_offset(own, other) for other in teammates))]
    grids = [own, *teammates]
    top = min(r for r, _ in offsets)
    left = min(c for _, c in offsets)
    bottom = max(r + g.height for (r, _), g in zip(offsets, grids, strict=True))
    right = max(c + g.width for (_, c), g in zip(offsets, grids, strict=True))
    data = np.full((bottom - top, right - left), CellState.UNKNOWN, np.int8)
    for (row, col), grid in reversed(list(zip(offsets, grids, strict=True))):  # the robot's own map last
        window = data[row - top : row - top + grid.height, col - left : col - left + grid.width]
        known = grid.data != CellState.UNKNOWN
        if grid is own:
            window[known] = grid.data[known]
        else:
            window[known & (window != CellState.OCCUPIED)] = grid.data[known & (window != CellState.OCCUPIED)]
    origin = (own.origin[0] + left * own.resolution, own.origin[1] + top * own.resolution)
    return OccupancyGrid(data, own.resolution, origin)
