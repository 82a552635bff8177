"""Log-odds occupancy mapping from LiDAR scans, like Gmapping's output grid.

The mapper keeps a log-odds array over the whole world extent, but a map *exported* from it covers
only the bounding box of the cells seen so far: it starts around the robot and grows as the robot
sees more, as a SLAM map does. Poses are taken as known (no localisation error).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.mapping.log_odds import (
    HIT,
    MAX_LOOKS,
    LogOddsRule,
    apply_pending,
    cast_and_mark,
    drop_marks,
    mark_beams,
)
from frontier_rl.core.mapping.map_merge import merge_window
from frontier_rl.core.sensing.lidar import MAX_BEAMS, Lidar, Scan
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose, wrap_angle
from frontier_rl.errors import ConfigError


@dataclass(frozen=True)
class MapperConfig:
    """Log-odds update rule.

    Attributes:
        hit: log-odds added to the cell a beam ends in.
        miss: log-odds added to each cell a beam passes through (below ``free_below``: one pass maps
            a cell free, or the first scan would map nothing free and an episode end at once).
        clamp_min: lower bound of a cell's log-odds.
        clamp_max: upper bound of a cell's log-odds.
        occupied_above: a cell is OCCUPIED once its log-odds exceed this.
        free_below: a cell is FREE once its log-odds drop below this. In between, a cell that
            has been classified keeps its class, and one never classified stays UNKNOWN: like a
            Gmapping map, a seen cell never turns unknown again.
        usable_range: beams are cropped here for mapping (m): Gmapping's ``maxUrange``.
        linear_update: a scan is processed after the robot moved this far (m) since the last one.
        angular_update: ... or turned this much (rad) ...
        temporal_update: ... or this much time passed (s); <= 0 disables the time trigger.

    The defaults are slam_gmapping's occupancy rule: a cell is occupied when more than a quarter of
    the scans that reached it ended in it (``occ_thresh`` 0.25), i.e. 3 x hits > passes. In
    log-odds a hit adds 0.75, a pass takes 0.25 and the class follows the sign (thresholds
    +-0.01), within the clamps. ``configs/mapper_hysteresis.yaml`` is the rule used before
    2026-11-26 (hit 0.85, miss -0.4, thresholds 0.6 / -0.35: a classified cell keeps its class in
    between, so one beam overshooting a wall could leave a lasting hole in it).

    The last four are the TurtleBot3 Gmapping settings the thesis ran with (maxUrange 3.0,
    linearUpdate 1.0, angularUpdate 0.2, temporalUpdate 0.5): the map is updated about twice a
    second, not at the LiDAR's 5 Hz.
    """

    hit: float = 0.75
    miss: float = -0.25
    clamp_min: float = -2.0
    clamp_max: float = 3.5
    occupied_above: float = 0.01
    free_below: float = -0.01
    usable_range: float = 3.0
    linear_update: float = 1.0
    angular_update: float = 0.2
    temporal_update: float = 0.5

    def __post_init__(self) -> None:
        for name in ("usable_range", "linear_update", "angular_update"):
            value = getattr(self, name)
            if not value > 0:
                raise ConfigError(f"MapperConfig.{name} must be positive, got {value!r}")
        for name in ("hit", "miss", "clamp_min", "clamp_max", "occupied_above", "free_below"):
            value = getattr(self, name)
            if not math.isfinite(value):
                raise ConfigError(f"MapperConfig.{name} must be finite, got {value!r}")
        if not (self.hit > 0 > self.miss):
            raise ConfigError(f"MapperConfig needs hit > 0 > miss, got hit={self.hit!r}, miss={self.miss!r}")
        if not self.miss < self.free_below:  # else the first scan maps nothing free: "explored" at t = 0
            raise ConfigError(
                f"MapperConfig needs miss < free_below (one pass maps a cell free), "
                f"got miss={self.miss!r}, free_below={self.free_below!r}"
            )
        if not (self.clamp_min < self.free_below < 0 < self.occupied_above < self.clamp_max):
            raise ConfigError(
                "MapperConfig needs clamp_min < free_below < 0 < occupied_above < clamp_max, got "
                f"{self.clamp_min!r}, {self.free_below!r}, {self.occupied_above!r}, {self.clamp_max!r}"
            )


@dataclass
class ScanUpdate:
    """Cells a scan revealed for the first time.

    Attributes:
        new_free: cells first classified FREE.
        new_occupied: cells first classified OCCUPIED.
        new_explorable: newly known cells that belong to the explorable region.
    """

    new_free: int
    new_occupied: int
    new_explorable: int


class LogOddsMapper:
    """Builds an occupancy grid from scans taken at known poses.

    Args:
        world: the ground-truth grid; only its shape, resolution and origin are used (the extent
            the map may grow to).
        config: the log-odds update rule.
        explorable: cells that count toward coverage (the world's explorable region); ``None``
            counts every cell.
    """

    def __init__(
        self,
        world: OccupancyGrid,
        config: MapperConfig | None = None,
        explorable: NDArray[np.bool_] | None = None,
    ) -> None:
        self.config = config or MapperConfig()
        self.resolution = world.resolution
        self.origin = world.origin
        shape = world.shape
        self.logodds = np.zeros(shape, dtype=np.float32)
        self.state = np.full(shape, CellState.UNKNOWN, dtype=np.int8)
        self.seen = np.zeros(shape, dtype=np.bool_)
        self.observed = np.zeros(shape, dtype=np.bool_)  # reached by this mapper's own scans, not merges
        self.looks = np.zeros(shape, dtype=np.uint16)  # scans that reached a cell (a merge may bring its count)
        self.felt = np.zeros(shape, dtype=np.bool_)  # occupied from contact (:meth:`mark_occupied`)
        self.explorable = np.ones(shape, np.bool_) if explorable is None else explorable.astype(np.bool_)
        self._pending = np.zeros(shape, dtype=np.int16)
        self._bbox = np.array([shape[0], -1, shape[1], -1], dtype=np.int64)
        self._changed = self._bbox.copy()  # the cells its own scans and bumps updated, see take_changed
        self._counters = np.zeros(3, dtype=np.int64)
        self._ranges = np.empty(0)  # scratch: the simulated scan's ranges (cells)
        self._extent = np.zeros(4, np.int64)  # scratch: the window the simulated scan marked
        c = self.config
        self._rule = LogOddsRule(c.clamp_min, c.clamp_max, c.free_below, c.occupied_above, c.hit, c.miss)
        self.explored_cells = 0
        self._last_update: tuple[Pose, float] | None = None

    @property
    def last_update(self) -> tuple[Pose, float] | None:
        """Pose and time (s) of the last scan folded in; None before the first."""
        return self._last_update

    def wants_scan(self, pose: Pose, time_s: float) -> bool:
        """Whether Gmapping would process a scan taken now: the first one, and then each after the
        robot moved ``linear_update`` or turned ``angular_update`` since the last processed scan,
        or ``temporal_update`` seconds passed."""
        if self._last_update is None:
            return True
        c = self.config
        last_pose, last_time = self._last_update
        return (
            (c.temporal_update > 0 and time_s - last_time >= c.temporal_update - 1e-9)
            or math.hypot(pose.x - last_pose.x, pose.y - last_pose.y) >= c.linear_update
            or abs(wrap_angle(pose.theta - last_pose.theta)) >= c.angular_update
        )

    def integrate(self, scan: Scan, max_range: float, time_s: float = 0.0) -> ScanUpdate:
        """Fold ``scan`` into the map.

        Args:
            scan: the scan.
            max_range: the sensor's maximum range (m); ``inf`` readings mean free up to it.
            time_s: when the scan was taken (s), for :meth:`wants_scan`.

        Raises:
            ValueError: more than :data:`~frontier_rl.core.sensing.lidar.MAX_BEAMS` beams.
        """
        if len(scan.ranges) > MAX_BEAMS:
            raise ValueError(f"a scan may have at most {MAX_BEAMS:,} beams, got {len(scan.ranges):,}")
        res = self.resolution
        mark_beams(
            self._pending,
            (scan.pose.x - self.origin[0]) / res,
            (scan.pose.y - self.origin[1]) / res,
            scan.dir_x,
            scan.dir_y,
            scan.ranges / res,
            min(max_range, self.config.usable_range) / res,
        )
        return self._apply(scan.pose, time_s)

    def integrate_simulated(
        self,
        lidar: Lidar,
        pose: Pose,
        rng: np.random.Generator | None,
        time_s: float = 0.0,
        filtered: tuple[NDArray[np.float64], float] | None = None,
    ) -> ScanUpdate:
        """Simulate a scan of ``lidar`` at ``pose`` (at ``time_s``) and fold it in: the same result,
        bit for bit, as ``integrate(lidar.scan(pose, rng), lidar.config.max_range, time_s)``,
        without the Python-side arrays. The lidar must cast on a world of this mapper's shape.
        ``filtered`` = (centres (k, 2) in m, radius in m): discs whose cells the scan leaves
        untouched (other robots: a laser filter keeps them out of the map)."""
        if lidar.grid.shape != self.state.shape:
            raise ValueError(f"lidar world shape {lidar.grid.shape} differs from the map's {self.state.shape}")
        res = self.resolution
        n = lidar.config.num_beams
        if self._ranges.shape[0] != n:
            self._ranges = np.empty(n)
        cx, cy = (pose.x - self.origin[0]) / res, (pose.y - self.origin[1]) / res
        cast_and_mark(
            lidar.blocked_padded,
            self._pending,
            cx,
            cy,
            math.cos(pose.theta),
            math.sin(pose.theta),
            lidar.cos_offsets,
            lidar.sin_offsets,
            lidar.normals(rng),
            lidar.range_noise,
            min(lidar.config.max_range, self.config.usable_range) / res,
            self._ranges,
            self._extent,
        )
        if filtered is not None and len(filtered[0]):
            centres, radius = filtered
            drop_marks(self._pending, centres[:, 0], centres[:, 1], radius, self.origin[0], self.origin[1], res)
        r0, r1, c0, c1 = self._extent
        return self._apply(pose, time_s, (int(r0), int(r1), int(c0), int(c1)))

    def mark_occupied(self, rows: NDArray[np.int64], cols: NDArray[np.int64]) -> None:
        """Set cells to certainly occupied (from contact, not from the LiDAR)."""
        if len(rows) == 0:
            return
        self.felt[rows, cols] = True
        self._pending[rows, cols] |= HIT
        saturating = self._rule._replace(hit=self.config.clamp_max)  # a hit that saturates
        window = (int(np.min(rows)), int(np.max(rows)) + 1, int(np.min(cols)), int(np.max(cols)) + 1)
        self._apply_window(window, saturating)
        self.looks[rows, cols] = MAX_LOOKS
        self.explored_cells += int(self._counters[2])

    def _apply_window(self, window: tuple[int, int, int, int], rule: LogOddsRule) -> None:
        """Apply the pending marks within ``window`` (row0, row1, col0, col1, exclusive ends) by
        ``rule``, counting into ``_counters`` from zero (:func:`~frontier_rl.core.mapping.log_odds.apply_pending`)."""
        self._counters[:] = 0
        apply_pending(
            self._pending,
            window,
            self.logodds,
            self.state,
            self.seen,
            self.observed,
            self.looks,
            self.explorable,
            rule,
            self._bbox,
            self._changed,
            self._counters,
        )

    def _apply(self, pose: Pose, time_s: float, window: tuple[int, int, int, int] | None = None) -> ScanUpdate:
        """Apply the marks of the scan taken at ``pose`` (all within ``window``, row0, row1, col0,
        col1 with exclusive ends; by default the square the usable range reaches) and record it
        as the last processed one."""
        if window is None:
            reach = int(math.ceil(self.config.usable_range / self.resolution)) + 2
            row = int(math.floor((pose.y - self.origin[1]) / self.resolution))
            col = int(math.floor((pose.x - self.origin[0]) / self.resolution))
            window = (row - reach, row + reach + 1, col - reach, col + reach + 1)
        self._apply_window(window, self._rule)
        self._last_update = (pose, time_s)
        update = ScanUpdate(int(self._counters[0]), int(self._counters[1]), int(self._counters[2]))
        self.explored_cells += update.new_explorable
        return update

    def merge_from(self, other: LogOddsMapper, window: tuple[int, int, int, int] | None = None) -> int:
        """Fold ``other``'s map (the same world and frame: known relative start poses) into this
        one, cell by cell: a cell ``other`` has looked at more often takes its class, log-odds and
        count (on a tie the higher log-odds wins, then occupied), and the walls ``other`` touched
        are known here too. Not multirobot_map_merge's rule, occupied > free > unknown: that rule
        builds a merged map afresh from the robots' own maps, and written back into them it made a
        stray hit a wall in every map for good. ``window`` (row0, row1, col0, col1; exclusive ends)
        limits the merge to part of the map. Returns the explorable cells newly known here."""
        if other.state.shape != self.state.shape:
            raise ValueError(f"maps of shapes {self.state.shape} and {other.state.shape} cannot be merged")
        rows, cols = self.state.shape
        r0, r1, c0, c1 = window if window is not None else (0, rows, 0, cols)
        # the walls the other robot touched come with their cells (walls never thinned: core/navigation/thin_walls.py)
        gained = merge_window(
            self.state,
            self.logodds,
            self.looks,
            self.felt,
            self.seen,
            self.explorable,
            other.state,
            other.logodds,
            other.looks,
            other.felt,
            (r0, r1, c0, c1),
            self._bbox,
        )
        self.explored_cells += gained
        return int(gained)

    def merge_both_ways(
        self, others: Sequence[LogOddsMapper], windows: Sequence[tuple[int, int, int, int] | None] | None = None
    ) -> None:
        """Take from each of ``others`` in turn, then let each take from this map (each pair over
        its window, None the whole map), so that afterwards all of them hold the same cells there:
        merged pair by pair, a third map's cell could leave two maps differing."""
        parts = [None] * len(others) if windows is None else windows
        for other, part in zip(others, parts, strict=True):
            self.merge_from(other, part)
        for other, part in zip(others, parts, strict=True):
            other.merge_from(self, part)

    def take_changed(self) -> tuple[int, int, int, int] | None:
        """The window (row0, row1, col0, col1; exclusive ends) of the cells this map's own scans and
        bumps have updated since the last call (None if none), and start the record afresh."""
        r0, r1, c0, c1 = (int(v) for v in self._changed)
        self._changed[:] = (self.state.shape[0], -1, self.state.shape[1], -1)
        return None if r1 < r0 else (r0, r1 + 1, c0, c1 + 1)

    @property
    def known_bounds(self) -> tuple[int, int, int, int] | None:
        """(row_min, row_max, col_min, col_max) of the cells seen so far, inclusive; None if none."""
        r0, r1, c0, c1 = (int(v) for v in self._bbox)
        return None if r1 < r0 else (r0, r1, c0, c1)

    def occupancy_grid(self, margin: int = 1) -> OccupancyGrid:
        """The map so far, cropped to the seen cells plus ``margin`` cells of unknown (a copy)."""
        bounds = self.known_bounds
        rows, cols = self.state.shape
        if bounds is None:
            r0, r1, c0, c1 = 0, rows - 1, 0, cols - 1
        else:
            r0, r1, c0, c1 = bounds
            r0, c0 = max(r0 - margin, 0), max(c0 - margin, 0)
            r1, c1 = min(r1 + margin, rows - 1), min(c1 + margin, cols - 1)
        res = self.resolution
        return OccupancyGrid(
            self.state[r0 : r1 + 1, c0 : c1 + 1].copy(),
            res,
            (self.origin[0] + c0 * res, self.origin[1] + r0 * res),
        )
