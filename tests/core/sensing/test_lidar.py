"""Tests of frontier_rl.core.sensing.lidar: ranges against walls at known distances, range limits, noise."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.typing import NDArray

from frontier_rl.core.sensing.lidar import Lidar, LidarConfig
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.errors import ConfigError

RES = 0.05


def box(
    rows: int, cols: int, wall: int = 1, resolution: float = RES, origin: tuple[float, float] = (0.0, 0.0)
) -> OccupancyGrid:
    """A free room of rows x cols cells with a wall of ``wall`` cells all round."""
    data = np.full((rows, cols), CellState.OCCUPIED, dtype=np.int8)
    data[wall:-wall, wall:-wall] = CellState.FREE
    return OccupancyGrid(data, resolution, origin)


def box_reference(grid: OccupancyGrid, pose: Pose, num_beams: int, wall: int = 1) -> NDArray[np.float64]:
    """Exact distance (m) from ``pose`` to the inner wall surface of :func:`box` along every beam."""
    res = grid.resolution
    x_lo, y_lo = grid.origin[0] + wall * res, grid.origin[1] + wall * res
    x_hi, y_hi = grid.origin[0] + (grid.width - wall) * res, grid.origin[1] + (grid.height - wall) * res
    angles = pose.theta + np.arange(num_beams) * (2.0 * math.pi / num_beams)
    out = np.empty(num_beams)
    for i, a in enumerate(angles):
        dx, dy = math.cos(a), math.sin(a)
        tx = (x_hi - pose.x) / dx if dx > 1e-12 else (pose.x - x_lo) / -dx if dx < -1e-12 else math.inf
        ty = (y_hi - pose.y) / dy if dy > 1e-12 else (pose.y - y_lo) / -dy if dy < -1e-12 else math.inf
        out[i] = min(tx, ty)
    return out


# ------------------------------------------------------------------------------ known distances
# A 4.0 m x 3.0 m box (80 x 60 cells) with one-cell walls: free x in [0.05, 3.95), y in [0.05, 2.95).
# From (1.0, 1.2) the wall surfaces are 2.95 m (+x), 1.75 m (+y), 0.95 m (-x) and 1.15 m (-y) away.
AXIS_DISTANCES = {0: 2.95, 90: 1.75, 180: 0.95, 270: 1.15}


@pytest.mark.parametrize("origin", [(0.0, 0.0), (-2.0, 5.0), (13.37, -4.2)])
@pytest.mark.parametrize("heading_deg", [0, 90, 180, 270, -90])
def test_axis_beams_hit_the_walls_at_the_expected_distance(origin: tuple[float, float], heading_deg: int) -> None:
    grid = box(60, 80, origin=origin)
    lidar = Lidar(grid)
    pose = Pose(origin[0] + 1.0, origin[1] + 1.2, math.radians(heading_deg))
    scan = lidar.scan(pose, None)
    assert scan.ranges.shape == (360,)
    for beam in (0, 90, 180, 270):
        world_angle = (beam + heading_deg) % 360
        expected = AXIS_DISTANCES[world_angle]
        assert scan.ranges[beam] == pytest.approx(expected, abs=1e-9), (beam, world_angle)
        assert abs(scan.ranges[beam] - expected) < RES  # the brief's bound, trivially implied
        assert scan.dir_x[beam] == pytest.approx(math.cos(math.radians(world_angle)), abs=1e-12)
        assert scan.dir_y[beam] == pytest.approx(math.sin(math.radians(world_angle)), abs=1e-12)
    assert scan.pose == pose


@pytest.mark.parametrize(
    "pose",
    [
        Pose(1.0, 1.2, 0.0),
        Pose(2.0, 1.5, 0.7),
        Pose(0.31, 2.77, -2.5),
        Pose(3.62, 0.43, 3.1),
        Pose(1.975, 1.475, 1.234),  # on a cell corner
    ],
)
def test_every_beam_matches_the_exact_distance_to_the_box_walls(pose: Pose) -> None:
    grid = box(60, 80)
    config = LidarConfig(num_beams=720, min_range=0.0)
    ranges = Lidar(grid, config).scan(pose, None).ranges
    reference = box_reference(grid, pose, config.num_beams)
    finite = reference < config.max_range - 1e-6
    np.testing.assert_allclose(ranges[finite], reference[finite], rtol=0, atol=1e-9)
    assert np.all(np.isinf(ranges[reference > config.max_range + 1e-6]))


def test_rotating_the_robot_rotates_the_scan() -> None:
    lidar = Lidar(box(60, 80))
    base = lidar.scan(Pose(1.3, 1.1, 0.0), None).ranges
    for k in (1, 45, 90, 200, 359):
        turned = lidar.scan(Pose(1.3, 1.1, k * 2.0 * math.pi / 360), None).ranges
        np.testing.assert_allclose(turned, np.roll(base, -k), rtol=0, atol=1e-9)


# ------------------------------------------------------------------------------------ limits
def test_beams_beyond_max_range_report_inf() -> None:
    grid = box(60, 80)
    lidar = Lidar(grid, LidarConfig(max_range=2.0))
    ranges = lidar.scan(Pose(1.0, 1.2, 0.0), None).ranges
    assert math.isinf(ranges[0]) and ranges[0] > 0  # wall at 2.95 m
    assert ranges[180] == pytest.approx(0.95, abs=1e-9)
    reference = box_reference(grid, Pose(1.0, 1.2, 0.0), 360)
    np.testing.assert_array_equal(np.isinf(ranges), reference > 2.0)


def test_an_open_world_gives_inf_everywhere_within_max_range() -> None:
    # 10 m x 10 m box: from the centre every wall is 4.95 m or more away, beyond 3.5 m.
    lidar = Lidar(box(200, 200))
    ranges = lidar.scan(Pose(5.0, 5.0, 0.4), None).ranges
    assert np.all(np.isposinf(ranges))


@pytest.mark.parametrize("gap", [0.02, 0.05, 0.1, 0.115])
def test_a_wall_closer_than_min_range_reads_nan(gap: float) -> None:
    lidar = Lidar(box(60, 60))
    ranges = lidar.scan(Pose(0.05 + gap, 1.2, 0.0), None).ranges
    assert math.isnan(ranges[180])  # -x: the wall surface is `gap` < 0.12 m away
    assert ranges[0] == pytest.approx(2.95 - 0.05 - gap, abs=1e-9)  # +x: far wall, valid
    # nothing else is invalid: only the beams that meet the near wall closer than 0.12 m
    near = box_reference(lidar.grid, Pose(0.05 + gap, 1.2, 0.0), 360) < 0.12
    np.testing.assert_array_equal(np.isnan(ranges), near)


def test_min_range_zero_reports_short_ranges() -> None:
    lidar = Lidar(box(60, 80), LidarConfig(min_range=0.0))
    assert lidar.scan(Pose(0.15, 1.2, 0.0), None).ranges[180] == pytest.approx(0.10, abs=1e-9)


def test_pose_outside_the_world_raises() -> None:
    lidar = Lidar(box(60, 80))
    with pytest.raises(ValueError, match="outside"):
        lidar.scan(Pose(-0.5, 1.0, 0.0), None)


# ------------------------------------------------------------------------------------- noise
def test_no_rng_means_no_noise() -> None:
    grid = box(60, 80)
    lidar = Lidar(grid)
    pose = Pose(1.7, 0.9, 0.3)
    a, b = lidar.scan(pose, None), lidar.scan(pose, None)
    np.testing.assert_array_equal(a.ranges, b.ranges)
    reference = box_reference(grid, pose, 360)
    np.testing.assert_allclose(a.ranges, reference, rtol=0, atol=1e-9)


def test_same_seed_same_noise_and_other_seed_other_noise() -> None:
    lidar = Lidar(box(60, 80))
    pose = Pose(1.7, 0.9, 0.3)
    a = lidar.scan(pose, np.random.default_rng(5)).ranges
    b = lidar.scan(pose, np.random.default_rng(5)).ranges
    c = lidar.scan(pose, np.random.default_rng(6)).ranges
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)
    assert not np.array_equal(a, lidar.scan(pose, None).ranges)


@pytest.mark.parametrize(
    "config",
    [LidarConfig(), LidarConfig(noise_abs=0.04, noise_rel=0.02, noise_rel_from=1.0)],
    ids=["lds01", "custom"],
)
def test_noise_is_unbiased_with_the_configured_sigma(config: LidarConfig) -> None:
    """noise_abs and noise_rel are documented as 2 sigma: sigma = noise_abs / 2 below
    noise_rel_from, noise_rel / 2 * range at and beyond it."""
    lidar = Lidar(box(60, 80), config)
    pose = Pose(0.45, 1.5, 0.0)  # the -x wall is 0.40 m away: short beams and long beams
    truth = lidar.scan(pose, None).ranges
    rng = np.random.default_rng(1234)
    noisy = np.stack([lidar.scan(pose, rng).ranges for _ in range(200)])
    short = (truth > 0.2) & (truth < config.noise_rel_from)
    long = (truth >= config.noise_rel_from) & (truth < 3.0)
    assert short.sum() > 20 and long.sum() > 100
    sigma_abs, sigma_rel = config.noise_abs / 2, config.noise_rel / 2
    e_short = (noisy[:, short] - truth[short]).ravel()
    z_long = ((noisy[:, long] - truth[long]) / truth[long]).ravel()
    assert np.all(np.isfinite(e_short)) and np.all(np.isfinite(z_long))
    assert abs(e_short.mean()) < 5 * sigma_abs / math.sqrt(e_short.size)
    assert abs(z_long.mean()) < 5 * sigma_rel / math.sqrt(z_long.size)
    assert e_short.std() == pytest.approx(sigma_abs, rel=0.05)
    assert z_long.std() == pytest.approx(sigma_rel, rel=0.05)


def test_noise_can_push_a_reading_out_of_range() -> None:
    # A wall 3.45 m away, just inside 3.5 m: with 5 % noise (sigma ~ 8.6 cm) many readings overshoot.
    grid = box(60, 80)
    lidar = Lidar(grid)
    pose = Pose(3.95 - 3.45, 1.5, 0.0)
    assert lidar.scan(pose, None).ranges[0] == pytest.approx(3.45, abs=1e-9)
    rng = np.random.default_rng(0)
    beam0 = np.array([lidar.scan(pose, rng).ranges[0] for _ in range(200)])
    assert np.isposinf(beam0).any()
    finite = beam0[np.isfinite(beam0)]
    assert finite.size > 0 and finite.max() <= 3.5


# -------------------------------------------------------------------------------------- config
def test_config_defaults_and_derived_values() -> None:
    c = LidarConfig()
    assert (c.num_beams, c.min_range, c.max_range, c.rate_hz) == (360, 0.12, 3.5, 5.0)
    assert c.period == pytest.approx(0.2)
    np.testing.assert_allclose(LidarConfig(num_beams=4).beam_offsets, [0, math.pi / 2, math.pi, 3 * math.pi / 2])


@pytest.mark.parametrize(
    ("kwargs", "named"),
    [
        ({"num_beams": 0}, "0"),
        ({"num_beams": -3}, "-3"),
        ({"min_range": -0.1}, "-0.1"),
        ({"min_range": 4.0}, "4.0"),
        ({"min_range": 3.5}, "3.5"),
        ({"max_range": math.inf}, "inf"),
        ({"max_range": math.nan}, "nan"),
        ({"min_range": math.nan}, "nan"),
        ({"rate_hz": 0.0}, "0.0"),
        ({"rate_hz": -5.0}, "-5.0"),
        ({"rate_hz": math.nan}, "nan"),
        ({"noise_abs": -0.01}, "-0.01"),
        ({"noise_rel": -0.05}, "-0.05"),
        ({"noise_rel": math.nan}, "nan"),
        ({"num_beams": 16_384}, "16384"),  # its pass counts would reach the map's hit bit
        ({"rate_hz": 1e12}, "1000000000000.0"),
        ({"rate_hz": math.inf}, "inf"),
        ({"noise_abs": math.inf}, "inf"),
    ],
)
def test_bad_config_raises_config_error_naming_the_value(kwargs: dict[str, float], named: str) -> None:
    with pytest.raises(ConfigError, match=named.replace(".", r"\.")):
        LidarConfig(**kwargs)  # type: ignore[arg-type]
