"""Tests of frontier_rl.core.mapping.mapper: log-odds updates, the growing exported map, scan gating,
the fused simulate-and-integrate kernel, and the fixed-size helpers for models."""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from functools import cache
from pathlib import Path

import numpy as np
import pytest
from numpy.typing import NDArray

from frontier_rl.config_files import load_sim_config
from frontier_rl.core.mapping.log_odds import HIT
from frontier_rl.core.mapping.mapper import LogOddsMapper, MapperConfig
from frontier_rl.core.sensing.lidar import MAX_BEAMS, Lidar, LidarConfig, Scan
from frontier_rl.core.world.catalog import generate_world
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.core.world.worlds import World
from frontier_rl.errors import ConfigError

RES = 0.05
CONFIGS = Path(__file__).parents[3] / "configs"
FREE, OCC, UNKNOWN = CellState.FREE.value, CellState.OCCUPIED.value, CellState.UNKNOWN.value


@cache
def office(seed: int = 0) -> World:
    return generate_world("office", seed)


def corridor(wall_col: int = 60, cols: int = 80, origin: tuple[float, float] = (0.0, 0.0)) -> OccupancyGrid:
    """20 x ``cols`` cells at 0.05 m: 2-cell walls at rows 0-1 and 18-19 and columns 0-1, a 2-cell
    wall at columns ``wall_col``..``wall_col + 1``, free space behind it."""
    data = np.full((20, cols), FREE, dtype=np.int8)
    data[:2, :] = OCC
    data[18:, :] = OCC
    data[:, :2] = OCC
    data[:, wall_col : wall_col + 2] = OCC
    return OccupancyGrid(data, RES, origin)


def beam_scan(pose: Pose, ranges: list[float], angles: list[float]) -> Scan:
    """A hand-made scan: one beam per (range, world angle)."""
    a = np.asarray(angles, dtype=np.float64)
    return Scan(pose, np.asarray(ranges, dtype=np.float64), np.cos(a), np.sin(a))


# ------------------------------------------------------------------------ one scan, by hand
@pytest.mark.parametrize("origin", [(0.0, 0.0), (-7.3, 2.15)])
def test_one_scan_marks_hits_occupied_the_beam_free_and_leaves_the_rest_unknown(
    origin: tuple[float, float],
) -> None:
    world = corridor(origin=origin)
    lidar = Lidar(world, LidarConfig(num_beams=4))
    mapper = LogOddsMapper(world)
    # robot at the centre of cell (10, 10): the +x wall surface is 2.475 m away, +y 0.375 m,
    # -x 0.425 m, -y 0.425 m
    pose = Pose(origin[0] + 10.5 * RES, origin[1] + 10.5 * RES, 0.0)
    update = mapper.integrate(lidar.scan(pose, None), lidar.config.max_range)
    expected = np.full(world.shape, UNKNOWN, dtype=np.int8)
    expected[10, 2:60] = FREE  # -x beam and +x beam
    expected[2:18, 10] = FREE  # -y beam and +y beam
    expected[10, 60] = OCC  # the +x hit; the cell behind it (10, 61) and beyond stay unknown
    expected[10, 1] = OCC  # -x hit; (10, 0) behind it stays unknown
    expected[18, 10] = OCC  # +y hit; (19, 10) stays unknown
    expected[1, 10] = OCC  # -y hit
    np.testing.assert_array_equal(mapper.state, expected)
    np.testing.assert_array_equal(mapper.seen, expected != UNKNOWN)
    assert update.new_occupied == 4
    assert update.new_free == np.count_nonzero(expected == FREE)
    assert update.new_explorable == np.count_nonzero(expected != UNKNOWN)  # explorable=None: all count
    assert mapper.explored_cells == update.new_explorable
    assert np.all(mapper.logodds[expected == OCC] == np.float32(mapper.config.hit))
    assert np.all(mapper.logodds[expected == FREE] == np.float32(mapper.config.miss))
    assert np.all(mapper.logodds[expected == UNKNOWN] == 0)


def test_a_full_scan_never_marks_cells_behind_the_wall() -> None:
    world = corridor()
    lidar = Lidar(world)
    mapper = LogOddsMapper(world)
    for x in (0.3, 1.0, 1.8, 2.6):
        mapper.integrate(lidar.scan(Pose(x, 0.5, 0.3), None), lidar.config.max_range)
    assert np.all(mapper.state[:, 62:] == UNKNOWN)  # free space behind the 2-cell wall
    assert np.all(mapper.state[:, 61] == UNKNOWN)  # the wall's far side is never hit
    assert np.any(mapper.state[:, 60] == OCC)
    # in noise-free scans, a free cell of the map is free in the world
    free = mapper.state == FREE
    assert np.all(world.data[free] == FREE)
    # and the map's wall cells are wall cells
    assert np.all(world.data[mapper.state == OCC] == OCC)


@pytest.mark.parametrize(("usable", "wall_col"), [(3.0, 74), (2.0, 54), (1.0, 34)])
def test_usable_range_crops_beams(usable: float, wall_col: int) -> None:
    """A wall 0.19 m beyond usable_range is seen by the LiDAR but not mapped; the beam is free up
    to usable_range and unknown after it."""
    world = corridor(wall_col=wall_col, cols=max(80, wall_col + 4))
    lidar = Lidar(world, LidarConfig(num_beams=1))
    mapper = LogOddsMapper(world, MapperConfig(usable_range=usable))
    x = 0.51  # cx = 10.2 cells: the wall surface (wall_col * 0.05 m) is usable + 0.19 m away
    scan = lidar.scan(Pose(x, 0.51, 0.0), None)
    assert scan.ranges[0] == pytest.approx(wall_col * RES - x, abs=1e-9)
    assert scan.ranges[0] == pytest.approx(usable + 0.19, abs=1e-9)
    mapper.integrate(scan, lidar.config.max_range)
    last_free = int(math.floor(10.2 + usable / RES - 1.0))  # cells whose far edge is within usable
    row = mapper.state[10]
    assert np.all(row[10 : last_free + 1] == FREE)
    assert np.all(row[last_free + 1 :] == UNKNOWN)
    assert (last_free + 1) * RES - x <= usable + 1e-9 < (last_free + 2) * RES - x
    assert row[wall_col] == UNKNOWN


def test_an_inf_reading_is_free_up_to_the_usable_range() -> None:
    world = corridor(wall_col=100, cols=110)
    mapper = LogOddsMapper(world)  # usable 3.0 m
    mapper.integrate(beam_scan(Pose(0.51, 0.51, 0.0), [math.inf], [0.0]), max_range=3.5)
    row = mapper.state[10]
    assert np.all(row[10:70] == FREE) and np.all(row[70:] == UNKNOWN)


def test_a_nan_reading_maps_nothing() -> None:
    world = corridor()
    mapper = LogOddsMapper(world)
    update = mapper.integrate(beam_scan(Pose(0.51, 0.51, 0.0), [math.nan], [0.0]), max_range=3.5)
    assert update.new_free == update.new_occupied == 0
    assert np.all(mapper.state == UNKNOWN)


@pytest.mark.parametrize("preset", [None, "mapper_hysteresis.yaml"])
def test_a_seen_cell_keeps_its_class_and_never_turns_unknown_again(preset: str | None) -> None:
    """A cell hit once (OCCUPIED) and then passed through keeps OCCUPIED while its log-odds sit
    between free_below and occupied_above, turns FREE below free_below, and never UNKNOWN: with the
    default rule (a band of +-0.01) and with the hysteresis preset (-0.35 to 0.6)."""
    config = MapperConfig() if preset is None else load_sim_config(CONFIGS / preset).mapper
    world = corridor(wall_col=100, cols=110)
    mapper = LogOddsMapper(world, config)
    pose = Pose(0.51, 0.51, 0.0)
    target = (10, 30)  # hit at 1.0 m: the beam ends in cell (10, 30)
    mapper.integrate(beam_scan(pose, [1.0], [0.0]), max_range=3.5)
    assert mapper.state[target] == OCC
    history = []
    for _ in range(6):
        mapper.integrate(beam_scan(pose, [math.inf], [0.0]), max_range=3.5)
        history.append((float(mapper.logodds[target]), int(mapper.state[target])))
    for value, state in history:
        assert state != UNKNOWN
        if value < config.free_below:
            assert state == FREE
        elif value <= config.occupied_above:
            assert state == OCC  # in between: keeps its class
    assert any(config.free_below <= value <= config.occupied_above for value, _ in history)
    assert history[-1][1] == FREE
    assert mapper.logodds[target] >= config.clamp_min


def test_seen_cells_never_return_to_unknown_over_a_noisy_run() -> None:
    w = office()
    lidar = Lidar(w.grid)
    mapper = LogOddsMapper(w.grid, explorable=w.explorable)
    rng = np.random.default_rng(3)
    free_cells = np.argwhere(w.grid.data == FREE)
    known = np.zeros(w.grid.shape, bool)
    for k in range(120):
        r, c = free_cells[rng.integers(len(free_cells))]
        x, y = w.grid.cell_to_world(r, c)
        mapper.integrate(lidar.scan(Pose(x, y, rng.uniform(-math.pi, math.pi)), rng), 3.5, 0.5 * k)
        now_known = mapper.state != UNKNOWN
        assert not np.any(known & ~now_known)
        np.testing.assert_array_equal(mapper.seen, now_known)
        known = now_known
    assert mapper.explored_cells == np.count_nonzero(mapper.seen & w.explorable)
    assert np.all((mapper.logodds >= mapper.config.clamp_min) & (mapper.logodds <= mapper.config.clamp_max))


# ----------------------------------------------------------- the fused kernel's documented contract
def _random_poses(world: World, n: int, rng: np.random.Generator) -> list[Pose]:
    free = np.argwhere(world.grid.data == FREE)
    cells = free[rng.integers(len(free), size=n)]
    res, (ox, oy) = world.grid.resolution, world.grid.origin
    return [
        Pose(ox + (c + rng.random()) * res, oy + (r + rng.random()) * res, rng.uniform(-math.pi, math.pi))
        for r, c in cells
    ]


def _assert_same_map(a: LogOddsMapper, b: LogOddsMapper) -> None:
    assert a.logodds.dtype == b.logodds.dtype == np.float32
    np.testing.assert_array_equal(a.logodds.view(np.int32), b.logodds.view(np.int32))  # bit for bit
    np.testing.assert_array_equal(a.state, b.state)
    np.testing.assert_array_equal(a.seen, b.seen)
    assert a.explored_cells == b.explored_cells
    assert a.known_bounds == b.known_bounds


@pytest.mark.parametrize(
    ("lidar_config", "mapper_config", "noisy"),
    [
        (LidarConfig(), MapperConfig(), True),
        (LidarConfig(num_beams=90, max_range=2.0, noise_abs=0.05, noise_rel=0.2), MapperConfig(), True),
        (LidarConfig(max_range=6.0, min_range=0.3), MapperConfig(usable_range=4.5), True),
        (LidarConfig(), MapperConfig(usable_range=1.2, hit=1.5, miss=-0.5), True),
        (LidarConfig(), MapperConfig(), False),
    ],
    ids=["default", "coarse-noisy", "long-range", "short-usable", "noise-free"],
)
def test_integrate_simulated_is_bit_identical_to_scan_then_integrate(
    lidar_config: LidarConfig, mapper_config: MapperConfig, noisy: bool
) -> None:
    w = office(1)
    lidar = Lidar(w.grid, lidar_config)
    fused = LogOddsMapper(w.grid, mapper_config, w.explorable)
    plain = LogOddsMapper(w.grid, mapper_config, w.explorable)
    rng_fused, rng_plain = np.random.default_rng(42), np.random.default_rng(42)
    for k, pose in enumerate(_random_poses(w, 200, np.random.default_rng(7))):
        t = 0.2 * k
        u_fused = fused.integrate_simulated(lidar, pose, rng_fused if noisy else None, t)
        u_plain = plain.integrate(lidar.scan(pose, rng_plain if noisy else None), lidar_config.max_range, t)
        assert u_fused == u_plain, k
        _assert_same_map(fused, plain)
        assert not fused._pending.any(), k  # the fused scan's window held every cell it marked
    assert fused.explored_cells > 0
    # the two generators were drawn from equally often
    assert rng_fused.random() == rng_plain.random()


@pytest.mark.parametrize("path", ["integrate_simulated", "integrate"])
def test_a_noise_free_beam_marks_every_cell_it_crosses_before_the_wall_free(path: str) -> None:
    """Sweep the robot along a corridor toward a wall at x = 3.0 m: every cell between the robot
    and the wall is crossed by the +x beam and must be mapped FREE, the wall cell OCCUPIED."""
    world = corridor()
    lidar = Lidar(world, LidarConfig(num_beams=1))
    missing = []
    for x in np.linspace(0.1, 2.5, 241):
        mapper = LogOddsMapper(world)
        pose = Pose(float(x), 0.51, 0.0)
        if path == "integrate":
            mapper.integrate(lidar.scan(pose, None), lidar.config.max_range)
        else:
            mapper.integrate_simulated(lidar, pose, None)
        col = int(x / RES)
        assert mapper.state[10, 60] == OCC
        if not np.all(mapper.state[10, col:60] == FREE):
            missing.append(round(float(x), 4))
    assert missing == []


@pytest.mark.parametrize("path", ["integrate_simulated", "integrate"])
def test_a_scan_of_the_most_beams_allowed_counts_its_passes_below_the_hit_bit(path: str) -> None:
    """Every beam of a scan leaves the robot's own cell: with MAX_BEAMS beams its pass count must
    stay below the HIT bit, or the cell would be taken for a hit (it was, from 16,384 beams up)."""
    assert MAX_BEAMS < HIT
    world = corridor()
    lidar = Lidar(world, LidarConfig(num_beams=MAX_BEAMS))
    mapper = LogOddsMapper(world)
    pose = Pose(10.5 * RES, 10.5 * RES, 0.0)
    if path == "integrate":
        mapper.integrate(lidar.scan(pose, None), lidar.config.max_range)
    else:
        mapper.integrate_simulated(lidar, pose, None)
    assert mapper.state[10, 10] == FREE
    assert mapper.logodds[10, 10] == np.float32(mapper.config.miss)


def test_integrate_refuses_a_scan_of_more_beams_than_its_pass_count_can_hold() -> None:
    n = MAX_BEAMS + 1
    scan = beam_scan(Pose(0.5, 0.5, 0.0), [1.0] * n, list(np.linspace(0.0, 2 * math.pi, n, endpoint=False)))
    with pytest.raises(ValueError, match="16,384"):
        LogOddsMapper(corridor()).integrate(scan, 3.5)


@pytest.mark.parametrize("length", range(1, 7))
def test_the_default_rule_classifies_a_cell_as_gmapping_does(length: int) -> None:
    """After any sequence of scans that end in a cell (hits) or pass it, the cell is occupied when
    3 x hits > passes (slam_gmapping's occ_thresh 0.25 on hits / visits) and free when
    3 x hits < passes; configs/mapper_gmapping_ratio.yaml is the same rule. The hysteresis preset
    (the default before 2026-11-26) keeps a cell free after a pass and then a hit, which is how
    range noise left holes in walls."""
    assert load_sim_config(CONFIGS / "mapper_gmapping_ratio.yaml").mapper == MapperConfig()
    pose = Pose(10.5 * RES, 10.5 * RES, 0.0)
    scans = {"hit": beam_scan(pose, [0.5], [0.0]), "pass": beam_scan(pose, [0.8], [0.0])}  # cell (10, 20)
    for sequence in itertools.product(("hit", "pass"), repeat=length):
        hits, passes = sequence.count("hit"), sequence.count("pass")
        if 3 * hits == passes:
            continue  # a tie keeps the cell's class; Gmapping calls it free
        mapper = LogOddsMapper(corridor())
        for kind in sequence:
            mapper.integrate(scans[kind], 3.5)
        assert mapper.state[10, 20] == (OCC if 3 * hits > passes else FREE), sequence
    hysteresis = load_sim_config(CONFIGS / "mapper_hysteresis.yaml").mapper
    assert hysteresis != MapperConfig() and hysteresis.usable_range == MapperConfig().usable_range
    before = LogOddsMapper(corridor(), hysteresis)
    for kind in ("pass", "hit"):
        before.integrate(scans[kind], 3.5)
    assert before.state[10, 20] == FREE


def test_integrate_simulated_rejects_a_lidar_of_another_world() -> None:
    mapper = LogOddsMapper(corridor())
    with pytest.raises(ValueError, match="shape"):
        mapper.integrate_simulated(Lidar(corridor(cols=90, wall_col=70)), Pose(0.5, 0.5, 0.0), None)


# --------------------------------------------------------------------- the exported, growing map
def test_exported_map_starts_around_the_robot_and_grows_as_it_moves() -> None:
    w = office(2)
    origin = (-4.0, 1.5)
    grid = OccupancyGrid(np.asarray(w.grid.data).copy(), RES, origin)
    lidar = Lidar(grid)
    mapper = LogOddsMapper(grid)
    before = mapper.occupancy_grid()
    assert before.shape == grid.shape and np.all(before.data == UNKNOWN)  # nothing seen: whole extent
    free = np.argwhere(grid.data == FREE)
    rng = np.random.default_rng(0)
    previous: tuple[int, int, int, int] | None = None
    for k in range(25):
        r, c = free[rng.integers(len(free))]
        x, y = grid.cell_to_world(r, c)
        mapper.integrate_simulated(lidar, Pose(x, y, 0.0), rng, float(k))
        bounds = mapper.known_bounds
        assert bounds is not None
        r0, r1, c0, c1 = bounds
        if k == 0:
            # the first map covers the usable range (3 m = 60 cells) around the robot at most
            assert r0 >= r - 61 and r1 <= r + 61 and c0 >= c - 61 and c1 <= c + 61
            assert (r1 - r0 + 1) * (c1 - c0 + 1) < grid.data.size
        if previous is not None:
            p0, p1, q0, q1 = previous
            assert r0 <= p0 and r1 >= p1 and c0 <= q0 and c1 >= q1  # only grows
        previous = bounds
        for margin in (0, 1, 3):
            exported = mapper.occupancy_grid(margin=margin)
            e0, e1 = max(r0 - margin, 0), min(r1 + margin, grid.height - 1)
            f0, f1 = max(c0 - margin, 0), min(c1 + margin, grid.width - 1)
            assert exported.shape == (e1 - e0 + 1, f1 - f0 + 1)
            assert exported.resolution == RES
            assert exported.origin == pytest.approx((origin[0] + f0 * RES, origin[1] + e0 * RES))
            np.testing.assert_array_equal(exported.data, mapper.state[e0 : e1 + 1, f0 : f1 + 1])
            # every exported cell's centre lands on the same cell of the world-sized map
            for rr, cc in ((0, 0), (exported.height - 1, exported.width - 1), (exported.height // 2, 3)):
                wr, wc = grid.world_to_cell(*exported.cell_to_world(rr, cc))
                assert (wr, wc) == (rr + e0, cc + f0)
                assert exported.data[rr, cc] == mapper.state[wr, wc]
    # the robot's cell is known in the export and sits where the world puts it
    exported = mapper.occupancy_grid()
    er, ec = exported.world_to_cell(x, y)
    assert exported.in_bounds(er, ec) and exported.data[er, ec] == FREE
    state_before = mapper.state.copy()
    exported.data[...] = OCC  # a copy: the mapper is not changed through it
    np.testing.assert_array_equal(mapper.state, state_before)


# --------------------------------------------------------------------------------------- gating
def test_wants_scan_defaults_are_gmapping_settings() -> None:
    c = MapperConfig()
    assert (c.temporal_update, c.linear_update, c.angular_update, c.usable_range) == (0.5, 1.0, 0.2, 3.0)


def _mapper_after_first_scan(config: MapperConfig | None = None) -> tuple[LogOddsMapper, Pose]:
    world = corridor()
    mapper = LogOddsMapper(world, config)
    pose = Pose(1.0, 0.5, 0.5)
    assert mapper.wants_scan(pose, 0.0)  # the first scan: always
    mapper.integrate(beam_scan(pose, [0.5], [0.0]), max_range=3.5, time_s=10.0)
    return mapper, pose


@pytest.mark.parametrize(
    ("dx", "dy", "dtheta", "dt", "wanted"),
    [
        (0.0, 0.0, 0.0, 0.0, False),
        (0.0, 0.0, 0.0, 0.3, False),
        (0.0, 0.0, 0.0, 0.49, False),
        (0.0, 0.0, 0.0, 0.5, True),  # temporal_update
        (0.0, 0.0, 0.0, 2.0, True),
        (0.99, 0.0, 0.0, 0.1, False),
        (1.0, 0.0, 0.0, 0.1, True),  # linear_update
        (0.6, 0.8, 0.0, 0.1, True),  # 1.0 m diagonally
        (0.0, -1.2, 0.0, 0.1, True),
        (0.0, 0.0, 0.19, 0.1, False),
        (0.0, 0.0, 0.2, 0.1, True),  # angular_update
        (0.0, 0.0, -0.25, 0.1, True),
        (0.0, 0.0, 2 * math.pi, 0.1, False),  # a full turn is no turn
        (0.0, 0.0, 2 * math.pi - 0.1, 0.1, False),  # -0.1 rad after wrapping
    ],
)
def test_wants_scan_time_distance_rotation_triggers(
    dx: float, dy: float, dtheta: float, dt: float, wanted: bool
) -> None:
    mapper, pose = _mapper_after_first_scan()
    moved = Pose(pose.x + dx, pose.y + dy, pose.theta + dtheta)
    assert mapper.wants_scan(moved, 10.0 + dt) is wanted


def test_wants_scan_across_the_angle_wrap() -> None:
    world = corridor()
    mapper = LogOddsMapper(world)
    mapper.integrate(beam_scan(Pose(1.0, 0.5, 3.1), [0.5], [0.0]), max_range=3.5, time_s=0.0)
    assert not mapper.wants_scan(Pose(1.0, 0.5, -3.1), 0.1)  # 0.083 rad apart through +-pi
    assert mapper.wants_scan(Pose(1.0, 0.5, -2.9), 0.1)  # 0.283 rad apart


def test_temporal_update_zero_disables_the_time_trigger() -> None:
    mapper, pose = _mapper_after_first_scan(MapperConfig(temporal_update=0.0))
    assert not mapper.wants_scan(pose, 1e6)
    assert mapper.wants_scan(Pose(pose.x + 1.0, pose.y, pose.theta), 10.0)


def test_gating_measures_from_the_last_processed_scan() -> None:
    mapper, pose = _mapper_after_first_scan()
    # a second scan at +0.6 m (processed because time passed) resets the reference pose
    second = Pose(pose.x + 0.6, pose.y, pose.theta)
    mapper.integrate(beam_scan(second, [0.5], [0.0]), max_range=3.5, time_s=10.6)
    assert not mapper.wants_scan(Pose(pose.x + 1.2, pose.y, pose.theta), 10.7)  # 0.6 m from the last
    assert mapper.wants_scan(Pose(pose.x + 1.6, pose.y, pose.theta), 10.7)


# ----------------------------------------------------------------------------------- mark_occupied
def test_mark_occupied_sets_cells_occupied_and_counts_them_once() -> None:
    world = corridor()
    explorable = np.zeros(world.shape, bool)
    explorable[5:15, 5:15] = True
    mapper = LogOddsMapper(world, explorable=explorable)
    mapper.mark_occupied(np.array([], np.int64), np.array([], np.int64))
    assert mapper.known_bounds is None and mapper.explored_cells == 0
    rows, cols = np.array([6, 7, 16]), np.array([6, 7, 30])
    mapper.mark_occupied(rows, cols)
    assert np.all(mapper.state[rows, cols] == OCC)
    assert np.all(mapper.logodds[rows, cols] == np.float32(mapper.config.clamp_max))
    assert mapper.seen[rows, cols].all()
    assert mapper.explored_cells == 2  # (16, 30) is not explorable
    assert mapper.known_bounds == (6, 16, 6, 30)
    assert np.count_nonzero(mapper.state != UNKNOWN) == 3
    mapper.mark_occupied(rows, cols)  # again: nothing new
    assert mapper.explored_cells == 2


def test_mark_occupied_overrides_a_free_cell() -> None:
    world = corridor(wall_col=100, cols=110)
    mapper = LogOddsMapper(world)
    pose = Pose(0.51, 0.51, 0.0)
    for _ in range(10):
        mapper.integrate(beam_scan(pose, [math.inf], [0.0]), max_range=3.5)
    assert mapper.state[10, 20] == FREE and mapper.logodds[10, 20] == np.float32(mapper.config.clamp_min)
    explored = mapper.explored_cells
    mapper.mark_occupied(np.array([10]), np.array([20]))
    assert mapper.state[10, 20] == OCC
    assert mapper.logodds[10, 20] > mapper.config.occupied_above
    assert mapper.explored_cells == explored  # already seen


# ------------------------------------------------------------------------------------------ config
@pytest.mark.parametrize(
    ("kwargs", "named"),
    [
        ({"usable_range": 0.0}, "0.0"),
        ({"usable_range": -1.0}, "-1.0"),
        ({"usable_range": math.nan}, "nan"),
        ({"linear_update": 0.0}, "0.0"),
        ({"angular_update": -0.2}, "-0.2"),
        ({"angular_update": math.nan}, "nan"),
        ({"hit": -0.5}, "-0.5"),
        ({"hit": 0.0}, "0.0"),
        ({"miss": 0.3}, "0.3"),
        ({"miss": -0.005}, "-0.005"),  # one pass would leave a cell unknown: the first scan maps nothing free
        ({"clamp_min": -0.005}, "-0.005"),  # above free_below
        ({"free_below": 0.2}, "0.2"),
        ({"occupied_above": -0.1}, "-0.1"),
        ({"occupied_above": 5.0}, "5.0"),  # above clamp_max
        ({"clamp_max": 0.005}, "0.005"),  # below occupied_above
        ({"clamp_max": math.inf}, "inf"),
        ({"hit": math.inf}, "inf"),
        ({"clamp_min": -math.inf}, "-inf"),
    ],
)
def test_bad_mapper_config_raises_config_error_naming_the_value(kwargs: dict[str, float], named: str) -> None:
    with pytest.raises(ConfigError, match=named.replace(".", r"\.")):
        MapperConfig(**kwargs)


def test_grid_from_text_fixture_round_trip(grid_from_text: Callable[..., OccupancyGrid]) -> None:
    g = grid_from_text(["#?", ".."])
    assert g.data[0, 0] == FREE and g.data[1, 0] == OCC and g.data[1, 1] == UNKNOWN


@pytest.mark.parametrize("noise_rel", [0.05, 1.5])
def test_fused_scan_matches_scan_then_integrate_even_with_huge_undershoots(noise_rel: float) -> None:
    """With 75 % range noise, readings fall metres short of the wall: the fused kernel must take
    back every mark beyond them (also past its ring of recent cells) exactly as the plain path."""
    from frontier_rl.core.world.catalog import generate_world

    world = generate_world("office", 5)
    lidar = Lidar(world.grid, LidarConfig(noise_rel=noise_rel, noise_abs=0.2))
    plain = LogOddsMapper(world.grid, explorable=world.explorable)
    fused = LogOddsMapper(world.grid, explorable=world.explorable)
    free = np.argwhere(world.explorable)
    pick = np.random.default_rng(1)
    rng_plain, rng_fused = np.random.default_rng(5), np.random.default_rng(5)
    for k in pick.choice(len(free), 60):
        x, y = world.grid.cell_to_world(*free[k])
        pose = Pose(x, y, pick.uniform(-3.0, 3.0))
        assert plain.integrate(lidar.scan(pose, rng_plain), lidar.config.max_range) == fused.integrate_simulated(
            lidar, pose, rng_fused
        )
        assert not fused._pending.any()  # its window held every cell it marked, long readings too
    np.testing.assert_array_equal(plain.logodds, fused.logodds)
    np.testing.assert_array_equal(plain.state, fused.state)


# ------------------------------------------------------------------------------- map merging
UNK, FREE, OCC = CellState.UNKNOWN, CellState.FREE, CellState.OCCUPIED


@pytest.mark.parametrize(
    ("mine", "theirs", "merged"),
    [
        # (class, log-odds, looks) of this map's cell, of the other map's, and the class merged
        ((UNK, 0.0, 0), (UNK, 0.0, 0), UNK),
        ((UNK, 0.0, 0), (FREE, -0.25, 1), FREE),
        ((UNK, 0.0, 0), (OCC, 0.75, 1), OCC),
        ((FREE, -0.25, 1), (UNK, 0.0, 0), FREE),
        ((FREE, -1.0, 4), (OCC, 0.75, 1), FREE),  # one stray hit does not undo four passes
        ((OCC, 0.75, 1), (FREE, -1.0, 4), FREE),  # ... in either direction
        ((OCC, 3.5, 14), (FREE, -1.0, 4), OCC),  # a wall seen often stays
        ((FREE, -0.25, 1), (OCC, 0.75, 1), OCC),  # a tie: the higher log-odds
        ((OCC, 0.0, 4), (FREE, 0.0, 4), OCC),  # ... then occupied
        ((FREE, 0.0, 4), (OCC, 0.0, 4), OCC),
    ],
)
def test_a_merge_takes_the_cell_the_other_map_looked_at_more(
    mine: tuple[int, float, int], theirs: tuple[int, float, int], merged: int
) -> None:
    grid = OccupancyGrid(np.full((2, 3), FREE, np.int8), 0.05)
    a, b = LogOddsMapper(grid), LogOddsMapper(grid)
    for mapper, (cls, value, looks) in ((a, mine), (b, theirs)):
        mapper.state[:], mapper.logodds[:], mapper.looks[:] = cls, value, looks
    a.merge_from(b)
    assert np.all(a.state == merged)
    winner = theirs if merged != mine[0] else mine
    assert np.all(a.looks == max(mine[2], theirs[2])) and np.all(a.logodds == np.float32(winner[1]))


def _merge_states(a: LogOddsMapper, b: LogOddsMapper) -> NDArray[np.int8]:
    """The merge rule, array-wise (the reference for the compiled merge): b's cell where b knows it
    and looked at it more often, or as often with a higher log-odds, or the same and occupied."""
    tie = b.looks == a.looks
    same = tie & (b.logodds == a.logodds)
    take = (b.state != UNK) & (
        (b.looks > a.looks) | (tie & (b.logodds > a.logodds)) | (same & (b.state == OCC) & (a.state != OCC))
    )
    return np.where(take, b.state, a.state).astype(np.int8)


def test_a_stray_hit_does_not_ratchet_between_two_robots() -> None:
    """Merged both ways, a cell one robot saw occupied once and the other free four times ends
    free in both maps (with the class rule, occupied > free, the stray wall spread to the other
    robot at once and came back at every merge for good: about 400 walls in free space on each
    robot's map of a 4-robot office episode, against 0-4 for one robot alone)."""
    grid = OccupancyGrid(np.full((1, 1), FREE, np.int8), 0.05)
    a, b = LogOddsMapper(grid), LogOddsMapper(grid)
    a.state[:], a.logodds[:], a.looks[:] = OCC, 0.75, 1
    b.state[:], b.logodds[:], b.looks[:] = FREE, -1.0, 4
    a.merge_from(b)
    b.merge_from(a)
    assert a.state[0, 0] == b.state[0, 0] == FREE


def _scanned(world: World, pose: Pose) -> LogOddsMapper:
    mapper = LogOddsMapper(world.grid, explorable=world.explorable)
    mapper.integrate_simulated(Lidar(world.grid), pose, None)
    return mapper


def test_mappers_merge_by_the_rule_and_count_what_they_gain() -> None:
    world = generate_world("office", 2)
    free = np.argwhere(world.explorable)
    first = world.grid.cell_to_world(*free[0])
    last = world.grid.cell_to_world(*free[-1])
    a, b = _scanned(world, Pose(*first, 0.0)), _scanned(world, Pose(*last, 0.0))
    expected = _merge_states(a, b)
    before = a.explored_cells
    gained = a.merge_from(b)
    assert np.array_equal(a.state, expected)
    assert gained > 0 and a.explored_cells == before + gained
    assert a.explored_cells == int(np.count_nonzero((a.state != UNK) & world.explorable))
    r0, r1, c0, c1 = a.known_bounds  # type: ignore[misc]
    rows, cols = np.nonzero(a.state != UNK)
    assert (r0, r1, c0, c1) == (rows.min(), rows.max(), cols.min(), cols.max())
    assert a.merge_from(b) == 0  # merging again changes nothing
    b.merge_from(a)
    assert np.array_equal(a.state, b.state)  # both robots now hold the same map


@pytest.mark.parametrize("window", [None, (0, 40, 0, 60), (-52, 73, -3, 60)])
def test_walls_a_teammate_touched_are_merged_as_touched(window: tuple[int, int, int, int] | None) -> None:
    """A wall a robot bumped into is never thinned by the narrow-passage recovery; after a merge
    the other robot knows that too (within the merged window, which may start before the map, as
    a window around a robot near its edge does: the touched walls were then not merged)."""
    world = generate_world("office", 2)
    a, b = LogOddsMapper(world.grid), LogOddsMapper(world.grid)
    a.state[10, 20], a.logodds[10, 20], a.looks[10, 20] = FREE, -2.0, 1000  # however often it was seen free
    b.mark_occupied(np.array([10, 100]), np.array([20, 150]))
    a.merge_from(b, window)
    assert a.state[10, 20] == OCC
    assert a.felt[10, 20]
    assert a.felt[100, 150] == (window is None)  # outside the window: not merged
    assert int(a.felt.sum()) == (2 if window is None else 1)
