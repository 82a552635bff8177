"""The full-knowledge ``oracle``: drives a coverage tour planned on the true map.

A near-limit reference for exploration time, not an exploration method: it knows the map before it
sees it. At the start of an episode it plans a :class:`~frontier_rl.core.navigation.coverage_tour.CoverageTour`
and then drives it with the same navigator and sensor as every other method, passing over the
viewpoints whose cells the robot's map already holds. The episode ends under the same rule as for
everyone (no reachable frontier left): when the tour is done and frontiers remain, it takes the
nearest.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.frontiers.ranking import nearest_cost, rank
from frontier_rl.core.navigation.costmap import Costmap, nearest_cell
from frontier_rl.core.navigation.coverage_tour import CoverageTour, plan_coverage_tour
from frontier_rl.core.navigation.path_costs import cost_field, descend
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import DecisionContext, Ranking
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.worlds import World
from frontier_rl.errors import ConfigError

_MAX_LEGS = 200  # legs toward one viewpoint before it is given up: a guard, never reached in practice


@dataclass
class OracleTour:
    """Full-knowledge coverage tour (a reference method, allowed to see the true map).

    The navigator only drives to cells the robot's own map shows free, so a viewpoint in unmapped
    space is approached in legs of at most ``leg_m``: each goal is the farthest point of the true
    shortest path to the viewpoint up to which the robot's map is free. Short legs also let the
    policy notice early that a viewpoint's cells have been mapped on the way. A viewpoint is
    passed once at most ``leftover_cells`` of its target cells are unmapped, once the robot is
    within ``reached_m`` of it, or when a leg toward it would not move the robot or did not.

    Args:
        spacing_m, min_gain_cells, detour_m, margin_cells, graze_cells: the tour's planning (see
            :func:`~frontier_rl.core.navigation.coverage_tour.plan_coverage_tour`).
        leftover_cells: a viewpoint is passed once at most this many of its target cells are unmapped.
        reached_m: a viewpoint is passed once the robot is this close to it (m).
        leg_m: longest leg toward a viewpoint (m).
        name: the policy's name.
    """

    spacing_m: float = 0.5
    min_gain_cells: int = 10
    detour_m: float = 3.0
    margin_cells: float = 1.0
    graze_cells: int = 3
    leftover_cells: int = 4
    reached_m: float = 0.2
    leg_m: float = 1.0
    name: str = "oracle"
    _tour: CoverageTour | None = field(default=None, init=False, repr=False)
    _costmap: Costmap | None = field(default=None, init=False, repr=False)
    _min_leg: float = field(default=0.0, init=False, repr=False)
    _next: int = field(default=0, init=False, repr=False)
    _legs: int = field(default=0, init=False, repr=False)
    _leg_from: tuple[float, float] = field(default=(0.0, 0.0), init=False, repr=False)
    _field: tuple[int, NDArray[np.float64], float] | None = field(default=None, init=False, repr=False)

    def __post_init__(self) -> None:
        for name in ("spacing_m", "leg_m"):
            if not getattr(self, name) > 0:
                raise ConfigError(f"oracle {name} must be positive, got {getattr(self, name)!r}")
        for name in ("reached_m", "leftover_cells", "detour_m", "margin_cells", "graze_cells"):
            if not getattr(self, name) >= 0:
                raise ConfigError(f"oracle {name} must be >= 0, got {getattr(self, name)!r}")

    @property
    def tour(self) -> CoverageTour | None:
        """The tour of the current episode (None before :meth:`begin_episode`)."""
        return self._tour

    def begin_episode(self, world: World, config: SimConfig) -> None:
        """Plan the coverage tour of ``world`` from its start."""
        self._tour = plan_coverage_tour(
            world,
            config.robot,
            config.navigation,
            config.lidar,
            config.mapper.usable_range,
            self.spacing_m,
            self.min_gain_cells,
            self.detour_m,
            self.margin_cells,
            self.graze_cells,
        )
        self._costmap = Costmap.build(world.grid, config.robot, config.navigation)
        self._min_leg = config.navigation.goal_tolerance
        self._next = 0
        self._legs = 0
        self._field = None

    def rank(self, context: DecisionContext, rng: np.random.Generator) -> Ranking:
        """A point goal toward the next viewpoint of the tour still worth visiting; after the
        tour, the nearest frontier."""
        tour = self._tour
        if tour is None:
            raise ConfigError("the oracle needs the true map: run it through run_episode")
        pose = context.pose
        while self._next < len(tour):
            index = self._next
            x, y = tour.viewpoints[index]
            targets = tour.targets[index]
            unknown = np.count_nonzero(self._map_state(context.grid, targets) == CellState.UNKNOWN)
            stalled = (
                self._legs > 0 and math.hypot(pose.x - self._leg_from[0], pose.y - self._leg_from[1]) < self._min_leg
            )
            if (
                unknown > self.leftover_cells
                and math.hypot(x - pose.x, y - pose.y) > self.reached_m
                and not stalled
                and self._legs < _MAX_LEGS
            ):
                goal = self._waypoint(index, context)
                if goal is not None and math.hypot(goal[0] - pose.x, goal[1] - pose.y) > self._min_leg:
                    self._legs += 1
                    self._leg_from = (pose.x, pose.y)
                    return Ranking(np.zeros(0, np.int64), goal=goal)
            self._next += 1
            self._legs = 0
        return Ranking(rank(nearest_cost(context.frontiers)))

    def _waypoint(self, index: int, context: DecisionContext) -> tuple[float, float] | None:
        """The farthest point, at most ``leg_m`` along the true shortest path from the robot to
        viewpoint ``index``, up to which the robot's map is free; None if there is no path."""
        assert self._tour is not None and self._costmap is not None
        world = self._costmap.grid
        cell = world.world_to_cell(context.pose.x, context.pose.y)
        if not (world.in_bounds(*cell) and self._costmap.traversable[cell]):  # e.g. the robot grazes a wall
            near = nearest_cell(self._costmap.traversable, cell, max_radius=int(round(0.5 / world.resolution)))
            if near is None:
                return None
            cell = near
        # The search from the viewpoint stops at the robot; its costs stay exact up to there, so
        # they serve as long as the robot is no farther from the viewpoint.
        if self._field is None or self._field[0] != index or not self._field[1][cell] <= self._field[2]:
            row, col = self._tour.cells[index]
            cost = cost_field(self._costmap, (int(row), int(col)), until=cell)
            self._field = (index, cost, float(cost[cell]))
        path = descend(self._field[1], cell)
        if path.shape[0] == 0:
            return None
        free = self._map_state(context.grid, path) == CellState.FREE
        end = path.shape[0] if free.all() else int(np.argmin(free))
        along = np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(path, axis=0).T)))) * world.resolution
        end = min(end, int(np.searchsorted(along, self.leg_m, side="right")))
        if context.costmap is not None:  # the goal on a cell the robot's own planner lets it stand on
            fits = self._map_state(context.grid, path[:end], context.costmap.traversable) == 1
            end = int(np.flatnonzero(fits)[-1]) + 1 if fits.any() else 0
        if end == 0:
            return None
        return world.cell_to_world(*path[end - 1])

    def _map_state(
        self, grid: OccupancyGrid, cells: NDArray[np.int64], layer: NDArray[np.generic] | None = None
    ) -> NDArray[np.int8]:
        """The robot's map ``grid`` (cropped to the seen area, with its own origin), or ``layer``
        (an array of its shape), at the true world's cells ``cells`` (row, col); UNKNOWN (-1)
        outside it."""
        assert self._costmap is not None
        row0, col0 = grid.offset_in(self._costmap.grid)
        rows, cols = cells[:, 0] - row0, cells[:, 1] - col0
        inside = (rows >= 0) & (rows < grid.height) & (cols >= 0) & (cols < grid.width)
        state = np.full(cells.shape[0], CellState.UNKNOWN, np.int8)
        state[inside] = (grid.data if layer is None else layer)[rows[inside], cols[inside]]
        return state
