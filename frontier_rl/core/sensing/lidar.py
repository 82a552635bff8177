"""A 2D LiDAR: ray casting on the ground-truth grid plus range noise (LDS-01 defaults)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numba as nb
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.raycast import cast_rays, pad_blocked
from frontier_rl.core.world.robot import Pose
from frontier_rl.errors import ConfigError

MAX_BEAMS = 16_383
"""Most beams per scan (2D LiDARs give a few thousand; the LDS-01 360). Every beam crosses the
robot's own cell, and the map update counts a cell's passes in the 14 bits below its hit bit
(:data:`frontier_rl.core.mapping.log_odds.HIT`): from 16,384 beams the count would set it."""

MAX_RATE_HZ = 100.0
"""Fastest scan rate (Hz): 2D LiDARs turn at 5-50 Hz; a scan costs wall time, so 10^12 Hz would
never let an episode end."""


@dataclass(frozen=True)
class LidarConfig:
    """LiDAR model; defaults are the TurtleBot3's LDS-01 datasheet.

    Attributes:
        num_beams: beams per scan, evenly spread over 360 degrees.
        min_range: shortest measurable range (m); closer returns are invalid.
        max_range: longest measurable range (m); beams without a return report ``inf``.
        rate_hz: scans per second.
        noise_abs: range accuracy below ``noise_rel_from`` (m), taken as 2 sigma of a Gaussian.
        noise_rel: relative range accuracy at and beyond ``noise_rel_from``, taken as 2 sigma.
        noise_rel_from: range (m) where the relative accuracy takes over.
    """

    num_beams: int = 360
    min_range: float = 0.12
    max_range: float = 3.5
    rate_hz: float = 5.0
    noise_abs: float = 0.015
    noise_rel: float = 0.05
    noise_rel_from: float = 0.5

    def __post_init__(self) -> None:
        if not (isinstance(self.num_beams, int) and not isinstance(self.num_beams, bool)):
            raise ConfigError(f"LidarConfig.num_beams must be an integer, got {self.num_beams!r}")
        if not 1 <= self.num_beams <= MAX_BEAMS:
            raise ConfigError(f"LidarConfig.num_beams must be within [1, {MAX_BEAMS:,}], got {self.num_beams!r}")
        if not (0.0 <= self.min_range < self.max_range and math.isfinite(self.max_range)):
            raise ConfigError(
                f"LidarConfig needs 0 <= min_range < max_range, got {self.min_range!r}, {self.max_range!r}"
            )
        if not 0 < self.rate_hz <= MAX_RATE_HZ:
            raise ConfigError(f"LidarConfig.rate_hz must be within (0, {MAX_RATE_HZ:g}] Hz, got {self.rate_hz!r}")
        if not (self.noise_rel_from >= 0 and math.isfinite(self.noise_rel_from)):
            raise ConfigError(f"LidarConfig.noise_rel_from must be >= 0, got {self.noise_rel_from!r}")
        if not (0 <= self.noise_abs < math.inf and 0 <= self.noise_rel < math.inf):
            raise ConfigError(
                "LidarConfig noise must be finite and >= 0, "
                f"got noise_abs={self.noise_abs!r}, noise_rel={self.noise_rel!r}"
            )

    @property
    def period(self) -> float:
        """Time between two scans (s)."""
        return 1.0 / self.rate_hz

    @property
    def beam_offsets(self) -> NDArray[np.float64]:
        """Beam angles relative to the robot heading (rad)."""
        return np.arange(self.num_beams, dtype=np.float64) * (2.0 * math.pi / self.num_beams)


class Scan(NamedTuple):
    """One LiDAR scan.

    Attributes:
        pose: where it was taken (m, rad).
        ranges: measured range per beam (m); ``inf`` = no return within max range (free up to
            it), ``nan`` = invalid (closer than min range: nothing known along the beam).
        dir_x, dir_y: world-frame unit direction of each beam.
    """

    pose: Pose
    ranges: NDArray[np.float64]
    dir_x: NDArray[np.float64]
    dir_y: NDArray[np.float64]


class RangeNoise(NamedTuple):
    """The range model as the compiled kernels take it (a tuple numba reads by field name)."""

    resolution: float
    """The grid's cell size (m): ranges are cast in cells."""
    min_range: float
    """m: a reading below it is invalid."""
    max_range: float
    """m: a reading beyond it is no return."""
    sigma_abs: float
    """The noise's standard deviation (m) below ``rel_from``."""
    sigma_rel: float
    """... and its share of the range from there on."""
    rel_from: float
    """The range (m) where the relative noise takes over."""


@nb.njit(cache=True, inline="always")
def noisy_range(cells: float, normal: float, noise: RangeNoise) -> float:
    """The reading (m) of a beam whose true range is ``cells`` (cells, ``inf`` for no return),
    given one standard-normal draw: Gaussian noise, ``inf`` beyond max range, ``nan`` under min range."""
    r: float = cells * noise.resolution
    if not math.isfinite(r):
        return r
    r += float(normal * (noise.sigma_abs if r < noise.rel_from else noise.sigma_rel * r))
    if r > noise.max_range:
        return np.inf
    if r < noise.min_range:
        return np.nan
    return r


@nb.njit(cache=True)
def add_range_noise(ranges: NDArray[np.float64], normals: NDArray[np.float64], noise: RangeNoise) -> None:
    """Turn cell ranges into noisy readings in metres, in place (see :func:`noisy_range`)."""
    for i in range(ranges.shape[0]):
        ranges[i] = noisy_range(ranges[i], normals[i], noise)


class Lidar:
    """Casts scans on a fixed ground-truth grid.

    Args:
        world: the ground-truth grid; OCCUPIED cells (and everything outside it) stop beams.
        config: the sensor model.
    """

    def __init__(self, world: OccupancyGrid, config: LidarConfig | None = None) -> None:
        self.config = config or LidarConfig()
        self.grid = world
        c = self.config
        self.blocked_padded = pad_blocked(world.data == CellState.OCCUPIED)
        offsets = c.beam_offsets
        self.cos_offsets = np.cos(offsets)
        self.sin_offsets = np.sin(offsets)
        self._zeros = np.zeros(c.num_beams)
        # the accuracies are two sigma
        self.range_noise = RangeNoise(
            world.resolution, c.min_range, c.max_range, 0.5 * c.noise_abs, 0.5 * c.noise_rel, c.noise_rel_from
        )

    def normals(self, rng: np.random.Generator | None) -> NDArray[np.float64]:
        """One standard-normal draw per beam from ``rng`` (zeros when it is None: no noise)."""
        return self._zeros if rng is None else rng.standard_normal(self.config.num_beams)

    def scan(self, pose: Pose, rng: np.random.Generator | None) -> Scan:
        """One scan at ``pose`` (m, rad); noise-free when ``rng`` is None."""
        g = self.grid
        row, col = g.world_to_cell(pose.x, pose.y)
        if not g.in_bounds(row, col):
            raise ValueError(f"LiDAR pose ({pose.x:.2f}, {pose.y:.2f}) is outside the world")
        n = self.config.num_beams
        ranges, dir_x, dir_y = np.empty(n), np.empty(n), np.empty(n)
        cast_rays(
            self.blocked_padded,
            (pose.x - g.origin[0]) / g.resolution,
            (pose.y - g.origin[1]) / g.resolution,
            math.cos(pose.theta),
            math.sin(pose.theta),
            self.cos_offsets,
            self.sin_offsets,
            self.config.max_range / g.resolution,
            ranges,
            dir_x,
            dir_y,
        )
        add_range_noise(ranges, self.normals(rng), self.range_noise)
        return Scan(pose, ranges, dir_x, dir_y)
