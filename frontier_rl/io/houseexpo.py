"""HouseExpo floor plans (JSON): one polygon of free space in metres, rasterised to a grid.

A file holds ``verts``, one closed polygon (m): inside is free, everything else is wall. Interior
walls are thin slits cut into the outline, and a slit narrower than a cell can fall between two
cell centres. Cells are sampled at their centres (matplotlib's point-in-polygon), then every place
where the outline passes between two 4-adjacent free centres (a wall that sampling lost) gets the
cell that the outline crosses marked occupied, so every wall stays at least one cell thick.

Files are untrusted input: a file over :data:`MAX_FILE_BYTES`, a polygon of more than
:data:`MAX_VERTICES` vertices or with a coordinate beyond +-:data:`MAX_COORDINATE_M`, a polygon
whose outline crosses itself (a bow tie, or a figure of eight through one vertex: inside and
outside are then undefined), one of zero area,
a grid of more than :data:`MAX_CELLS` cells, or one whose cells times the polygon's vertices exceed
:data:`MAX_RASTER_WORK` (minutes of sampling) is refused with a :class:`MapError` naming the
file. Repeated consecutive vertices are dropped (they add no edge); edges that only touch (a slit
of zero width) are kept.
"""

from __future__ import annotations

import json
import math
import numbers
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.errors import MapError
from frontier_rl.io.loaded_map import MAX_COORDINATE_M, LoadedMap, positive_metres

#: Default cell size (m), the Gmapping default.
HOUSEEXPO_RESOLUTION = 0.05
#: Default band of wall (m) around the polygon's bounding box.
HOUSEEXPO_MARGIN = 0.5
#: Largest grid (cells) the loader will allocate, against a typo such as resolution 1e-6.
MAX_CELLS = 16_000_000
#: Polygons with less area (m^2) than this are degenerate.
MIN_AREA = 1e-9
#: Largest HouseExpo file (bytes) read; the dataset's files are a few kilobytes.
MAX_FILE_BYTES = 16 * 1024 * 1024
#: Most polygon vertices accepted; the dataset's outlines have hundreds.
MAX_VERTICES = 10_000
#: Most vertex-cells (the polygon's vertices times the grid's cells) rasterised: sampling every cell
#: against every edge takes about a second per 3e8 (the dataset's plans: up to about 3e7).
MAX_RASTER_WORK = 2_000_000_000
#: Two edges cross only where each passes more than this (m) to either side of the other's line.
CROSSING_TOLERANCE_M = 1e-6
_PAIRS_AT_ONCE = 1_000_000  # edge pairs compared at once (bounded memory)


def _is_number(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def _read_verts(path: Path) -> NDArray[np.float64]:  # noqa: C901 (a validator: one branch per malformed-input case, each with its own error)
    """The polygon of a HouseExpo JSON as an (n, 2) array (m): repeated consecutive vertices (a
    repeated closing vertex included) dropped, checked not to cross itself and to have an area."""
    if not path.is_file():
        raise MapError(f"map file not found: {path}")
    try:
        size = path.stat().st_size
        if size > MAX_FILE_BYTES:
            raise MapError(f"{path}: a HouseExpo file of {size} bytes is too large (at most {MAX_FILE_BYTES})")
        doc = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError, RecursionError) as exc:  # ValueError: not UTF-8, not JSON, a 4300-digit integer
        reason = "nested too deeply" if isinstance(exc, RecursionError) else str(exc)[:200]
        raise MapError(f"cannot parse HouseExpo JSON {path}: {reason}") from None
    if not isinstance(doc, dict) or "verts" not in doc:
        raise MapError(f"{path}: a HouseExpo file must be a JSON object with a 'verts' field")
    raw = doc["verts"]
    if not isinstance(raw, list):
        raise MapError(f"{path}: 'verts' must be a list of [x, y] pairs in metres, got {type(raw).__name__}")
    if len(raw) > MAX_VERTICES:
        raise MapError(f"{path}: 'verts' has {len(raw)} vertices, more than the {MAX_VERTICES} accepted")
    for k, pair in enumerate(raw):
        if not (isinstance(pair, list) and len(pair) == 2 and all(_is_number(v) for v in pair)):
            shown = json.dumps(pair)[:80]
            raise MapError(f"{path}: 'verts' must be a list of [x, y] pairs in metres; vertex {k} is {shown}")
    try:
        verts = np.array(raw, dtype=np.float64).reshape(-1, 2)
    except OverflowError:
        raise MapError(f"{path}: 'verts' must be a list of finite [x, y] pairs, got a number too large") from None
    if not np.isfinite(verts).all():
        raise MapError(f"{path}: 'verts' must be a list of finite [x, y] pairs, got shape {verts.shape}")
    if verts.size and float(np.abs(verts).max()) > MAX_COORDINATE_M:
        worst = float(np.abs(verts).max())
        raise MapError(f"{path}: 'verts' coordinates must be within +-{MAX_COORDINATE_M:g} m, got {worst:g}")
    # Drop every vertex equal to the next one (cyclically: a repeated closing vertex too), so
    # that no edge has zero length.
    keep = np.any(verts != np.roll(verts, -1, axis=0), axis=1)
    if keep.size and not keep.any():  # every vertex the same point: keep one
        keep[0] = True
    index = np.flatnonzero(keep)
    verts = verts[keep]
    if len(verts) >= 3:
        _check_simple(path, verts, index)
    x, y = verts[:, 0], verts[:, 1]
    area = 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y)))
    if len(verts) < 3 or area < MIN_AREA:
        raise MapError(f"{path}: degenerate polygon ({len(verts)} vertices, area {area:g} m^2)")
    return verts


def _crossings(verts: NDArray[np.float64]) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """The pairs (i, j), i < j, of edges of the closed polygon ``verts`` (edge k runs from vertex k
    to k + 1) that cross: each passes more than :data:`CROSSING_TOLERANCE_M` to either side of the
    other's line, or one ends on the inside of the other and the outline goes on to its other
    side (it crosses through a vertex). Edges that only touch or overlap along a line do not count.

    A sweep along x: edges sorted by their left end are compared only with the edges that start
    before they end, at most :data:`_PAIRS_AT_ONCE` pairs at a time."""
    a = verts
    b = np.roll(verts, -1, axis=0)
    n = len(a)
    d = b - a
    length = np.hypot(d[:, 0], d[:, 1])
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    order = np.argsort(lo[:, 0], kind="stable")
    ends = np.searchsorted(lo[order, 0], hi[order, 0], side="right")  # sorted edges that start before k ends
    counts = np.maximum(ends - np.arange(1, n + 1), 0)
    cumulative = np.cumsum(counts)

    def offsets(e: NDArray[np.int64], p: NDArray[np.float64]) -> NDArray[np.float64]:
        """Signed distance (m) of the points ``p`` from the lines of the edges ``e``."""
        rel = p - a[e]
        return np.asarray((d[e, 0] * rel[:, 1] - d[e, 1] * rel[:, 0]) / length[e])

    def straddles(e: NDArray[np.int64], other: NDArray[np.int64]) -> NDArray[np.bool_]:
        s, t = offsets(e, a[other]), offsets(e, b[other])
        tol = CROSSING_TOLERANCE_M
        return np.asarray(((s > tol) & (t < -tol)) | ((s < -tol) & (t > tol)))

    def through_vertex(e: NDArray[np.int64], other: NDArray[np.int64]) -> NDArray[np.bool_]:
        """Whether ``other`` ends on the inside of ``e`` and the outline passes from one side of
        ``e``'s line to the other at that vertex."""
        tol = CROSSING_TOLERANCE_M
        crossing = np.zeros(len(e), np.bool_)
        for vertex in (other, (other + 1) % n):  # each end of ``other``
            point = a[vertex]
            along = ((point - a[e]) * d[e]).sum(axis=1) / length[e]
            on = (np.abs(offsets(e, point)) <= tol) & (along > tol) & (along < length[e] - tol)
            before, after = offsets(e, a[(vertex - 1) % n]), offsets(e, a[(vertex + 1) % n])
            crossing |= on & (((before > tol) & (after < -tol)) | ((before < -tol) & (after > tol)))
        return crossing

    found: list[NDArray[np.int64]] = []
    first = 0
    while first < n:
        done = int(cumulative[first - 1]) if first else 0
        last = max(int(np.searchsorted(cumulative, done + _PAIRS_AT_ONCE, side="right")), first + 1)
        k = np.arange(first, min(last, n))
        reps = counts[k]
        left = np.repeat(k, reps)
        right = left + 1 + np.arange(int(reps.sum())) - np.repeat(np.cumsum(reps) - reps, reps)
        i, j = np.minimum(order[left], order[right]), np.maximum(order[left], order[right])
        keep = (j - i > 1) & ~((i == 0) & (j == n - 1))  # neither an edge's neighbour
        keep &= (lo[i, 1] <= hi[j, 1]) & (lo[j, 1] <= hi[i, 1])  # bounding boxes overlap in y
        i, j = i[keep], j[keep]
        crossing = (straddles(i, j) & straddles(j, i)) | through_vertex(i, j) | through_vertex(j, i)
        found.append(np.column_stack((i[crossing], j[crossing])))
        first = last
    pairs = np.unique(np.concatenate(found).astype(np.int64).reshape(-1, 2), axis=0)
    return pairs[:, 0], pairs[:, 1]


def _vertex_crossings(verts: NDArray[np.float64]) -> list[tuple[int, int]]:
    """The pairs (i, j), i < j, of vertices of the closed polygon ``verts`` at the same point
    (within :data:`CROSSING_TOLERANCE_M`) where the outline's second pass crosses its first: its
    edges in and out of the point lie on either side of the first pass's two edges (a figure of
    eight through one vertex). Passes that only touch (two rooms meeting at a corner) or run along
    each other do not count. :func:`_crossings` leaves shared vertices out."""
    n = len(verts)
    keys = np.round(verts / CROSSING_TOLERANCE_M).astype(np.int64)
    _, group, counts = np.unique(keys, axis=0, return_inverse=True, return_counts=True)
    found = []
    for label in np.flatnonzero(counts > 1):
        at = np.flatnonzero(group.ravel() == label)
        for a, i in enumerate(at):
            for j in at[a + 1 :]:
                if _passes_cross(verts, int(i), int(j), n):
                    found.append((int(i), int(j)))
    return found


def _passes_cross(verts: NDArray[np.float64], i: int, j: int, n: int) -> bool:
    """Whether the outline's passes through vertices ``i`` and ``j`` (the same point) cross."""
    point = verts[i]

    def angle(k: int) -> float:
        dx, dy = verts[k % n] - point
        return math.atan2(float(dy), float(dx))

    start = angle(i - 1)
    turn = [(angle(k) - start) % (2 * math.pi) for k in (i + 1, j - 1, j + 1)]
    tol = 1e-9
    if any(t < tol or t > 2 * math.pi - tol for t in turn) or any(abs(t - turn[0]) < tol for t in turn[1:]):
        return False  # a ray along the first pass: the outlines overlap there, they do not cross
    return (turn[1] < turn[0]) != (turn[2] < turn[0])


def _check_simple(path: Path, verts: NDArray[np.float64], index: NDArray[np.int64]) -> None:
    """MapError naming the first crossing edges (by the file's vertex numbers) if the outline
    ``verts`` crosses itself, or the vertex it crosses itself at; ``index`` holds each vertex's
    number in the file."""
    cross_i, cross_j = _crossings(verts)
    if cross_i.size == 0:
        at_vertex = _vertex_crossings(verts)
        if at_vertex:
            (i, j), (x, y) = at_vertex[0], verts[at_vertex[0][0]]
            raise MapError(
                f"{path}: the polygon crosses itself (inside and outside are undefined): it passes through "
                f"({x:g}, {y:g}) as vertex {index[i]} and again as vertex {index[j]}, crossing its first pass"
            )
        return
    n = len(verts)

    def edge(k: int) -> str:
        (x0, y0), (x1, y1) = verts[k], verts[(k + 1) % n]
        return f"{index[k]}-{index[(k + 1) % n]} ({x0:g}, {y0:g})-({x1:g}, {y1:g})"

    i, j = int(cross_i[0]), int(cross_j[0])
    more = f" ({cross_i.size} crossing pairs in all)" if cross_i.size > 1 else ""
    raise MapError(
        f"{path}: the polygon crosses itself (inside and outside are undefined): "
        f"edge {edge(i)} crosses edge {edge(j)}{more}"
    )


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


@dataclass(frozen=True, eq=False)
class HouseExpoPlan:
    """A HouseExpo floor plan, read and checked, and the grid it is rasterised on.

    Attributes:
        verts: the polygon, an (n, 2) array (m), repeated consecutive vertices dropped.
        origin: the grid's lower-left corner (x, y) (m).
        cols: cells along x.
        rows: cells along y.
        resolution: cell size (m).
    """

    verts: NDArray[np.float64]
    origin: tuple[float, float]
    cols: int
    rows: int
    resolution: float


def read_houseexpo_plan(
    json_path: str | Path, resolution: float = HOUSEEXPO_RESOLUTION, margin_m: float = HOUSEEXPO_MARGIN
) -> HouseExpoPlan:
    """Read a HouseExpo file's polygon and size its grid, without rasterising: the polygon's
    bounding box and a band of ``margin_m`` (m) around it, in cells of ``resolution`` (m). The one
    place the grid's size is computed (:func:`load_houseexpo` rasterises this plan).

    Raises:
        MapError: a missing or malformed file, no or a degenerate polygon, or bad sizes.
    """
    path = Path(json_path)
    res = positive_metres(resolution, "resolution", path)
    if isinstance(margin_m, bool) or not isinstance(margin_m, numbers.Real) or not math.isfinite(margin_m):
        raise MapError(f"{path}: margin_m must be a finite number of metres >= 0, got {margin_m!r}")
    if margin_m < 0:
        raise MapError(f"{path}: margin_m must be a finite number of metres >= 0, got {margin_m!r}")
    verts = _read_verts(path)
    origin = verts.min(axis=0) - float(margin_m)
    extent = verts.max(axis=0) + float(margin_m) - origin
    with np.errstate(over="ignore"):
        span = extent / res  # cells along x and y, before anything is allocated
    if not (np.isfinite(span).all() and float(np.maximum(span, 1.0)[0]) * float(np.maximum(span, 1.0)[1]) <= MAX_CELLS):
        size = f"{extent[0]:g} m x {extent[1]:g} m"
        raise MapError(f"{path}: {size} at resolution {res!r} m is more than {MAX_CELLS} cells")
    cols, rows = (max(math.ceil(e / res - 1e-9), 1) for e in extent)
    if rows * cols > MAX_CELLS:
        raise MapError(f"{path}: a {rows} x {cols} grid at resolution {res!r} m is too large")
    if rows * cols * len(verts) > MAX_RASTER_WORK:
        raise MapError(
            f"{path}: a polygon of {len(verts)} vertices on a {rows} x {cols} grid is too much to rasterise "
            f"(at most {MAX_RASTER_WORK:.0e} vertex-cells); give a coarser resolution or a simpler polygon"
        )
    return HouseExpoPlan(verts, (float(origin[0]), float(origin[1])), cols, rows, res)


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

    plan = read_houseexpo_plan(json_path, resolution, margin_m)
    verts, res, rows, cols = plan.verts, plan.resolution, plan.rows, plan.cols
    origin = np.array(plan.origin)
    xs = origin[0] + (np.arange(cols) + 0.5) * res
    ys = origin[1] + (np.arange(rows) + 0.5) * res
    centres = np.column_stack([np.tile(xs, rows), np.repeat(ys, cols)])
    polygon = PolygonPath(np.vstack([verts, verts[:1]]), closed=True)
    inside = np.asarray(polygon.contains_points(centres), dtype=np.bool_).reshape(rows, cols)
    free = _restore_thin_walls(inside, verts, origin, res)
    data = np.where(free, CellState.FREE, CellState.OCCUPIED).astype(np.int8)
    grid = OccupancyGrid(data, res, plan.origin)
    return LoadedMap(grid=grid, start=None, source=Path(json_path))
