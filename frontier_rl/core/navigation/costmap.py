"""The costmap: inflated obstacles on the current map, and the planner's entry points on it.

Unknown cells are passable at an extra cost (as move_base's ``allow_unknown``); cells closer to a
wall than the robot radius are not, and the cost decays away from walls so that paths keep clear
of them when there is room.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property

import numba as nb
import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from frontier_rl.core.navigation.astar import SearchScratch, astar_padded
from frontier_rl.core.navigation.config import NavigationConfig
from frontier_rl.core.navigation.distance import flood_known
from frontier_rl.core.navigation.group_costs import BlockGrid
from frontier_rl.core.navigation.inflation import InflationMemory, inflate
from frontier_rl.core.navigation.path_costs import cost_field
from frontier_rl.core.navigation.step_costs import inflation_table, step_costs
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import RobotConfig

_NO_COSTS = np.zeros(0)  # astar_padded works the step costs out itself

ESCAPE_RADIUS_M = 0.25
"""Around the robot, cells closer to a wall than the robot radius may be crossed within this
distance (m), if no closer to a wall than the robot already is: so it can leave a wall it ended up
against (move_base clears the robot's footprint for the same reason)."""

Departure = tuple[tuple[int, int], float]
"""A cell a path-cost search sets out from (row, col) and the way to it from the robot (m)."""
CostSearch = Callable[[tuple[int, int]], tuple[NDArray[np.float64], bool]]
"""Path costs (m) from a start cell, and whether the search covered all it could reach."""


@dataclass(frozen=True)
class Costmap:
    """Planning costs on one map, kept with a one-cell blocked border (so the compiled planner
    needs no bounds checks); the properties give the unpadded views.

    A cell's step cost factor follows from its clearance and state (:attr:`cost_padded`); the
    planner works it out for the cells it reaches, so that a costmap costs no sweep for it.

    Attributes:
        grid: the map.
        open_padded: traversable cells (not within the robot radius of a wall), padded.
        clearance_padded: distance (cells) from each cell centre to the nearest occupied cell
            centre, by a chamfer transform (exact or up to 8 % over), capped just above the
            inflation radius, padded.
        inflation_table: the inflation cost by clearance, in steps of 1/64 cell.
        inflation_radius: clearance (cells) from which a cell has no inflation cost.
        unknown_cost: extra cost factor of an unknown cell.
        scratch: the planner's scratch arrays.
        block_grids: by block edge (cells), the blocks searches on a large map have worked out
            so far (:mod:`~frontier_rl.core.navigation.group_costs`), kept for the next search.
    """

    grid: OccupancyGrid
    open_padded: NDArray[np.bool_] = field(repr=False)
    clearance_padded: NDArray[np.float64] = field(repr=False)
    inflation_table: NDArray[np.float64] = field(repr=False)
    inflation_radius: float
    unknown_cost: float
    scratch: SearchScratch = field(default_factory=SearchScratch, repr=False, compare=False)
    block_grids: dict[int, BlockGrid] = field(default_factory=dict, repr=False, compare=False)

    @classmethod
    def build(
        cls,
        grid: OccupancyGrid,
        robot: RobotConfig,
        config: NavigationConfig,
        scratch: SearchScratch | None = None,
        memory: InflationMemory | None = None,
    ) -> Costmap:
        """Inflate the obstacles of ``grid`` for a robot of ``robot.radius``; its searches use
        ``scratch`` (a new one by default: pass one to reuse it from map to map). With ``memory``
        (the last map's inflation), only what the map's changes can reach is inflated again."""
        res = grid.resolution
        lethal_below = (robot.radius + 0.5 * res) / res  # cell centre to wall surface, in cells
        inflation_radius = config.inflation_radius / res
        if memory is None:
            clearance_p, open_p = inflate(grid.data, lethal_below, inflation_radius)
        else:
            clearance_p, open_p = memory.inflate(grid, lethal_below, inflation_radius)
        table = inflation_table(lethal_below, inflation_radius, config.cost_scaling * res, config.inflation_cost)
        return cls(grid, open_p, clearance_p, table, inflation_radius, config.unknown_cost, scratch or SearchScratch())

    @cached_property
    def cost_padded(self) -> NDArray[np.float64]:
        """Step cost factor per cell, 1 + inflation and unknown penalties, padded (made on first use)."""
        return step_costs(
            self.grid.data, self.clearance_padded, self.inflation_table, self.inflation_radius, self.unknown_cost
        )

    @property
    def traversable(self) -> NDArray[np.bool_]:
        """Cells the robot centre may occupy (a view)."""
        return self.open_padded[1:-1, 1:-1]

    @property
    def penalty(self) -> NDArray[np.float64]:
        """Extra cost factor per cell (inflation + unknown), >= 0."""
        return self.cost_padded[1:-1, 1:-1] - 1.0

    @property
    def clearance(self) -> NDArray[np.float64]:
        """Distance (m) from each cell centre to the nearest occupied cell centre (chamfer, capped)."""
        return self.clearance_padded[1:-1, 1:-1] * self.grid.resolution

    def with_discs_blocked(
        self, centres: NDArray[np.float64], radius: float, backing_from: tuple[float, float] | None = None
    ) -> Costmap:
        """A copy in which every cell whose centre lies within ``radius`` (m) of one of ``centres``
        ((k, 2) world points, m) is blocked (and costed) like a wall: other robots, for planning
        around them. With ``backing_from`` (a robot's position, m), the cells next to it that lie
        farther from a centre than it does stay open, so that a robot in contact may back away."""
        open_p = self.open_padded.copy()
        clear_p = self.clearance_padded.copy()
        g = self.grid
        for x, y in centres:
            rows, cols, cx, cy = g.centres_near(float(x), float(y), radius)
            if not (len(cx) and len(cy)):
                continue
            gap = np.hypot(cx[None, :] - x, cy[:, None] - y)
            inside = gap <= radius
            if backing_from is not None:
                bx, by = backing_from
                beside = np.hypot(cx[None, :] - bx, cy[:, None] - by) <= 1.5 * g.resolution
                inside &= ~(beside & (gap > math.hypot(bx - x, by - y)))
            padded = (slice(rows.start + 1, rows.stop + 1), slice(cols.start + 1, cols.stop + 1))
            open_p[padded] &= ~inside
            clear_p[padded][inside] = 0.0  # so the start's escape zone stays shut
        return Costmap(g, open_p, clear_p, self.inflation_table, self.inflation_radius, self.unknown_cost, self.scratch)

    def with_cells_blocked(self, blocked: NDArray[np.bool_]) -> Costmap:
        """A copy in which the cells set in ``blocked`` (the map's shape) are blocked like a wall."""
        open_p = self.open_padded.copy()
        clear_p = self.clearance_padded.copy()
        open_p[1:-1, 1:-1] &= ~blocked
        clear_p[1:-1, 1:-1][blocked] = 0.0  # so the start's escape zone stays shut
        return Costmap(
            self.grid, open_p, clear_p, self.inflation_table, self.inflation_radius, self.unknown_cost, self.scratch
        )

    def with_felt_walls(self, felt: NDArray[np.bool_], radius: float) -> Costmap:
        """A copy that keeps the robot's centre ``radius`` (m) off the walls it touched (``felt``,
        the map's shape): the collision check on the true map found them there, and refuses every
        cell closer (:func:`felt_keep_out`), which the start's escape zone would otherwise let a
        path cross where the map draws a wall a cell nearer than it is. Itself when none was felt."""
        if not felt.any():
            return self
        keep_out = felt_keep_out(radius, self.grid.resolution)
        n = keep_out.shape[0] // 2
        rows, cols = np.nonzero(felt)
        # dilated within the touched walls' box and its margin only: the same cells, and a few of a
        # large map's instead of all of them at every costmap (10 ms on 1,000 x 1,000 cells)
        box = (slice(max(int(rows.min()) - n, 0), int(rows.max()) + n + 1),
               slice(max(int(cols.min()) - n, 0), int(cols.max()) + n + 1))  # fmt: skip
        blocked = np.zeros_like(felt)
        blocked[box] = ndimage.binary_dilation(felt[box], keep_out)
        return self.with_cells_blocked(blocked)

    def with_cells_opened(self, opened: NDArray[np.bool_]) -> Costmap:
        """A copy in which the cells set in ``opened`` (the map's shape) are traversable."""
        open_p = self.open_padded.copy()
        open_p[1:-1, 1:-1] |= opened
        return Costmap(
            self.grid,
            open_p,
            self.clearance_padded,
            self.inflation_table,
            self.inflation_radius,
            self.unknown_cost,
            self.scratch,
        )

    def reachable_known(self, start: tuple[int, int], escape_radius: float = ESCAPE_RADIUS_M) -> NDArray[np.bool_]:
        """Known-free cells the robot at ``start`` (row, col) can drive to: traversable cells
        connected (8-way) to it, through the cells within ``escape_radius`` (m) it may cross to
        leave a wall as :meth:`plan` does; from the nearest traversable known-free cell within
        0.5 m when the start itself is not known free."""
        r, c = start
        if not self.grid.in_bounds(r, c):
            return np.zeros(self.grid.shape, np.bool_)
        escape = escape_radius / self.grid.resolution
        reach = flood_known(self.open_padded, self.grid.data, r, c, self.clearance_padded, escape)
        if not reach[r, c]:
            nearest = self.departure_near(start)
            if nearest is not None:
                reach = flood_known(self.open_padded, self.grid.data, *nearest)
        return reach

    def departure_near(self, start: tuple[int, int]) -> tuple[int, int] | None:
        """The cell a robot at ``start`` (row, col) sets out from when its map does not have
        ``start`` free (a wall cell under the robot: a speck the LiDAR drew there, or a gap only
        the narrow-passage recovery's costmap opened, where a leg ended): the nearest traversable
        known-free cell within 0.5 m; None if there is none. :meth:`reachable_known` and
        :meth:`plan` both set out from it, so that every cell one calls reachable the other plans to."""
        mask = self.traversable & (self.grid.data == CellState.FREE)
        return nearest_cell(mask, start, max_radius=int(round(0.5 / self.grid.resolution)))

    def set_out(self, start: tuple[int, int], escape_radius: float = ESCAPE_RADIUS_M) -> list[Departure]:
        """Where path-cost searches for a robot at ``start`` (row, col) set out, each with the way
        there (m): ``start`` itself when it is traversable; else the nearest traversable cell of
        each group of them the robot gets to across the cells within ``escape_radius`` (m) it may
        cross, as :meth:`plan` does (no closer to a wall than ``start``, never occupied): one way
        out beside a wall, two from a gap it stands in; else, on a cell the map does not have
        free, :meth:`departure_near`; ``start`` (and no path) when there is none.

        The cost searches cannot cross those cells, so from a robot that ended up too close to a
        wall every frontier had cost "no path", though the planner had a path to each."""
        r, c = start
        if not self.grid.in_bounds(r, c) or self.traversable[r, c]:
            return [(start, 0.0)]
        escape = escape_radius / self.grid.resolution
        k = math.ceil(escape) + 1
        rows, cols = self.grid.shape
        r0, r1 = max(r - k, 0), min(r + k + 1, rows)
        c0, c1 = max(c - k, 0), min(c + k + 1, cols)
        window = (slice(r0, r1), slice(c0, c1))
        clearance = self.clearance_padded[1:-1, 1:-1][window]
        dr, dc = np.ogrid[r0 - r : r1 - r, c0 - c : c1 - c]
        floor_clear = max(float(clearance[r - r0, c - c0]), 0.5)  # >= 0.5: never an occupied cell
        exits = self.traversable[window]
        crossable = exits | ((dr * dr + dc * dc <= escape * escape) & (clearance >= floor_clear))
        crossable[r - r0, c - c0] = True
        eight = np.ones((3, 3), np.bool_)
        parts, _ = ndimage.label(crossable, structure=eight)
        groups, n_groups = ndimage.label(exits & (parts == parts[r - r0, c - c0]), structure=eight)
        if n_groups == 0:
            near = self.departure_near(start) if self.grid.data[r, c] != CellState.FREE else None
            cells = [] if near is None else [near]
        else:
            d2 = np.broadcast_to(dr * dr + dc * dc, groups.shape)
            first = ndimage.minimum_position(d2, groups, np.arange(1, n_groups + 1))
            cells = [(r0 + int(i), c0 + int(j)) for i, j in first]
        if not cells:
            return [(start, 0.0)]
        return [(cell, math.hypot(cell[0] - r, cell[1] - c) * self.grid.resolution) for cell in cells]

    def costs_from(self, start: tuple[int, int], search: CostSearch) -> tuple[NDArray[np.float64], bool]:
        """``search``'s costs (m) for a robot at ``start`` (row, col): the least over the places it
        sets out from (:meth:`set_out`), each with the way there; and whether every search covered
        all it could reach (``search`` returns both for a start cell)."""
        best: NDArray[np.float64] | None = None
        exhausted = True
        for cell, lead in self.set_out(start):
            costs, covered = search(cell)
            best = costs + lead if best is None else np.minimum(best, costs + lead)
            exhausted &= covered
        assert best is not None  # set_out gives at least one place
        return best, exhausted

    def cost_to_go(self, start: tuple[int, int]) -> NDArray[np.float64]:
        """Planner path cost (m, weighted by the cell costs) from ``start`` (row, col) to every
        traversable cell; inf where there is no path."""
        if not self.grid.in_bounds(*start):
            return np.full(self.grid.shape, np.inf)
        return cost_field(self, start)

    def plan(
        self, start: tuple[int, int], goal: tuple[int, int], escape_radius: float = ESCAPE_RADIUS_M
    ) -> NDArray[np.int64]:
        """A* path (cells, (n, 2) rows and columns) from ``start`` to ``goal``; empty if none.

        Cells within ``escape_radius`` (m) of the start may be crossed even if inflated (not if
        occupied), so that a robot that ended up too close to a wall can still leave. A robot on
        a cell its map does not have free (a wall cell under it), from which no path leads, sets
        out from :meth:`departure_near`, as :meth:`reachable_known` does (the path starts there).
        """
        if not (self.grid.in_bounds(*start) and self.grid.in_bounds(*goal)):
            return np.zeros((0, 2), np.int64)
        escape = escape_radius / self.grid.resolution
        cells = self._astar(start, goal, escape)
        if len(cells) == 0 and self.grid.data[start] != CellState.FREE:
            nearest = self.departure_near(start)
            if nearest is not None:
                cells = self._astar(nearest, goal, escape)
        return cells

    def _astar(self, start: tuple[int, int], goal: tuple[int, int], escape: float) -> NDArray[np.int64]:
        """:meth:`plan`'s search from ``start``, ``escape`` in cells."""
        scratch, stamp = self.scratch.next_search(self.open_padded.size)
        costs = (self.grid.data, self.inflation_table, self.inflation_radius, self.unknown_cost)
        return astar_padded(
            self.open_padded,
            self.clearance_padded,
            costs,
            _NO_COSTS,
            start[0],
            start[1],
            goal[0],
            goal[1],
            escape,
            scratch,
            stamp,
        )


def felt_keep_out(radius: float, resolution: float) -> NDArray[np.bool_]:
    """The cells round a wall the robot touched where the planner keeps its centre out: a square
    mask (2n + 1 cells a side) of the cell centres closer than ``radius`` (m) to the middle one's,
    on cells of ``resolution`` (m)."""
    reach = radius / resolution
    n = int(math.ceil(reach))
    dr, dc = np.mgrid[-n : n + 1, -n : n + 1]
    return np.asarray(dr**2 + dc**2 < reach**2)


def nearest_cell(mask: NDArray[np.bool_], target: tuple[int, int], max_radius: int) -> tuple[int, int] | None:
    """The True cell of ``mask`` nearest to ``target`` (row, col), searched in growing windows
    up to ``max_radius`` cells; None if there is none that close."""
    row, col = _nearest_cell(np.asarray(mask, np.bool_), int(target[0]), int(target[1]), int(max_radius))
    return None if row < 0 else (int(row), int(col))


@nb.njit(cache=True, inline="always")
def _slice_stop(stop: int, size: int) -> int:
    """Where a slice ``[...:stop]`` of an axis of ``size`` ends, as Python counts it."""
    if stop < 0:
        stop += size
    return min(max(stop, 0), size)


@nb.njit(cache=True)
def _nearest_cell(mask: NDArray[np.bool_], r: int, c: int, max_radius: int) -> tuple[int, int]:
    """:func:`nearest_cell`, (-1, -1) for None. Windows of radius 2, 4, 8, ... (capped): the first
    with a True cell within the radius gives the nearest, ties to the first in row-major order."""
    rows, cols = mask.shape
    radius = min(2, max_radius)
    while True:
        r0, c0 = min(max(r - radius, 0), rows), min(max(c - radius, 0), cols)
        r1, c1 = _slice_stop(r + radius + 1, rows), _slice_stop(c + radius + 1, cols)
        best, best_row, best_col = -1, -1, -1
        for rr in range(r0, r1):
            for cc in range(c0, c1):
                if mask[rr, cc]:
                    d2 = (rr - r) ** 2 + (cc - c) ** 2
                    if best < 0 or d2 < best:
                        best, best_row, best_col = d2, rr, cc
        if best >= 0 and best <= radius * radius:
            return best_row, best_col
        if radius >= max_radius:
            return -1, -1
        radius = min(radius * 2, max_radius)
