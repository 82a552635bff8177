"""Where one robot can go on its own map: the candidates of a decision, the paths a leg replans,
and the map checks along them. The :class:`~frontier_rl.core.sim.simulator.ExplorationSimulator`
keeps one per episode (it moves the robot; this decides where it may move)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.frontiers.blacklist import Blacklist
from frontier_rl.core.frontiers.fringe import count_fringe
from frontier_rl.core.mapping.mapper import LogOddsMapper
from frontier_rl.core.navigation.astar import SearchScratch
from frontier_rl.core.navigation.costmap import felt_keep_out
from frontier_rl.core.navigation.follower import footprint_offsets
from frontier_rl.core.navigation.inflation import InflationMemory
from frontier_rl.core.navigation.thin_walls import Recovery, recovery_robot
from frontier_rl.core.sim.candidates import Candidates, find_candidates
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode_log import EpisodeLog
from frontier_rl.core.sim.look_state import LookState
from frontier_rl.core.sim.paths import map_blocks_path, recovery_blocks_path, replan_path, replan_round_teammates
from frontier_rl.core.sim.teammates import Teammates
from frontier_rl.core.sim.trail import mark_path
from frontier_rl.core.world.grid import OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.core.world.worlds import World

CANDIDATE_MAP_MARGIN = 2
"""Unknown cells (around the seen area) of the map the candidates are found on."""


class Navigator:
    """The robot's map as its navigation sees it, for one episode.

    Args:
        world: the world (its grid is the frame of the map and of the paths' cells).
        config: the settings.
        mapper: the robot's map; blacklist: its failed goals; robots: the other robots, as obstacles.
        scratch, inflation: the planner's scratch and the last costmap's inflation, kept from map
            to map (and from episode to episode: they belong to the simulator).
        log: the episode's record, whose poses make the robot's trail (:meth:`trail`).
    """

    def __init__(
        self,
        world: World,
        config: SimConfig,
        mapper: LogOddsMapper,
        blacklist: Blacklist,
        robots: Teammates,
        scratch: SearchScratch,
        inflation: InflationMemory,
        log: EpisodeLog,
    ) -> None:
        self._world, self._config, self._mapper, self._robots = world, config, mapper, robots
        self._log = log
        self._trail = np.zeros(world.grid.shape, np.bool_)
        self._trail_from = 0  # the first logged pose the trail has not taken in
        self.blacklist = blacklist
        self._scratch, self._inflation = scratch, inflation
        res = world.grid.resolution
        self._footprints = {
            level: footprint_offsets(recovery_robot(config.robot, res, level).radius, res) for level in Recovery
        }
        self._keep_out = felt_keep_out(config.robot.radius, res)
        self._cached: list[Candidates] | None = None  # see _levels
        self._looks: Candidates | None = None  # the last looks of the cached levels, once asked for
        self.look_state = LookState()
        """Which last looks the robot still takes (:meth:`looked` tells it how each went)."""
        self._gave_way_on: tuple[float, float] | None = None  # the goal of a leg that gave way, see give_way

    def trail(self) -> NDArray[np.bool_]:
        """The cells the robot's centre has crossed (the world's shape; :mod:`~frontier_rl.core.sim.trail`),
        brought up to date from the poses logged since the last call: only the recovery needs it."""
        count = self._log.pose_count
        if count > self._trail_from:
            mark_path(self._trail, self._world.grid, self._log.poses_since(max(self._trail_from - 1, 0))[:, :2])
            self._trail_from = count
        return self._trail

    def forget(self) -> None:
        """The map or the blacklist changed: find the candidates afresh."""
        self._cached = self._looks = None

    def candidates(self, pose: Pose) -> Candidates:
        """The current map, its costmap and the reachable, non-blacklisted frontiers for a robot at
        ``pose`` (cached until :meth:`forget`; see :func:`~frontier_rl.core.sim.candidates.find_candidates`).
        When the normal costmap leaves none, those of the narrow-passage recovery's levels in turn
        (the map with its walls a cell thinner, as range noise made them a cell thicker, for a robot
        half a cell and then a cell slimmer: :class:`~frontier_rl.core.navigation.thin_walls.Recovery`)
        are the candidates, the first level that has any; when none has any, the last looks
        (:func:`~frontier_rl.core.sim.looks.last_looks`, then
        :func:`~frontier_rl.core.sim.looks.spent_looks`) from the first level that has one."""
        levels = self._levels(pose)
        if len(levels[-1].frontiers):
            return levels[-1]
        if self._looks is None:  # computed once per map: a look costs rays from thousands of viewpoints
            self._looks = self.look_state.looks(levels, pose, self._config, self.blacklist)
        return self._looks

    def _levels(self, pose: Pose) -> list[Candidates]:
        """The candidates of the normal costmap and then of each narrow-passage recovery level in
        turn, up to the first that has a frontier (cached until :meth:`forget`): without the last
        looks, which only a decision needs (a replanning leg needs the costmaps)."""
        if self._cached is None:
            grid = self._mapper.occupancy_grid(margin=CANDIDATE_MAP_MARGIN)
            cand = self.candidates_on(grid, Recovery.NONE, pose)
            if len(cand.frontiers) == 0 and self._gave_way_on is not None:  # their way again, as a failure
                self.blacklist.fail(*self._gave_way_on, self._mapper.state)
                self._gave_way_on = None
                cand = self.candidates_on(grid, Recovery.NONE, pose)
            levels = [cand]
            for level in (Recovery.HALF_CELL, Recovery.WHOLE_CELL):
                if len(levels[-1].frontiers):
                    break
                levels.append(self.candidates_on(grid, level, pose))
            self._cached = levels
        return self._cached

    def looked(self, revealed_m2: float, blind: bool = False) -> None:
        """A look at the small clusters mapped ``revealed_m2`` of floor (m², cells newly known free;
        ``blind``: a blind look): see :meth:`LookState.looked <frontier_rl.core.sim.look_state.LookState.looked>`."""
        self.look_state.looked(revealed_m2, blind)
        self.forget()

    def decision_candidates(self, pose: Pose) -> Candidates:
        """The candidates of a decision: after :meth:`give_way`, of this decision only."""
        cand = self.candidates(pose)
        if self._gave_way_on is not None:
            self._gave_way_on = None
            self.forget()
        return cand

    def candidates_on(self, grid: OccupancyGrid, recovery: Recovery, pose: Pose) -> Candidates:
        """The candidates on ``grid`` (a crop of the robot's map) with the normal costmap or a
        narrow-passage ``recovery``'s."""
        top, left = self._world.grid.world_to_cell(*grid.cell_to_world(0, 0))
        crop = (slice(top, top + grid.height), slice(left, left + grid.width))
        felt = self._mapper.felt[crop]
        trail = None if recovery is Recovery.NONE else self.trail()[crop]
        mates = self._robots
        walls = None if self._gave_way_on is None else (mates.in_contact((pose.x, pose.y)), mates.radius)
        state = self._mapper.state
        return find_candidates(
            grid,
            pose,
            self._config,
            self.blacklist,
            state,
            self._scratch,
            recovery,
            felt,
            self._inflation,
            walls,
            trail,
        )

    def replan(self, goal: tuple[float, float], recovery: Recovery, pose: Pose) -> NDArray[np.float64] | None:
        """A new path from ``pose`` to ``goal`` (m) on the current map, on the costmap the leg was
        planned on (``recovery``): a leg through a passage opened by the narrow-passage recovery
        keeps to it (on the normal costmap the robot inside the passage could not move)."""
        return replan_path(self._replan_candidates(recovery, pose), pose, goal, self._robots, self._config)

    def replan_round_teammates(
        self, goal: tuple[float, float], recovery: Recovery, pose: Pose
    ) -> NDArray[np.float64] | None:
        """:meth:`replan`'s path, but only one that keeps out of the teammates in contact with the robot."""
        return replan_round_teammates(self._replan_candidates(recovery, pose), pose, goal, self._robots)

    def _replan_candidates(self, recovery: Recovery, pose: Pose) -> Candidates:
        """The candidates (their costmap) a replan of a leg planned on ``recovery``'s costmap uses."""
        levels = self._levels(pose)
        cand = levels[-1] if len(levels[-1].frontiers) else levels[0]
        if recovery is not Recovery.NONE and cand.recovery is not recovery:
            cand = self.candidates_on(cand.grid, recovery, pose)
        return cand

    def give_way(self, goal: tuple[float, float]) -> None:
        """A teammate blocks the leg to ``goal`` (m): the next decision sees those in contact as walls."""
        self._gave_way_on = goal
        self.forget()

    def path_blocked(self, path_cells: NDArray[np.int64], first: int, recovery: Recovery) -> bool:
        """Whether the robot's map puts a wall on the path (world cells) from index ``first`` on;
        for a leg of the narrow-passage ``recovery``, the map with its walls thinned around the path
        and the slimmer robot, open along its trail, as it was planned on."""
        state, cells = self._mapper.state, path_cells[first:]
        if recovery is Recovery.NONE:
            return map_blocks_path(state, cells, self._footprints[recovery])
        return recovery_blocks_path(
            state, cells, self._footprints[recovery], self._mapper.felt, self.trail(), self._keep_out
        )

    def frontier_alive(self, cells: NDArray[np.int64]) -> bool:
        """Whether more than the drop size of a frontier's cells (world cells) are still fringe cells."""
        drop = self._config.drop_cells(self._world.grid.resolution)
        return count_fringe(self._mapper.state, cells[:, 0], cells[:, 1]) > drop

    def blacklist_goal(
        self, goal: tuple[float, float], frontier_cells: NDArray[np.int64] | None, *, reached: bool = False
    ) -> None:
        """A leg to ``goal`` (m) for the frontier of ``frontier_cells`` (world cells; None for a
        point goal) failed (``reached``: got there, and its frontier stayed): blacklist it, and find
        the candidates afresh."""
        cells = None if frontier_cells is None else self._world.grid.cells_to_world(frontier_cells)
        self.blacklist.fail(*goal, self._mapper.state, reached=reached, frontier=cells)
        self.forget()
