"""Log-odds occupancy mapping from LiDAR scans, like Gmapping's output grid.

The mapper keeps a log-odds array over the whole world extent, but a map *exported* from it covers
only the bounding box of the cells seen so far: it starts around the robot and grows as the robot
sees more, as a SLAM map does. Poses are taken as known (no localisation error).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba as nb
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.grid import CellState, OccupancyGrid
from frontier_rl.core.lidar import Lidar, Scan
from frontier_rl.core.raycast import FASTMATH, ray_start
from frontier_rl.core.robot import Pose, wrap_angle
from frontier_rl.errors import ConfigError

_UNKNOWN = np.int8(CellState.UNKNOWN)
_FREE = np.int8(CellState.FREE)
_OCCUPIED = np.int8(CellState.OCCUPIED)


@dataclass(frozen=True)
class MapperConfig:
    """Log-odds update rule.

    Attributes:
        hit: log-odds added to the cell a beam ends in.
        miss: log-odds added to each cell a beam passes through (negative).
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

    The last four are the TurtleBot3 Gmapping settings the thesis ran with (maxUrange 3.0,
    linearUpdate 1.0, angularUpdate 0.2, temporalUpdate 0.5): the map is updated about twice a
    second, not at the LiDAR's 5 Hz.
    """

    hit: float = 0.85
    miss: float = -0.4
    clamp_min: float = -2.0
    clamp_max: float = 3.5
    occupied_above: float = 0.6
    free_below: float = -0.35
    usable_range: float = 3.0
    linear_update: float = 1.0
    angular_update: float = 0.2
    temporal_update: float = 0.5

    def __post_init__(self) -> None:
        for name in ("usable_range", "linear_update", "angular_update"):
            value = getattr(self, name)
            if not value > 0:
                raise ConfigError(f"MapperConfig.{name} must be positive, got {value!r}")
        if not (self.hit > 0 > self.miss):
            raise ConfigError(f"MapperConfig needs hit > 0 > miss, got hit={self.hit!r}, miss={self.miss!r}")
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


@nb.njit(cache=True, fastmath=FASTMATH)
def integrate_scan(
    logodds: NDArray[np.float32],
    state: NDArray[np.int8],
    stamp: NDArray[np.int32],
    scan_id: int,
    seen: NDArray[np.bool_],
    explorable: NDArray[np.bool_],
    cx: float,
    cy: float,
    dirs_x: NDArray[np.float64],
    dirs_y: NDArray[np.float64],
    ranges: NDArray[np.float64],
    resolution: float,
    usable_range: float,
    params: NDArray[np.float64],
    bbox: NDArray[np.int64],
    counters: NDArray[np.int64],
    touched: NDArray[np.int64],
) -> None:
    """Fold one scan into the map: ``ranges`` in m, (cx, cy) and ``usable_range`` in cells.

    Each cell is updated at most once per scan, and a hit wins over a pass, so beams that graze
    a wall do not erase it. ``ranges`` holds ``inf`` for "free up to max range" and ``nan`` for
    invalid beams. Beams are cropped at ``usable_range`` (Gmapping's maxUrange): free up to it,
    no hit beyond it. ``params`` = (clamp_min, clamp_max, free_below, occupied_above, hit, miss).
    ``counters`` receives the cells first classified free, occupied, and explorable.
    ``touched`` is scratch space for at least one entry per cell a beam can visit.
    """
    rows, cols = logodds.shape
    n_touched = 0  # touched[:n_touched] are flat cell indices, the first n_hits of them hits
    for i in range(ranges.shape[0]):
        r = ranges[i] / resolution
        if math.isfinite(r) and r <= usable_range:
            row = int(math.floor(cy + (r + 1e-4) * dirs_y[i]))
            col = int(math.floor(cx + (r + 1e-4) * dirs_x[i]))
            if 0 <= row < rows and 0 <= col < cols and stamp[row, col] != scan_id:
                stamp[row, col] = scan_id
                touched[n_touched] = row * cols + col
                n_touched += 1
    n_hits = n_touched
    for i in range(ranges.shape[0]):
        r = ranges[i] / resolution
        if math.isnan(r):
            continue
        limit = min(r, usable_range)
        row, col, s_r, s_c, tm_r, tm_c, td_r, td_c = ray_start(cx, cy, dirs_x[i], dirs_y[i])
        while min(tm_r, tm_c) <= limit and 0 <= row < rows and 0 <= col < cols:
            if stamp[row, col] != scan_id:
                stamp[row, col] = scan_id
                touched[n_touched] = row * cols + col
                n_touched += 1
            if tm_c < tm_r:
                col += s_c
                tm_c += td_c
            else:
                row += s_r
                tm_r += td_r
    apply_updates(touched, n_touched, n_hits, logodds, state, seen, explorable, params, bbox, counters)


@nb.njit(cache=True)
def apply_updates(
    touched: NDArray[np.int64],
    n_touched: int,
    n_hits: int,
    logodds: NDArray[np.float32],
    state: NDArray[np.int8],
    seen: NDArray[np.bool_],
    explorable: NDArray[np.bool_],
    params: NDArray[np.float64],
    bbox: NDArray[np.int64],
    counters: NDArray[np.int64],
) -> None:
    """Add ``hit`` to the first ``n_hits`` cells of ``touched[:n_touched]`` (flat indices) and
    ``miss`` to the rest, then reclassify them and count the cells seen for the first time."""
    cols = logodds.shape[1]
    low, high, free_below, occupied_above = params[0], params[1], params[2], params[3]
    flat_logodds = logodds.reshape(-1)
    flat_state = state.reshape(-1)
    flat_seen = seen.reshape(-1)
    flat_explorable = explorable.reshape(-1)
    for k in range(n_touched):
        cell = touched[k]
        delta = params[4] if k < n_hits else params[5]
        value = min(max(flat_logodds[cell] + delta, low), high)
        flat_logodds[cell] = value
        if value > occupied_above:
            new_state = _OCCUPIED
        elif value < free_below:
            new_state = _FREE
        else:
            new_state = flat_state[cell]  # in between: a seen cell keeps its class (as Gmapping's do)
        flat_state[cell] = new_state
        if new_state != _UNKNOWN and not flat_seen[cell]:
            flat_seen[cell] = True
            counters[0 if new_state == _FREE else 1] += 1
            if flat_explorable[cell]:
                counters[2] += 1
            row = cell // cols
            col = cell % cols
            bbox[0] = min(bbox[0], row)
            bbox[1] = max(bbox[1], row)
            bbox[2] = min(bbox[2], col)
            bbox[3] = max(bbox[3], col)


@nb.njit(cache=True, fastmath=FASTMATH)
def simulate_scan(
    blocked_padded: NDArray[np.bool_],
    cx: float,
    cy: float,
    cos_t: float,
    sin_t: float,
    cos_offsets: NDArray[np.float64],
    sin_offsets: NDArray[np.float64],
    normals: NDArray[np.float64],
    noise: NDArray[np.float64],
    ranges: NDArray[np.float64],
    trav_cells: NDArray[np.int64],
    trav_exit: NDArray[np.float64],
    touched: NDArray[np.int64],
    stamp: NDArray[np.int32],
    scan_id: int,
    usable: float,
) -> tuple[int, int]:
    """Cast a noisy scan on the ground truth and collect the map cells it updates, in one
    traversal per beam: the same cells, ranges and order as :class:`~frontier_rl.core.lidar.Lidar`'s
    ``scan`` followed by :func:`integrate_scan`, at about half the cost.

    ``noise`` = (resolution, min_range, max_range, sigma_abs, sigma_rel, rel_from), lengths in m;
    (cx, cy) and ``usable`` (the range where beams are cropped for mapping) in cells. Writes the
    measured ranges (m) into ``ranges`` and the touched cells into
    ``touched``; returns (number touched, number of hits among them, which come first).
    """
    res, min_r, max_r = noise[0], noise[1], noise[2]
    max_cells = max_r / res
    rows = blocked_padded.shape[0] - 2
    cols = blocked_padded.shape[1] - 2
    n_beams = cos_offsets.shape[0]
    beam_end = np.empty(n_beams, np.int64)
    beam_limit = np.empty(n_beams)
    flat_blocked = blocked_padded.reshape(-1)
    pcols = cols + 2
    n_trav = 0
    n_touched = 0
    for i in range(n_beams):
        dx = cos_t * cos_offsets[i] - sin_t * sin_offsets[i]
        dy = sin_t * cos_offsets[i] + cos_t * sin_offsets[i]
        row, col, s_r, s_c, tm_r, tm_c, td_r, td_c = ray_start(cx, cy, dx, dy)
        # Walk on flat indices with selects instead of branches: the step direction of a DDA is
        # unpredictable, and a mispredicted branch per cell would double the cost.
        padded = (row + 1) * pcols + (col + 1)
        cell = row * cols + col
        row_step_p, row_step = s_r * pcols, s_r * cols
        t = 0.0
        t_hit = np.inf
        while t <= max_cells:
            if flat_blocked[padded]:
                t_hit = t
                break
            along_col = tm_c < tm_r
            t = tm_c if along_col else tm_r
            trav_cells[n_trav] = cell
            trav_exit[n_trav] = t
            n_trav += 1
            padded += s_c if along_col else row_step_p
            cell += s_c if along_col else row_step
            col += s_c if along_col else 0
            row += 0 if along_col else s_r
            tm_c = tm_c + td_c if along_col else tm_c
            tm_r = tm_r if along_col else tm_r + td_r
        r = t_hit * res
        if math.isfinite(r):
            sigma = noise[3] if r < noise[5] else noise[4] * r
            r += normals[i] * sigma
            if r > max_r:
                r = np.inf
            elif r < min_r:
                r = np.nan
        ranges[i] = r
        limit = np.nan if math.isnan(r) else min(r / res, usable)
        if math.isfinite(t_hit) and limit > t_hit:  # the reading overshoots: trace on through the wall
            while 0 <= row < rows and 0 <= col < cols and min(tm_r, tm_c) <= limit:
                trav_cells[n_trav] = row * cols + col
                trav_exit[n_trav] = min(tm_r, tm_c)
                n_trav += 1
                if tm_c < tm_r:
                    col += s_c
                    tm_c += td_c
                else:
                    row += s_r
                    tm_r += td_r
        beam_end[i] = n_trav
        beam_limit[i] = limit
        if math.isfinite(r) and r / res <= usable:
            hit_row = int(math.floor(cy + (r / res + 1e-4) * dy))
            hit_col = int(math.floor(cx + (r / res + 1e-4) * dx))
            if 0 <= hit_row < rows and 0 <= hit_col < cols and stamp[hit_row, hit_col] != scan_id:
                stamp[hit_row, hit_col] = scan_id
                touched[n_touched] = hit_row * cols + hit_col
                n_touched += 1
    n_hits = n_touched
    flat_stamp = stamp.reshape(-1)
    start = 0
    for i in range(n_beams):
        limit = beam_limit[i]
        if not math.isnan(limit):
            for k in range(start, beam_end[i]):
                if trav_exit[k] > limit:
                    break
                cell = trav_cells[k]
                # Branch-free: always write, count only a cell not stamped yet (near the robot
                # many beams cross the same cells, and that branch would be a coin toss).
                fresh = flat_stamp[cell] != scan_id
                flat_stamp[cell] = scan_id
                touched[n_touched] = cell
                n_touched += fresh
        start = beam_end[i]
    return n_touched, n_hits


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
        self.explorable = np.ones(shape, np.bool_) if explorable is None else explorable.astype(np.bool_)
        self._stamp = np.zeros(shape, dtype=np.int32)
        self._scan_id = 0
        self._bbox = np.array([shape[0], -1, shape[1], -1], dtype=np.int64)
        self._counters = np.zeros(3, dtype=np.int64)
        self._touched = np.empty(0, dtype=np.int64)
        self._trav_cells = np.empty(0, dtype=np.int64)
        self._trav_exit = np.empty(0, dtype=np.float64)
        self.last_ranges = np.empty(0, dtype=np.float64)
        c = self.config
        self._params = np.array(
            [c.clamp_min, c.clamp_max, c.free_below, c.occupied_above, c.hit, c.miss], dtype=np.float64
        )
        self.explored_cells = 0
        self._last_update: tuple[Pose, float] | None = None

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
        """
        res = self.resolution
        usable = min(max_range, self.config.usable_range)
        self._begin_scan()
        integrate_scan(
            self.logodds,
            self.state,
            self._stamp,
            self._scan_id,
            self.seen,
            self.explorable,
            (scan.pose.x - self.origin[0]) / res,
            (scan.pose.y - self.origin[1]) / res,
            scan.dir_x,
            scan.dir_y,
            scan.ranges,
            res,
            usable / res,
            self._params,
            self._bbox,
            self._counters,
            self._touched_buffer(scan.ranges.shape[0], max_range / res),
        )
        return self._finish(scan.pose, time_s)

    def integrate_simulated(
        self, lidar: Lidar, pose: Pose, rng: np.random.Generator | None, time_s: float = 0.0
    ) -> ScanUpdate:
        """Simulate a scan of ``lidar`` at ``pose`` (at ``time_s``) and fold it in: the same result,
        bit for bit, as ``integrate(lidar.scan(pose, rng), lidar.config.max_range, time_s)``, in a
        single traversal per beam. The lidar must cast on a world of this mapper's shape."""
        if lidar.grid.shape != self.state.shape:
            raise ValueError(
                f"lidar world shape {lidar.grid.shape} differs from the map's {self.state.shape}"
            )
        res = self.resolution
        cfg = lidar.config
        n = cfg.num_beams
        max_cells = cfg.max_range / res
        per_beam = 2 * int(math.ceil(max_cells)) + 4
        if self._trav_cells.shape[0] < n * per_beam:
            self._trav_cells = np.empty(n * per_beam, np.int64)
            self._trav_exit = np.empty(n * per_beam)
        if self.last_ranges.shape[0] != n:
            self.last_ranges = np.empty(n)
        self._begin_scan()
        touched = self._touched_buffer(n, max_cells)
        n_touched, n_hits = simulate_scan(
            lidar.blocked_padded,
            (pose.x - self.origin[0]) / res,
            (pose.y - self.origin[1]) / res,
            math.cos(pose.theta),
            math.sin(pose.theta),
            lidar.cos_offsets,
            lidar.sin_offsets,
            lidar.normals(rng),
            lidar.noise_params,
            self.last_ranges,
            self._trav_cells,
            self._trav_exit,
            touched,
            self._stamp,
            self._scan_id,
            min(cfg.max_range, self.config.usable_range) / res,
        )
        apply_updates(touched, n_touched, n_hits, self.logodds, self.state, self.seen, self.explorable,
                      self._params, self._bbox, self._counters)  # fmt: skip
        return self._finish(pose, time_s)

    def mark_occupied(self, rows: NDArray[np.int64], cols: NDArray[np.int64]) -> None:
        """Set cells to certainly occupied (from contact, not from the LiDAR)."""
        if len(rows) == 0:
            return
        self._begin_scan()
        touched = (np.asarray(rows, np.int64) * self.state.shape[1] + np.asarray(cols, np.int64)).copy()
        params = self._params.copy()
        params[4] = self.config.clamp_max  # a hit that saturates
        n = len(touched)
        apply_updates(
            touched,
            n,
            n,
            self.logodds,
            self.state,
            self.seen,
            self.explorable,
            params,
            self._bbox,
            self._counters,
        )
        self.explored_cells += int(self._counters[2])

    def _begin_scan(self) -> None:
        self._scan_id += 1
        self._counters[:] = 0

    def _finish(self, pose: Pose, time_s: float) -> ScanUpdate:
        self._last_update = (pose, time_s)
        update = ScanUpdate(int(self._counters[0]), int(self._counters[1]), int(self._counters[2]))
        self.explored_cells += update.new_explorable
        return update

    def _touched_buffer(self, n_beams: int, max_range_cells: float) -> NDArray[np.int64]:
        # a beam of length L cells crosses at most 2L + 2 cell boundaries
        needed = n_beams * (2 * int(math.ceil(max_range_cells)) + 4)
        if self._touched.shape[0] < needed:
            self._touched = np.empty(needed, np.int64)
        return self._touched

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


def fit_to_size(data: NDArray[np.int8], size: int, center: tuple[int, int] | None = None) -> NDArray[np.int8]:
    """A ``size`` × ``size`` window of ``data`` centred on ``center`` (row, col), unknown outside.

    Args:
        data: a grid of :class:`CellState` values.
        size: edge of the output (cells).
        center: the cell placed at the window's centre; the grid's own centre when ``None``.
    """
    if size < 1:
        raise ConfigError(f"size must be >= 1, got {size!r}")
    rows, cols = data.shape
    cr, cc = (rows // 2, cols // 2) if center is None else center
    out = np.full((size, size), CellState.UNKNOWN, dtype=np.int8)
    r0, c0 = cr - size // 2, cc - size // 2
    src_r0, src_c0 = max(r0, 0), max(c0, 0)
    src_r1, src_c1 = min(r0 + size, rows), min(c0 + size, cols)
    if src_r1 > src_r0 and src_c1 > src_c0:
        out[src_r0 - r0 : src_r1 - r0, src_c0 - c0 : src_c1 - c0] = data[src_r0:src_r1, src_c0:src_c1]
    return out


def downsample(data: NDArray[np.int8], factor: int) -> NDArray[np.int8]:
    """Shrink a grid by an integer ``factor`` (the shape must divide).

    A block is OCCUPIED if any of its cells is, else FREE if at least half its cells are known
    free, else UNKNOWN: walls never vanish, and half-seen blocks stay unexplored.
    """
    rows, cols = data.shape
    if factor < 1 or rows % factor or cols % factor:
        raise ConfigError(f"downsample factor {factor!r} must be >= 1 and divide the shape {data.shape}")
    blocks = data.reshape(rows // factor, factor, cols // factor, factor)
    occupied = (blocks == CellState.OCCUPIED).any(axis=(1, 3))
    free = (blocks == CellState.FREE).sum(axis=(1, 3)) * 2 >= factor * factor
    out = np.full(occupied.shape, CellState.UNKNOWN, dtype=np.int8)
    out[free] = CellState.FREE
    out[occupied] = CellState.OCCUPIED
    return out
