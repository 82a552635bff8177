"""The settings of a simulated episode: the robot, its sensor, mapper and navigation, and the
episode's limits."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from frontier_rl.core.mapping.mapper import MapperConfig
from frontier_rl.core.navigation.config import NavigationConfig
from frontier_rl.core.sensing.lidar import LidarConfig
from frontier_rl.core.world.robot import RobotConfig
from frontier_rl.core.world.worlds import World, make_world
from frontier_rl.errors import ConfigError

SPECK_CELLS = 4
"""The thesis's drop size (cells): frontier clusters this small, and as little unseen space beside
a frontier, leave nothing to explore (but see :data:`UNSEEN_ROOM_M2`)."""
UNSEEN_ROOM_M2 = 0.5
"""More unseen free space than this (m²) behind a frontier left, however small the frontier, is a
room, not a speck: the episode ends ``unreachable``. 0.5 m² is 0.7 m x 0.7 m, room for a person.
On 0.1 m cells a slot of 3 cells (a speck) led to 2.5 m² never seen, an episode that would have
ended ``explored``; the most found behind a speck in 94 ``nearest`` episodes of the generators and
the catalogue's real maps that ended ``explored`` was 0.14 m² (under furniture in ``aws_small_house``)."""
MAX_FRONTIER_DROP_CELLS = 1_000_000
"""Largest ``min_frontier_cells`` (and the ROS node's ``~min_cluster_size``): a drop of a million
cells is more than any frontier of a map file holds (2**63 overflowed the frontier kernels' integers)."""

DROP_CELL_M = 0.05
"""The cell size (m) that drop sizes in cells are counted in: the thesis's map's."""


def drop_cells_at(cells: int, resolution: float) -> int:
    """A drop size of ``cells`` cells of :data:`DROP_CELL_M` on a map of ``resolution`` m cells: as
    many cells on finer cells, where a speck of LiDAR noise still takes a few cells, and on coarser
    cells no more than fit in the same length (4 cells of 0.05 m, 0.2 m, are 2 of 0.1 m), so that an
    opening drawn on coarse cells is not dropped as a speck. The ratio gets a relative margin of
    1e-6: a ROS map's resolution is a float32, 0.05 m read back as 0.0500000007 m."""
    return min(cells, math.floor(cells * DROP_CELL_M / resolution * (1.0 + 1e-6)))


@dataclass(frozen=True)
class SimConfig:
    """Everything that defines a simulated episode besides the world and the seed.

    Attributes:
        robot: robot footprint and speed limits.
        lidar: the range sensor.
        mapper: the log-odds map update.
        navigation: costmap, planner and controller.
        min_frontier_cells: frontier clusters of this many cells or fewer are not candidates (the
            robot does not go to them), counted in cells of 0.05 m: on coarser maps, clusters no
            longer than that many such cells (:meth:`drop_cells`); an episode that ends with one
            beside more unseen free space than :meth:`speck_cells` ends ``unreachable``, not
            ``explored``.
        max_sim_time: sim-time cap of an episode (s); the episode is truncated there. ``None``
            (the default) scales it with the world: see :meth:`time_cap`.
        sensor_noise: whether LiDAR ranges get noise.
        time_per_area: the default cap allows this much sim time per m² of explorable space (s/m²):
            about three times what the fastest method takes on the harder survey's 50-100 m floors
            (7 s/m²), so that a policy that meets the cap wanders.
        min_time_cap: ... and never less than this (s).
        frontier_segment_length: frontier clusters longer than this (m) are split into segments,
            each a candidate with its own goal (about the mapping range: one view resolves one).
        frontier_goal_reach: a frontier's goal is a reachable cell that sees it from at most this
            far (m), and never farther than :attr:`mapping_range`; a frontier with none is not a
            candidate.
    """

    robot: RobotConfig = field(default_factory=RobotConfig)
    lidar: LidarConfig = field(default_factory=LidarConfig)
    mapper: MapperConfig = field(default_factory=MapperConfig)
    navigation: NavigationConfig = field(default_factory=NavigationConfig)
    min_frontier_cells: int = 4
    max_sim_time: float | None = None
    sensor_noise: bool = True
    time_per_area: float = 25.0
    min_time_cap: float = 3600.0
    frontier_segment_length: float = 3.0
    frontier_goal_reach: float = 3.0

    def __post_init__(self) -> None:
        if not 0 <= self.min_frontier_cells <= MAX_FRONTIER_DROP_CELLS:
            raise ConfigError(
                f"min_frontier_cells must be 0 to {MAX_FRONTIER_DROP_CELLS:,}, got {self.min_frontier_cells!r}"
            )
        if self.max_sim_time is not None and not (self.max_sim_time > 0 and math.isfinite(self.max_sim_time)):
            raise ConfigError(f"max_sim_time must be a positive number of seconds, got {self.max_sim_time!r}")
        for name in ("time_per_area", "min_time_cap", "frontier_segment_length", "frontier_goal_reach"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ConfigError(f"{name} must be a positive number, got {value!r}")

    def drop_cells(self, resolution: float) -> int:
        """The frontier clusters of at most this many cells are not candidates on a map of
        ``resolution`` m cells: ``min_frontier_cells``, counted in cells of 0.05 m on coarser maps
        (:func:`drop_cells_at`)."""
        return drop_cells_at(self.min_frontier_cells, resolution)

    def speck_cells(self, resolution: float) -> int:
        """The most cells a frontier cluster, or the unseen free space beside a frontier, may have
        and still be a speck when an episode ends on a map of ``resolution`` m cells
        (:func:`~frontier_rl.core.sim.episode_log.completion_reason`): :meth:`drop_cells`, but never
        more than the thesis's 4 cells of 0.05 m. A robot told to skip larger clusters
        (``min_frontier_cells`` 40: a 2 m doorway) may end with them, but not as explored."""
        return drop_cells_at(min(self.min_frontier_cells, SPECK_CELLS), resolution)

    @property
    def mapping_range(self) -> float:
        """The range (m) within which a scan updates the map: the LiDAR's, cropped at the mapper's."""
        return min(self.lidar.max_range, self.mapper.usable_range)

    def fit_world(self, world: World) -> World:
        """``world`` with its explorable space computed for this robot's radius and mapping range
        (the same world when it already is)."""
        if (world.robot_radius, world.sensor_range) == (self.robot.radius, self.mapping_range):
            return world
        return make_world(
            world.grid, world.name, start=world.start, robot_radius=self.robot.radius, sensor_range=self.mapping_range
        )

    def time_cap(self, world: World) -> float:
        """The sim-time cap (s) of an episode on ``world``: ``max_sim_time`` when set, else
        ``time_per_area`` s per m² of its explorable space, at least ``min_time_cap`` (an office
        of 12.5 m x 12.5 m gets 3,600 s; a floor with 1,000 m² to explore 25,000 s)."""
        if self.max_sim_time is not None:
            return self.max_sim_time
        area = world.explorable_count * world.grid.resolution**2
        return max(self.min_time_cap, self.time_per_area * area)
