"""HouseExpo floor plans (JSON): one polygon of free space in metres, rasterised to a grid.

A file holds ``verts``, one closed polygon (m): inside is free, everything else is wall. Interior
walls are thin slits cut into the outline, and a slit narrower than a cell can fall between two
cell centres. Cells are sampled at their centres (matplotlib's point-in-polygon), then every place
where the outline passes between two 4-adjacent free centres (a wall that sampling lost) gets the
cell that the outline crosses marked occupied, so every wall stays at least one cell thick.
"""

from __future__ import annotations

import json
import math
import numbers
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.grid import CellState, OccupancyGrid
from frontier_rl.errors import MapError
from frontier_rl.io.loaded_map import LoadedMap, positive_metres

#: Default cell size (m), the Gmapping default.
HOUSEEXPO_RESOLUTION = 0.05
#: Default band of wall (m) around the polygon's bounding box.
HOUSEEXPO_MARGIN = 0.5
#: Largest grid (cells) the loader will allocate, against a typo such as resolution 1e-6.
MAX_CELLS = 16_000_000
#: Polygons with less area (m^2) than this are degenerate.
MIN_AREA = 1e-9


def _read_verts(path: Path) -> NDArray[np.float64]:
    """The polygon of a HouseExpo JSON as an (n, 2) array (m), without a repeated closing vertex."""
    if not path.is_file():
        raise MapError(f"map file not found: {path}")
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise MapError(f"cannot parse HouseExpo JSON {path}: {exc}") from exc
    if not isinstance(doc, dict) or "verts" not in doc:
        raise MapError(f"{path}: a HouseExpo file must be a JSON object with a 'verts' field")
    try:
        verts = np.asarray(doc["verts"], dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise MapError(f"{path}: 'verts' must be a list of [x, y] pairs in metres: {exc}") from exc
    if verts.ndim != 2 or verts.shape[1] != 2 or not np.isfinite(verts).all():
        raise MapError(f"{path}: 'verts' must be a list of finite [x, y] pairs, got shape {verts.shape}")
    if len(verts) > 1 and np.array_equal(verts[0], verts[-1]):
        verts = verts[:-1]
    x, y = verts[:, 0], verts[:, 1]
    area = 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y)))
    if len(verts) < 3 or area < MIN_AREA:
        raise MapError(f"{path}: degenerate polygon ({len(verts)} vertices, area {area:g} m^2)")
    return verts


def _line_crossings(
    a0: NDArray[np.float64],
    b0: NDArray[np.float64],
    a1: NDArray[np.float64],
    b1: NDArray[np.float64],
    n_lines: int,
) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """Where segments (a0, b0)-(a1, b1) cross the lines b = 0, 1, ..., n_lines - 1: (line, a) pairs."""
    lo, hi = np.minimum(b0, b1), np.maximum(b0, b1)
    first = np.maximum(np.ceil(lo), 0).astype(np.int64)
    last = np.minimum(np.floor(hi), n_lines - 1).astype(np.int64)
    counts = np.where(b0 != b1, np.maximum(last - first + 1, 0), 0)
    edge = np.repeat(np.arange(len(a0)), counts)
    offset = np.arange(int(counts.sum())) - np.repeat(np.cumsum(counts) - counts, counts)
    line = first[edge] + offset
    t = (line - b0[edge]) / (b1[edge] - b0[edge])
    return line, a0[edge] + t * (a1[edge] - a0[edge])


def _restore_thin_walls(
    inside: NDArray[np.bool_], verts: NDArray[np.float64], origin: NDArray[np.float64], resolution: float
) -> NDArray[np.bool_]:
    """Free mask: ``inside`` minus the cells where the outline runs between two free centres."""
    # Cell units in which the centre of cell (row, col) sits at (u, v) = (col, row).
    start = (verts - origin) / resolution - 0.5
    end = np.roll(start, -1, axis=0)
    free = inside.copy()
    rows, cols = inside.shape
    # Crossings of the rows (v = row) lie between columns floor(u) and floor(u) + 1, and vice versa.
    row, u = _line_crossings(start[:, 0], start[:, 1], end[:, 0], end[:, 1], rows)
    left = np.floor(u).astype(np.int64)
    ok = (left >= 0) & (left < cols - 1)
    row, u, left = row[ok], u[ok], left[ok]
    lost = inside[row, left] & inside[row, left + 1]
    free[row[lost], np.floor(u[lost] + 0.5).astype(np.int64)] = False
    col, v = _line_crossings(start[:, 1], start[:, 0], end[:, 1], end[:, 0], cols)
    below = np.floor(v).astype(np.int64)
    ok = (below >= 0) & (below < rows - 1)
    col, v, below = col[ok], v[ok], below[ok]
    lost = inside[below, col] & inside[below + 1, col]
    free[np.floor(v[lost] + 0.5).astype(np.int64), col[lost]] = False
    return free


def load_houseexpo(
    json_path: str | Path, resolution: float = HOUSEEXPO_RESOLUTION, margin_m: float = HOUSEEXPO_MARGIN
) -> LoadedMap:
    """Rasterise a HouseExpo floor plan: inside the polygon free, everything else occupied.

    Args:
        json_path: the HouseExpo JSON file.
        resolution: cell size (m).
        margin_m: band of wall (m) added around the polygon's bounding box.

    Returns:
        The grid, placed so that world coordinates equal the file's metres, and no start (None).

    Raises:
        MapError: a missing or malformed file, no or a degenerate polygon, or bad sizes.
    """
    from matplotlib.path import Path as PolygonPath  # deferred: matplotlib is slow to import

    path = Path(json_path)
    res = positive_metres(resolution, "resolution", path)
    if isinstance(margin_m, bool) or not isinstance(margin_m, numbers.Real) or not math.isfinite(margin_m):
        raise MapError(f"{path}: margin_m must be a finite number of metres >= 0, got {margin_m!r}")
    if margin_m < 0:
        raise MapError(f"{path}: margin_m must be a finite number of metres >= 0, got {margin_m!r}")
    verts = _read_verts(path)
    origin = verts.min(axis=0) - float(margin_m)
    extent = verts.max(axis=0) + float(margin_m) - origin
    cols, rows = (max(math.ceil(e / res - 1e-9), 1) for e in extent)
    if rows * cols > MAX_CELLS:
        raise MapError(f"{path}: a {rows} x {cols} grid at resolution {res!r} m is too large")
    xs = origin[0] + (np.arange(cols) + 0.5) * res
    ys = origin[1] + (np.arange(rows) + 0.5) * res
    centres = np.column_stack([np.tile(xs, rows), np.repeat(ys, cols)])
    polygon = PolygonPath(np.vstack([verts, verts[:1]]), closed=True)
    inside = np.asarray(polygon.contains_points(centres), dtype=np.bool_).reshape(rows, cols)
    free = _restore_thin_walls(inside, verts, origin, res)
    data = np.where(free, CellState.FREE, CellState.OCCUPIED).astype(np.int8)
    grid = OccupancyGrid(data, res, (float(origin[0]), float(origin[1])))
    return LoadedMap(grid=grid, start=None, source=path)
