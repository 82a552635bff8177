"""The last looks (issue 58): before an episode ends, a frontier cluster too small to be a candidate
that a reachable viewpoint would see a room's worth of unknown through (a gap in a thin wall
narrower than the robot) gets one look; specks do not, and no cluster gets two. A frontier given
up after its tries gets looks from elsewhere too, at most two. Where the robot saw no floor beyond
anything at all, blind looks go to the clusters that promise a fortieth of its map, until one pays;
before the robot gives up on the unknown a frontier left opens onto, each cluster opening onto it
that promises a person's room gets a look;
the search for a look's viewpoint finds what casting every ray on the whole map would."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from frontier_rl import load_world, make_policy, run_episode
from frontier_rl.core.frontiers.blacklist import AUDIT_BUDGET, Blacklist
from frontier_rl.core.frontiers.detection import Frontiers, detect_frontiers, visible_unknown
from frontier_rl.core.sim.candidates import Look, find_candidates, reachable_frontiers
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.look_state import LookState
from frontier_rl.core.sim.look_views import look_promise_cells, unknown_regions
from frontier_rl.core.sim.looks import (
    BLIND_LOOK_SHARE,
    LEFT_FRONTIER_MIN_CELLS,
    LOOK_MIN_GAIN_M2,
    LOOK_PAYOFF_M2,
    blind_looks,
    last_looks,
    looks_into_unknown_left,
    spent_look_min_gain_m2,
    spent_looks,
)
from frontier_rl.core.sim.navigator import Navigator
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.core.world.worlds import make_world

RES = 0.05
FREE, OCC, UNKNOWN = (np.int8(v) for v in (CellState.FREE, CellState.OCCUPIED, CellState.UNKNOWN))
GAP_ROWS = slice(38, 41)  # three cells, 0.15 m: narrower than the robot (0.21 m)


def window_map() -> OccupancyGrid:
    """A robot's map: a 3 m x 4 m room seen, walled; its right wall one cell thick with a gap of
    three cells at y = 1.9-2.05 m, and behind it a room not seen but for a patch of floor 2 m
    beyond, seen through the gap (no frontier goal sees it: the way there is unknown)."""
    data = np.full((82, 130), UNKNOWN, np.int8)
    data[:, :62] = OCC
    data[1:81, 1:61] = FREE
    data[GAP_ROWS, 61] = FREE
    data[35:44, 100:109] = FREE
    return OccupancyGrid(data, RES)


def _blacklist() -> Blacklist:
    return Blacklist(
        radius=0.25, max_failures=SimConfig().navigation.max_goal_failures, resolution=RES, origin=(0.0, 0.0)
    )


def _looks(grid: OccupancyGrid, blacklist: Blacklist | None = None, confirmed: bool = False) -> tuple[Pose, Frontiers]:
    config, pose = SimConfig(), Pose(0.5, 0.5, 0.0)
    _, reachable, frontiers = reachable_frontiers(grid, pose, config)
    assert len(frontiers) == 0  # the gap is too small a cluster to be a candidate
    return pose, last_looks(grid, pose, reachable, config, blacklist or _blacklist(), confirmed)


def test_a_gap_in_a_thin_wall_gets_one_look_from_a_viewpoint_in_line_with_it() -> None:
    grid = window_map()
    _, looks = _looks(grid)
    assert len(looks) == 1 and looks.sizes[0] <= SimConfig().min_frontier_cells
    row, col = looks.goal_cells[0]
    gap_row = (GAP_ROWS.start + GAP_ROWS.stop - 1) / 2
    # the view through a slot: straight through it, from as near as the robot gets (the widest fan)
    assert abs(row - gap_row) <= 1 and 0 < (61 - col) * RES <= 0.2
    assert grid.data[row, col] == FREE


def test_specks_and_the_unknown_in_a_walls_mass_get_no_look() -> None:
    speck = window_map()
    speck.data[GAP_ROWS, 61] = OCC
    speck.data[40, 30] = UNKNOWN  # one unseen cell in the room: 0.0025 m², below the least gain
    assert LOOK_MIN_GAIN_M2 > RES**2
    assert len(_looks(speck)[1]) == 0
    unseen = window_map()
    unseen.data[:, 62:] = UNKNOWN  # nothing seen through the gap: a hole in a wall, to the robot
    assert len(_looks(unseen)[1]) == 0


def _into_unknown_left(grid: OccupancyGrid) -> Frontiers:
    config, pose = SimConfig(), Pose(0.5, 0.5, 0.0)
    _, reachable, frontiers = reachable_frontiers(grid, pose, config)
    assert len(frontiers) == 0
    return looks_into_unknown_left(grid, pose, reachable, config, _blacklist())


def test_a_hole_opening_onto_the_unknown_a_frontier_left_opens_onto_gets_a_look() -> None:
    """``uom_floor3``'s corridor mouth: a cluster the size filter drops, nothing seen through it,
    opening onto the unknown that frontiers with no way there (rays out of a room) open onto too.
    Where no frontier is left (the office's episodes end so), a hole in a wall gets none."""
    hole = window_map()
    hole.data[:, 62:] = UNKNOWN  # nothing seen through the gap: a hole in a wall, to the robot
    assert len(_into_unknown_left(hole)) == 0
    rays = OccupancyGrid(hole.data.copy(), RES)
    rays.data[20, 62:80] = FREE  # a ray's streak through the wall: a frontier of 18 cells, no way there
    looks = _into_unknown_left(rays)
    assert len(looks) == 1 and set(looks.cells_of(0)[:, 1]) == {61}  # the gap's cells
    assert len(_looks(rays)[1]) == 0  # the looks at small clusters need floor seen through them
    apart = OccupancyGrid(rays.data.copy(), RES)
    apart.data[30, 62:] = OCC  # a wall beyond: the streak's unknown and the gap's are two regions
    assert len(_into_unknown_left(apart)) == 0


def test_a_frontier_left_a_few_cells_more_than_a_speck_opens_no_look() -> None:
    """On the dungeon maps a frontier left of 5-8 cells opened ten looks into unknown the robot
    could not map: a frontier left counts when longer than :data:`LEFT_FRONTIER_MIN_CELLS`."""
    config = SimConfig()
    for length, looked in ((LEFT_FRONTIER_MIN_CELLS - 2, False), (LEFT_FRONTIER_MIN_CELLS + 2, True)):
        rays = window_map()
        rays.data[:, 62:] = UNKNOWN
        rays.data[20, 62 : 62 + length] = FREE  # a ray's streak through the wall, no way there
        streak = detect_frontiers(rays, Pose(0.5, 0.5, 0.0), None, config.speck_cells(RES))
        assert len(streak) == 1 and config.speck_cells(RES) < streak.sizes[0] <= length + 2
        assert (len(_into_unknown_left(rays)) == 1) is looked, length


def test_the_looks_into_the_unknown_left_come_when_the_other_looks_are_over_and_no_miss_ends_them() -> None:
    hole = window_map()
    hole.data[:, 62:] = UNKNOWN
    hole.data[20, 62:80] = FREE  # a frontier with no way there, into the gap's unknown
    config, pose, blacklist = SimConfig(), Pose(0.5, 0.5, 0.0), _blacklist()
    levels = [find_candidates(hole, pose, config, blacklist, hole.data)]
    state = LookState()
    state.looked(0.0)  # a look through floor seen beyond missed: the looks at small clusters are over
    assert not state.looking
    for _ in range(2):  # each a visit: the gap is looked at twice at most
        cand = state.looks(levels, pose, config, blacklist)
        assert cand.looks is Look.UNKNOWN_LEFT and len(cand.frontiers) == 1
        gap = hole.cells_to_world(cand.frontiers.cells_of(0))
        blacklist.fail(*cand.frontiers.goals[0], hole.data, reached=True, frontier=gap)
    assert state.looks(levels, pose, config, blacklist).looks is Look.NONE


def test_floor_seen_beyond_the_mapping_range_takes_a_look_that_paid_first() -> None:
    far = window_map()
    far.data[35:44, 100:109] = UNKNOWN
    far.data[35:44, 121:130] = FREE  # the floor seen through the gap lies 3 m beyond it
    assert len(_looks(far)[1]) == 0  # none near enough: a look must first pay (frontier_rl.core.sim.looks)
    assert len(_looks(far, confirmed=True)[1]) == 1  # then the unknown beside any floor seen beyond


def _navigator() -> Navigator:
    world = make_world(window_map(), "window", start=Pose(0.5, 0.5, 0.0))
    return ExplorationSimulator(world, SimConfig(), np.random.default_rng(0)).navigator


def test_a_look_that_maps_little_ends_the_looks_and_one_that_pays_confirms_them() -> None:
    navigator = _navigator()
    assert navigator.look_state.looking and not navigator.look_state.confirmed
    navigator.looked(LOOK_PAYOFF_M2 / 2)  # a look through floor seen beyond that missed
    assert not navigator.look_state.looking and not navigator.look_state.confirmed
    navigator.looked(10.0)
    assert not navigator.look_state.looking  # for the rest of the episode
    navigator = _navigator()
    navigator.looked(LOOK_PAYOFF_M2)
    assert navigator.look_state.looking and navigator.look_state.confirmed


def test_a_miss_on_a_paid_looks_word_ends_those_looks_and_the_others_go_on() -> None:
    navigator = _navigator()
    navigator.looked(LOOK_PAYOFF_M2)  # paid: the next look needs no floor seen near its clusters
    navigator.looked(0.0)  # and missed
    # the looks through floor seen beyond go on
    assert navigator.look_state.looking and not navigator.look_state.confirmed
    navigator.looked(LOOK_PAYOFF_M2)
    assert navigator.look_state.looking and not navigator.look_state.confirmed  # none on a paid look's word again
    navigator.looked(0.0)
    assert not navigator.look_state.looking


def test_a_cluster_looked_at_once_gets_a_second_look_from_elsewhere_and_none_after() -> None:
    grid = window_map()
    looked = _blacklist()
    gap = grid.cells_to_world(np.array([[39, 61]]))
    first = _looks(grid, looked)[1]
    assert len(first) == 1
    looked.fail(*first.goals[0], grid.data, reached=True, frontier=gap)
    second = _looks(grid, looked)[1]
    assert len(second) == 1 and np.hypot(*(second.goals[0] - first.goals[0])) > looked.radius
    looked.fail(*second.goals[0], grid.data, reached=True, frontier=gap)
    assert len(_looks(grid, looked)[1]) == 0


def _blind(grid: OccupancyGrid) -> Frontiers:
    config, pose = SimConfig(), Pose(0.5, 0.5, 0.0)
    _, reachable, frontiers = reachable_frontiers(grid, pose, config)
    assert len(frontiers) == 0
    return blind_looks(grid, pose, reachable, config, _blacklist())


def test_a_gap_with_nothing_seen_through_it_gets_a_blind_look_where_it_promises_a_fortieth_of_the_map() -> None:
    unseen = window_map()
    unseen.data[:, 62:] = UNKNOWN  # nothing seen through the gap: no last look (above), but a blind one
    looks = _blind(unseen)
    assert len(looks) == 1 and abs(looks.goal_cells[0][0] - 39) <= 1 and 0 < (61 - looks.goal_cells[0][1]) * RES <= 0.2
    speck = window_map()
    speck.data[:, 61:] = OCC
    speck.data[40, 30] = UNKNOWN  # one unseen cell in the room promises 0.0025 m²
    assert len(_blind(speck)) == 0
    # the same gap in the wall of a 15 m x 15 m hall promises less than a fortieth of it
    large = np.full((302, 370), OCC, np.int8)
    large[1:301, 1:300] = FREE
    large[GAP_ROWS, 300] = FREE
    large[:, 301:] = UNKNOWN
    big = OccupancyGrid(large, RES)
    _, reachable, _ = reachable_frontiers(big, Pose(0.5, 0.5, 0.0), SimConfig())
    gap_rows = np.flatnonzero(big.data[:, 300] == FREE)
    gap = np.column_stack([gap_rows, np.full_like(gap_rows, 300)])
    promise_m2 = look_promise_cells(big, gap, reachable, SimConfig(), unknown_regions(big)) * RES**2
    mapped_m2 = np.count_nonzero(large == FREE) * RES**2
    assert LOOK_MIN_GAIN_M2 < promise_m2 < BLIND_LOOK_SHARE * mapped_m2 < 2 * promise_m2
    assert len(_blind(big)) == 0


def test_blind_looks_go_on_from_elsewhere_until_one_pays_and_that_one_confirms_the_looks() -> None:
    unseen = window_map()
    unseen.data[:, 62:] = UNKNOWN
    world = make_world(unseen, "window", start=Pose(0.5, 0.5, 0.0))
    sim = ExplorationSimulator(world, SimConfig(), np.random.default_rng(0))
    sim.mapper.state[:] = unseen.data  # the robot's map as drawn, all of it seen
    sim.mapper._bbox[:] = (0, unseen.shape[0] - 1, 0, unseen.shape[1] - 1)
    sim.navigator.forget()
    pose, gap = Pose(0.5, 0.5, 0.0), unseen.cells_to_world(np.array([[39, 61]]))
    goals = []
    for _ in range(2):  # a blind look that missed ends no look; the next is from elsewhere
        cand = sim.navigator.candidates(pose)
        assert cand.looks is Look.BLIND and len(cand.frontiers) == 1
        goals.append(cand.frontiers.goals[0])
        sim.blacklist.fail(*goals[-1], sim.mapper.state, reached=True, frontier=gap, viewed=True)
        sim.navigator.looked(0.0, blind=True)
        assert sim.navigator.look_state.looking and not sim.navigator.look_state.confirmed
    assert np.hypot(*(goals[1] - goals[0])) > sim.blacklist.radius
    assert sim.navigator.candidates(pose).looks is Look.NONE  # the gap was looked at twice
    navigator = _navigator()
    navigator.looked(LOOK_PAYOFF_M2, blind=True)
    assert navigator.look_state.looking and navigator.look_state.confirmed


def _given_up(closet: tuple[slice, slice] | None = None, speck: int = 0) -> tuple[OccupancyGrid, Blacklist, Frontiers]:
    """The window map with a gap of seven cells (0.35 m), a frontier, given up after the audit's
    budget of failed legs to its goal (with ``closet``, the unknown behind it is only those cells,
    walled in; with ``speck``, the gap is walled up and the frontier is round a square of ``speck``
    unknown cells in the middle of the room); and the last looks at it."""
    grid = window_map()
    grid.data[35:42, 61] = FREE
    if closet is not None:
        grid.data[:, 62:] = OCC
        grid.data[closet] = UNKNOWN
    if speck:
        grid.data[:, 61] = OCC
        side = math.isqrt(speck)
        grid.data[40 : 40 + side, 30 : 30 + side] = UNKNOWN
    config, pose = SimConfig(), Pose(0.5, 0.5, 0.0)
    _, reachable, frontiers = reachable_frontiers(grid, pose, config)
    assert len(frontiers) == 1  # the gap (or the speck) is a candidate
    blacklist, frontier = _blacklist(), grid.cells_to_world(frontiers.cells_of(0))
    for _ in range(AUDIT_BUDGET * blacklist.max_failures):
        blacklist.fail(*frontiers.goals[0], grid.data, frontier=frontier)
    return grid, blacklist, spent_looks(grid, pose, reachable, config, blacklist)


def test_a_frontier_given_up_gets_a_look_from_elsewhere_twice_at_most() -> None:
    grid, blacklist, looks = _given_up()
    assert len(looks) == 1 and looks.sizes[0] > SimConfig().min_frontier_cells
    tried = blacklist.entries[0].goals
    assert np.hypot(*(looks.goals[0] - tried[0])) > blacklist.radius and grid.data[tuple(looks.goal_cells[0])] == FREE
    gap = grid.cells_to_world(looks.cells_of(0))
    for visit in range(2):  # each look a visit that revealed nothing: then one from elsewhere, then none
        blacklist.fail(*looks.goals[0], grid.data, reached=True, frontier=gap)
        config, pose = SimConfig(), Pose(0.5, 0.5, 0.0)
        _, reachable, _ = reachable_frontiers(grid, pose, config)
        again = spent_looks(grid, pose, reachable, config, blacklist)
        assert len(again) == (1 - visit)
        if len(again):
            assert np.hypot(*(again.goals[0] - looks.goals[0])) > blacklist.radius
            looks = again


def test_a_look_whose_leg_aborted_is_offered_again_until_its_goal_has_used_the_budget() -> None:
    """A look whose leg aborted had no view: the same viewpoint is offered again (its goal failed
    twice, below the audit's budget); after a second abort the frontier has had its two looks."""
    grid, blacklist, looks = _given_up()
    config, pose = SimConfig(), Pose(0.5, 0.5, 0.0)
    _, reachable, _ = reachable_frontiers(grid, pose, config)
    gap, first = grid.cells_to_world(looks.cells_of(0)), looks.goals[0].copy()
    for aborted in range(2):  # as the simulator records a look whose leg aborted
        blacklist.fail(*first, grid.data)
        blacklist.fail(*first, grid.data, reached=True, frontier=gap, viewed=False)
        again = spent_looks(grid, pose, reachable, config, blacklist)
        assert len(again) == 1 - aborted
        if len(again):
            assert np.hypot(*(again.goals[0] - first)) <= blacklist.radius
    assert not blacklist.views_had(first[None, :])[0] and blacklist.spent_near(first[None, :])[0]


def test_a_frontier_given_up_onto_a_nook_gets_a_look_but_not_onto_a_speck() -> None:
    """A look at a frontier given up needs to promise more than a speck, not a person's room: a
    nook of 0.14 m² (11 x 5 cells) behind the gap gets one, a square of four cells (a speck) in
    the open does not."""
    config = SimConfig()
    speck = config.speck_cells(0.05)
    least = spent_look_min_gain_m2(config, 0.05)
    assert least == pytest.approx((speck + 1) * 0.05**2) and least < LOOK_MIN_GAIN_M2
    assert len(_given_up(closet=(slice(33, 44), slice(62, 67)))[2]) == 1
    assert speck == 4 and len(_given_up(speck=speck)[2]) == 0


def test_the_window_of_a_slam_map_is_looked_through(real_maps: Path) -> None:
    """``brsu_c069``: a 12.8 m² fan seen through a gap of three or four cells in a thin wall; the
    survey's episodes stopped at 94 % of the explorable space without the last looks."""
    world = load_world("brsu_c069", seed=0)
    result = run_episode(world, make_policy("nearest"), seed=0)
    assert result.coverage >= 0.99 and not result.truncated, result.summary()  # 0.9415 without the looks


def test_a_window_nothing_was_seen_through_gets_the_blind_look(real_maps: Path) -> None:
    """``brsu_c069`` by ``tour`` from seed 2: the robot never saw floor through the window (no last
    look), and stopped at 94.2 % of the explorable space before the blind look."""
    world = load_world("brsu_c069", seed=2)
    result = run_episode(world, make_policy("tour"), seed=2)
    assert result.coverage >= 0.99 and not result.truncated, result.summary()


def _every_ray_promise(grid: OccupancyGrid, cells: np.ndarray, reachable: np.ndarray, config: SimConfig) -> int:
    """What :func:`look_promise_cells` promises, by the definition: every ray from every reachable
    cell within a frontier goal's reach of the cluster, cast on the whole map."""
    labels, areas = unknown_regions(grid)
    beside = {int(labels[r + dr, c + dc]) for r, c in cells for dr in (-1, 0, 1) for dc in (-1, 0, 1)}
    target = np.isin(labels, [label for label in beside if label > 0 and areas[label] > 0])
    occupied = np.where(grid.data == OCC, OCC, FREE)
    state = np.where(target, UNKNOWN, occupied).astype(np.int8)
    views = np.argwhere(reachable)
    reach = min(config.frontier_goal_reach, config.mapping_range)
    views = views[np.hypot(*(views - cells.mean(axis=0)).T) * grid.resolution <= reach]
    if len(views) == 0:
        return 0
    origins = views[:, ::-1].astype(np.float64) + 0.5
    return int(visible_unknown(state, origins, config.lidar.num_beams, config.mapping_range / grid.resolution).max())


@pytest.mark.parametrize("seed", range(3))
def test_a_looks_promise_is_what_every_ray_would_see(seed: int) -> None:
    # the search casts only the rays that can meet the unknown, in the part of the map they reach:
    # it must find what casting every ray on the whole map finds, for each small cluster of a
    # map with rooms left unseen behind walls with holes
    rng = np.random.default_rng(seed)
    config, pose = SimConfig(), Pose(0.5, 0.5, 0.0)
    data = np.full((90, 140), FREE, np.int8)
    data[[0, -1], :], data[:, [0, -1]] = OCC, OCC
    for top, left in ((10, 30), (50, 80), (20, 100)):  # rooms walled round but for a few holes
        data[top : top + 22, left : left + 26] = OCC
        data[top + 1 : top + 21, left + 1 : left + 25] = UNKNOWN
        wall = np.argwhere(data[top : top + 22, left : left + 26] == OCC) + np.array([top, left])
        holes = wall[rng.choice(len(wall), 6, replace=False)]
        data[holes[:, 0], holes[:, 1]] = FREE
    grid = OccupancyGrid(data, RES)
    _, reachable, _ = reachable_frontiers(grid, pose, config)
    small = detect_frontiers(grid, pose, reachable, 0)
    assert len(small) >= 3
    regions = unknown_regions(grid)
    promised = [look_promise_cells(grid, small.cells_of(i), reachable, config, regions) for i in range(len(small))]
    assert promised == [_every_ray_promise(grid, small.cells_of(i), reachable, config) for i in range(len(small))]
    assert max(promised) > 0
