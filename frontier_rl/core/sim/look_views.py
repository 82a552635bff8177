"""Where a last look is taken from: of the reachable cells on a lattice, the one whose LiDAR scan
would see the most of the unknown a frontier cluster opens onto (:mod:`frontier_rl.core.sim.looks`).

A view's promise is counted by casting the scan's rays
(:func:`~frontier_rl.core.frontiers.detection.visible_unknown`) on the map with only that unknown
left unknown: other unknown cells let the rays through uncounted. The clusters that open onto the
same unknown share the counts (:class:`ViewGains`), and only the rays that can meet the unknown
are cast, in the part of the map the scans reach: the office's sealed rooms pass the area check of
every blind look at the end of its episodes, and casting every ray there cost a third of their
CPU time.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from frontier_rl.core.frontiers.detection import Frontiers, visible_unknown
from frontier_rl.core.frontiers.fringe import NEIGHBOURS_8, labels_beside
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.worlds import dilate

VIEWPOINT_STRIDE = 2
"""Every how many reachable cells (along rows and columns) a viewpoint is tried: 0.1 m on the
thesis's 0.05 m cells, finer than a gap the robot can see through is wide."""


def unknown_regions(grid: OccupancyGrid) -> tuple[NDArray[np.int32], NDArray[np.float64]]:
    """The labels of ``grid``'s 4-connected unknown regions (0: known cells) and each one's area (m²)."""
    labels, count = ndimage.label(grid.data == CellState.UNKNOWN)
    areas = np.bincount(labels.ravel(), minlength=count + 1) * grid.resolution**2
    return np.asarray(labels, np.int32), areas.astype(np.float64)


def opened_onto(regions: tuple[NDArray[np.int32], NDArray[np.float64]], cells: NDArray[np.int64]) -> NDArray[np.int64]:
    """The labels of the unknown ``regions`` (labels, areas in m²) the cluster ``cells`` (rows,
    cols) opens onto: those beside its cells, but any whose area is 0 (one a look may not count)."""
    labels, areas = regions
    beside = labels_beside(labels, cells[:, 0], cells[:, 1])
    return beside[areas[beside] > 0]


def segments_opened_areas(
    flat_cells: NDArray[np.int64], spans: NDArray[np.int64], regions: tuple[NDArray[np.int32], NDArray[np.float64]]
) -> NDArray[np.float64]:
    """(n,) the area (m²) of the unknown ``regions`` (labels, areas in m²) each cluster opens onto
    (:func:`opened_onto`), for all at once: the clusters whose cells are ``flat_cells[start:end]``
    (flat indices into the map) for each (start, end) of ``spans``."""
    labels, areas = regions
    sizes = spans[:, 1] - spans[:, 0]
    owner = np.repeat(np.arange(len(spans)), sizes)
    at = np.repeat(spans[:, 0] - np.cumsum(sizes) + sizes, sizes) + np.arange(len(owner))
    rows, cols = np.divmod(flat_cells[at], labels.shape[1])
    r, c = rows[:, None] + NEIGHBOURS_8[:, 0], cols[:, None] + NEIGHBOURS_8[:, 1]
    inside = (r >= 0) & (r < labels.shape[0]) & (c >= 0) & (c < labels.shape[1])
    beside = np.where(inside, labels[np.clip(r, 0, labels.shape[0] - 1), np.clip(c, 0, labels.shape[1] - 1)], 0)
    count = len(areas)  # each (cluster, region) pair once, as one number
    pairs = np.unique(np.repeat(owner, 8) * count + beside.ravel())
    owners, regions_beside = np.divmod(pairs[pairs % count > 0], count)
    return np.asarray(np.bincount(owners, weights=areas[regions_beside], minlength=len(spans)), np.float64)


def look_promise_cells(
    grid: OccupancyGrid,
    cells: NDArray[np.int64],
    reachable: NDArray[np.bool_],
    config: SimConfig,
    regions: tuple[NDArray[np.int32], NDArray[np.float64]],
) -> int:
    """How many cells of the unknown the frontier ``cells`` (rows, cols of ``grid``) opens onto a
    scan would see from the best of the ``reachable`` cells (every one, not a lattice's) within a
    frontier goal's reach of it: the most any look at it could reveal. ``regions``: the map's
    unknown regions (:func:`unknown_regions`)."""
    target = np.isin(regions[0], opened_onto(regions, cells)) & (regions[0] > 0)
    reach = min(config.frontier_goal_reach, config.mapping_range)
    return best_viewpoint(grid, target, np.argwhere(reachable).astype(np.int64), cells, reach, config)[1]


def viewpoint_cells(
    reachable: NDArray[np.bool_], grid: OccupancyGrid, tried: Callable[[NDArray[np.float64]], NDArray[np.bool_]]
) -> NDArray[np.int64]:
    """(k, 2) the reachable cells (row, col) on the viewpoint lattice, but those ``tried`` (a mask
    of world points (m), such as :meth:`~frontier_rl.core.frontiers.blacklist.Blacklist.tried_near`)."""
    lattice = np.zeros_like(reachable)
    lattice[::VIEWPOINT_STRIDE, ::VIEWPOINT_STRIDE] = True
    views = np.argwhere(reachable & lattice).astype(np.int64)
    if len(views):
        views = views[~tried(grid.cells_to_world(views))]
    return views


def best_looks(
    grid: OccupancyGrid,
    clusters: Frontiers,
    chosen: list[int],
    map_unknown: tuple[NDArray[np.int32], NDArray[np.float64]],
    views: NDArray[np.int64],
    config: SimConfig,
    least_m2: float,
) -> dict[tuple[int, int], list[int]]:
    """The ``chosen`` clusters worth a look, by the viewpoint (row, col) of ``views`` that is the
    best look at each: whose scan would see at least ``least_m2`` of the unknown regions the
    cluster opens onto (``map_unknown``: the labels of the map's unknown regions and each one's
    area in m², 0 for those a look may not count)."""
    labels, areas = map_unknown
    reach = min(config.frontier_goal_reach, config.mapping_range)
    least = least_m2 / grid.resolution**2
    groups: dict[tuple[int, int], list[int]] = {}
    counted: dict[tuple[int, ...], ViewGains] = {}  # by the regions opened onto
    for i in chosen:
        cells = clusters.cells_of(i)
        regions = opened_onto(map_unknown, cells)
        if areas[regions].sum() < least_m2:
            continue
        key = tuple(regions.tolist())  # sorted and unique, as labels_beside gives them
        if key not in counted:  # labels > 0, as opened onto
            target = labels == key[0] if len(key) == 1 else np.isin(labels, key)
            counted[key] = ViewGains(grid, target, views, config)
        best, gain = counted[key].best(cells, reach)
        if gain >= least:
            groups.setdefault((int(best[0]), int(best[1])), []).append(i)
    return groups


def best_viewpoint(
    grid: OccupancyGrid,
    target: NDArray[np.bool_],
    views: NDArray[np.int64],
    cells: NDArray[np.int64],
    reach: float,
    config: SimConfig,
) -> tuple[NDArray[np.int64], int]:
    """The viewpoint (row, col) of ``views`` within ``reach`` (m) of the cluster ``cells`` whose
    scan would see the most ``target`` cells (:class:`ViewGains`), and that count."""
    return ViewGains(grid, target, views, config).best(cells, reach)


class ViewGains:
    """How many of the ``target`` cells of ``grid`` (the unknown a cluster opens onto; other
    unknown cells let the rays through uncounted) a scan from each of the viewpoints ``views``
    (row, col) would see: counted when first asked for, so that the clusters opening onto the same
    unknown share them."""

    def __init__(self, grid: OccupancyGrid, target: NDArray[np.bool_], views: NDArray[np.int64], config: SimConfig):
        self._grid = grid
        self._target = target
        self._views = views
        self._gains = np.full(len(views), -1, np.int64)  # -1: not counted yet
        self._rays = config.lidar.num_beams
        self._sight = config.mapping_range / grid.resolution

    def best(self, cells: NDArray[np.int64], reach: float) -> tuple[NDArray[np.int64], int]:
        """The viewpoint (row, col) within ``reach`` (m) of the cluster ``cells`` that sees the
        most target cells (the first of those), and that count; (-1, -1) and 0 where none is."""
        near = np.flatnonzero(np.hypot(*(self._views - cells.mean(axis=0)).T) * self._grid.resolution <= reach)
        if len(near) == 0:
            return np.array([-1, -1], np.int64), 0
        todo = near[self._gains[near] < 0]
        if len(todo):
            self._gains[todo] = self._count(self._views[todo])
        best = near[int(np.argmax(self._gains[near]))]
        return self._views[best], int(self._gains[best])

    def _count(self, views: NDArray[np.int64]) -> NDArray[np.int64]:
        """The target cells a scan from each of ``views`` (row, col) would see, cast in the window
        of the map the scans reach (a ray goes no farther than the sight and a cell and a half),
        with the hints of :func:`~frontier_rl.core.frontiers.detection.visible_unknown`: the box
        of the target cells there and those a ray can first meet them at."""
        margin = int(math.ceil(self._sight)) + 2
        top, left = np.maximum(views.min(axis=0) - margin, 0)
        bottom, right = views.max(axis=0) + margin + 1
        target = self._target[top:bottom, left:right]
        rows, cols = np.nonzero(target)
        if len(rows) == 0:
            return np.zeros(len(views), np.int64)
        occupied = self._grid.data[top:bottom, left:right] == CellState.OCCUPIED
        state = np.where(occupied, CellState.OCCUPIED, CellState.FREE).astype(np.int8)
        state[rows, cols] = CellState.UNKNOWN
        # where a ray can first meet the target: its cells beside a cell neither target nor wall
        # (4-neighbours: a ray crosses cells through their sides)
        entries = np.argwhere(target & dilate(~target & ~occupied, 1.0)).astype(np.int64)
        box = (float(rows.min()), float(rows.max() + 1), float(cols.min()), float(cols.max() + 1))
        origins = (views - (top, left))[:, ::-1].astype(np.float64) + 0.5  # (col, row), cell units
        return visible_unknown(state, origins, self._rays, self._sight, box, entries)
