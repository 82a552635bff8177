"""Last looks: before an episode ends, frontier clusters too small to be candidates through which
the robot saw floor it cannot drive to, looked through once more from the cell that sees most.

The size filter (``min_frontier_cells``, the thesis's 4) drops clusters of a few cells as LiDAR
specks. A gap in a thin wall narrower than the robot, a window between rooms, is one too: on the
harder survey's ``brsu_c069`` 15 of 20 episodes stopped at 94 % of the space the robot could see,
12.8 m² behind such a gap of three or four cells. Taken as candidates all along, such clusters cost
the office a third of its speed, and on the robot's map a window looks like a speck at a wall's
foot or a streak's end: a few free cells beside unknown. What tells them apart is what the robot
saw through them: floor (:data:`LOOK_EVIDENCE_M2`) on the far side, farther than
:data:`LOOK_BEYOND_M` from anywhere it can reach, not the single-cell rays of a streak through
glass, and nothing beyond a wall's mass.

So when no candidate is left, each such cluster with that floor within the mapping range gets a
look: the reachable cell within a frontier goal's reach whose scan would see the most of the
unknown the cluster opens onto (:func:`~frontier_rl.core.frontiers.detection.visible_unknown`), if
at least :data:`LOOK_MIN_GAIN_M2`. The clusters one cell is best for make one look. Once a look has
paid (mapped :data:`LOOK_PAYOFF_M2` of floor), the building has such windows, and any cluster whose
unknown borders free space seen beyond may be one (``confirmed``), until a look taken on that word
maps less: then the looks need floor seen through their clusters again, and the first of those
that maps less ends the episode's looks. A look is recorded in the blacklist as a visit of its
clusters whatever it reveals, and no look is taken from near a goal already tried, so a cluster
gets at most two looks (visited twice it is unrevealable), each from another place.

Where the robot saw no floor beyond anything it can reach at all, nothing tells a window from a
speck, and on ``brsu_c069`` five of the seven episodes still below 99 % had passed its window only
at angles it could not see through. So such an episode gets *blind looks* (:func:`blind_looks`) at
the clusters whose best viewpoint would see a fortieth of the free space mapped
(:data:`BLIND_LOOK_SHARE`): more than any small cluster promises at the end of the office's, the
cluttered world's and the cave's episodes. Once one is taken they go on, whatever they show, until
one pays; that one counts as a paid look.

Where the robot's map still has frontiers when no candidate is left (each failed its tries, or no
costmap has a way there), the episode is about to give up on the unknown they open onto. Before it
does, each small cluster opening onto that same unknown gets a look if it promises
:data:`LOOK_MIN_GAIN_M2` of it, floor seen through it or not, and no miss ends them
(:func:`looks_into_unknown_left`): on ``uom_floor3`` a corridor 0.30 m wide, which the robot fits
into, has a mouth its map draws four cells wide, a cluster the size filter drops with no floor seen
through it, opening onto the unknown around the building that the fans of rays out of its rooms
(frontiers with no way there) open onto too. The office's episodes end with no frontier left, so
its specks (the wall-surface holes whose looks cost it 5 % of its time when taken freely) get none,
and a frontier left counts only when longer than :data:`LEFT_FRONTIER_MIN_CELLS`: a frontier of a
few cells more than a speck opens onto unknown no look maps either.

Then the frontiers given up after the audit's tries (:func:`spent_looks`) get looks too, from a
reachable cell away from every goal tried for them: on the harder survey's Willow Garage maps a
frontier given up after four failed legs through a gap narrower than the robot had 2.9 m² of
floor behind it that a cell the robot could reach sees. They need no floor seen through them (the
frontier is the robot's own evidence of free space there) and no look ends them: each is a visit,
so a frontier gets at most two. Such a look need promise only more than a speck
(:func:`spent_look_min_gain_m2`): a frontier given up with more unseen space than that beside it
ends the episode ``unreachable``, and on the harder survey those left with a path had nooks of
0.03-0.13 m² behind them (on ``gdc_3ne`` a slanted slot narrower than the robot, seen into from
neither end).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from frontier_rl.core.frontiers.blacklist import Blacklist
from frontier_rl.core.frontiers.detection import Frontiers, detect_frontiers
from frontier_rl.core.frontiers.fringe import labels_beside
from frontier_rl.core.sim.config import SimConfig, drop_cells_at
from frontier_rl.core.sim.look_views import (
    VIEWPOINT_STRIDE,
    best_looks,
    segments_opened_areas,
    unknown_regions,
    viewpoint_cells,
)
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose

LOOK_MIN_GAIN_M2 = 1.0
"""The least unknown area (m²) a look must promise: room for a person lying down (0.5 m by 2 m).
At the end of the office's episodes the small clusters promise at most 0.54 m²."""

LEFT_FRONTIER_MIN_CELLS = 10
"""The frontiers left (more than a speck each) whose unknown the looks of :func:`looks_into_unknown_left`
count have more than this many cells (of 0.05 m: half a metre; fewer on coarser cells, as
:func:`~frontier_rl.core.sim.config.drop_cells_at` counts them). Measured where those looks opened: in
each of the seven harder-survey episodes they brought to 99 % the largest frontier left had 25-146
cells; on the dungeon maps those left had 5-8, beside unknown the robot could not map, and their
looks cost up to twice an episode's time; on ``aws_bookstore`` 5-7, where they mapped 0.07-0.35 %
more of episodes already at 99.6 % or more, at 35-126 % more time."""

LOOK_BEYOND_M = 0.75
"""How far (m) from every cell the robot can reach the floor seen through a cluster (or, once a
look paid, the free space bordering its unknown) must lie: seen through the gap, on the wall's far
side. The unknown in a wall's mass borders only free cells the robot drove beside: at most 0.46 m
away at the end of the office's, the cluttered world's and the cave's episodes; beyond
``brsu_c069``'s window 1.0-3.0 m."""

LOOK_EVIDENCE_M2 = 0.02
"""How much floor seen beyond (m², cells whose eight neighbours are free: not the single rays of a
streak) must lie within the mapping range of a cluster for a look before one has paid. Measured: 0.022-0.13
m² beside the clusters at ``brsu_c069``'s window; at most 0.008 m² beside those ``aws_bookstore``'s
looks were taken for when any floor counted (within 3.5 m), where they mapped 0.02-0.09 m² each."""

LOOK_PAYOFF_M2 = 0.25
"""A look that maps less floor than this (m²) ends the episode's looks: the unknown the robot's
map offers is then most likely wall (behind glass, in a wall's mass), which a look at the next
cluster would not map either. One taken while a paid look's word held (``confirmed``) that maps
less ends only that word: the looks that need floor seen through their clusters go on. On
``brsu_c069`` the looks through its window mapped 0.3-3.5 m² each; on ``willow_2010`` and
``aws_bookstore``, whose streaks through glass are seen floor too, 0-0.09 m² (a few 0.14-0.61 m²)."""

BLIND_LOOK_SHARE = 0.025
"""The least unknown area a look must promise where the robot saw no floor beyond anything it can
reach (:func:`blind_looks`), as a share of the free space it has mapped: a look that may add a
fortieth to the map. At the end of the fingerprinted episodes of the office, the cluttered world
and the cave the small clusters promise at most 1.0 %, 0.9 % and 1.6 % of the free space mapped;
at ``brsu_c069``'s window, in the episodes that ended without a look, 3.5-7 %."""

BLIND_SCREEN_STRIDE = 5
"""How many times coarser (than :data:`~frontier_rl.core.sim.look_views.VIEWPOINT_STRIDE`) the
lattice of viewpoints is on which a blind look's clusters are screened first (half the promise
needed): 0.5 m, a 25th of the rays.
At the end of every office episode its sealed rooms pass the area check: their search cost a
third of the CPU time of 20 episodes of ``fixed:0.75`` casting every ray, 4 % casting only those
that can meet the unknown, 1.6 % screened too; the seven ``brsu_c069`` episodes the blind looks
are for reach 99 % screened."""


def may_look(grid: OccupancyGrid, reachable: NDArray[np.bool_]) -> bool:
    """Whether the robot saw enough floor beyond the ``reachable`` cells for a look anywhere (before
    a look has paid): at least :data:`LOOK_EVIDENCE_M2` of :func:`floor_seen_beyond`. Costmaps that
    let the robot reach more see less beyond, so the answer of the level the robot stands on holds
    for every level."""
    return len(floor_seen_beyond(grid, reachable)) * grid.resolution**2 >= LOOK_EVIDENCE_M2


def last_looks(
    grid: OccupancyGrid,
    pose: Pose,
    reachable: NDArray[np.bool_],
    config: SimConfig,
    blacklist: Blacklist,
    confirmed: bool = False,
) -> Frontiers:
    """The small frontier clusters of ``grid`` (those the size filter drops) worth a look from
    the cells a robot at ``pose`` can reach (``reachable``), each at the viewpoint that sees most
    of the unknown it opens onto; the clusters one viewpoint is best for make one frontier, so
    that one look is taken for all of them. Clusters visited twice (``blacklist``) are left out,
    and so are viewpoints near a goal tried before. Without ``confirmed`` (no look has paid yet) a
    cluster needs floor seen beyond it within the mapping range; with it, unknown that borders
    free space seen beyond anywhere."""
    regions = unknown_regions(grid)
    if confirmed:  # a look paid: any unknown beside space seen beyond may be a room
        labels, areas = regions
        areas[np.setdiff1d(np.arange(len(areas)), _regions_seen_beyond(grid, reachable, labels))] = 0.0
    small = _small_clusters(grid, pose, reachable, config, regions, LOOK_MIN_GAIN_M2)
    if len(small) == 0:
        return small
    floor = None if confirmed else floor_seen_beyond(grid, reachable)
    return _small_cluster_looks(small, pose, reachable, config, blacklist, regions, floor, LOOK_MIN_GAIN_M2)


def blind_looks(
    grid: OccupancyGrid, pose: Pose, reachable: NDArray[np.bool_], config: SimConfig, blacklist: Blacklist
) -> Frontiers:
    """The looks of :func:`last_looks` where the robot saw no floor beyond anything it can reach:
    at the small clusters whose best viewpoint would see at least :data:`BLIND_LOOK_SHARE` of the
    free space mapped (and :data:`LOOK_MIN_GAIN_M2`) of the unknown they open onto, whether or not
    floor was seen through them."""
    mapped_m2 = np.count_nonzero(grid.data == CellState.FREE) * grid.resolution**2
    least_m2 = max(BLIND_LOOK_SHARE * mapped_m2, LOOK_MIN_GAIN_M2)
    regions = unknown_regions(grid)
    small = _small_clusters(grid, pose, reachable, config, regions, least_m2)
    if len(small) == 0:
        return small
    return _small_cluster_looks(small, pose, reachable, config, blacklist, regions, None, least_m2, BLIND_SCREEN_STRIDE)


def looks_into_unknown_left(
    grid: OccupancyGrid, pose: Pose, reachable: NDArray[np.bool_], config: SimConfig, blacklist: Blacklist
) -> Frontiers:
    """The looks of :func:`last_looks` at the small clusters that open onto an unknown region a
    frontier of ``grid`` opens onto (one of more than :data:`LEFT_FRONTIER_MIN_CELLS`), promising
    :data:`LOOK_MIN_GAIN_M2` of such regions, whether or not floor was seen through them. Asked when
    no candidate is left: each such frontier is one the robot is about to give up on, and these are
    the last views into what lies behind it."""
    labels, areas = unknown_regions(grid)
    least_cells = drop_cells_at(LEFT_FRONTIER_MIN_CELLS, grid.resolution)  # above any speck size
    left = detect_frontiers(grid, pose, None, least_cells, config.frontier_segment_length)
    if len(left) == 0:
        return left
    cells = np.vstack([left.cells_of(i) for i in range(len(left))])
    kept = np.zeros(len(areas), np.bool_)
    kept[labels_beside(labels, cells[:, 0], cells[:, 1])] = True
    regions = (labels, np.where(kept, areas, 0.0))  # a look counts only those regions
    small = _small_clusters(grid, pose, reachable, config, regions, LOOK_MIN_GAIN_M2)
    if len(small) == 0:
        return small
    return _small_cluster_looks(small, pose, reachable, config, blacklist, regions, None, LOOK_MIN_GAIN_M2)


def _small_clusters(
    grid: OccupancyGrid,
    pose: Pose,
    reachable: NDArray[np.bool_],
    config: SimConfig,
    regions: tuple[NDArray[np.int32], NDArray[np.float64]],
    least_m2: float,
) -> Frontiers:
    """The frontier clusters of ``grid`` the size filter drops that open onto at least
    ``least_m2`` of the unknown ``regions`` (:func:`~frontier_rl.core.sim.look_views.segments_opened_areas`)
    and that a robot at ``pose`` can get to see from the ``reachable`` cells. The area is checked
    first: at the end of an office episode some 80 specks are left, and looking for the cells that
    see each was most of the time spent finding them."""
    reach = min(config.frontier_goal_reach, config.mapping_range)
    drop = config.drop_cells(grid.resolution)

    def worth_a_look(cells: NDArray[np.int64], sizes: NDArray[np.int64]) -> NDArray[np.bool_]:
        ends = np.cumsum(sizes)
        spans = np.column_stack((ends - sizes, ends))
        # with room for rounding
        return np.asarray((sizes <= drop) & (segments_opened_areas(cells, spans, regions) >= least_m2 - 1e-9))

    return detect_frontiers(grid, pose, reachable, 0, config.frontier_segment_length, reach, worth_a_look)


def _small_cluster_looks(
    small: Frontiers,
    pose: Pose,
    reachable: NDArray[np.bool_],
    config: SimConfig,
    blacklist: Blacklist,
    regions: tuple[NDArray[np.int32], NDArray[np.float64]],
    floor: NDArray[np.int64] | None,
    least_m2: float,
    screen_stride: int = 1,
) -> Frontiers:
    """The looks at the ``small`` clusters not visited twice that promise ``least_m2`` of the
    unknown ``regions`` they open onto; where ``floor`` (cells seen beyond) is given, only at those
    with :data:`LOOK_EVIDENCE_M2` of it within the mapping range. With a ``screen_stride`` above 1,
    only those whose viewpoints on a lattice that many times coarser promise half of it are searched."""
    grid = small.grid
    evidence = LOOK_EVIDENCE_M2 / grid.resolution**2
    sight = config.mapping_range / grid.resolution
    chosen = []
    for i in range(len(small)):
        cells = small.cells_of(i)
        if blacklist.history_of(grid.cells_to_world(cells))[1]:  # looked at twice (or reached in vain)
            continue
        if floor is not None and np.count_nonzero(np.hypot(*(floor - cells.mean(axis=0)).T) <= sight) < evidence:
            continue  # no floor seen through it: a speck at a wall's foot, or rays through glass
        chosen.append(i)
    if not chosen:
        return small.subset(np.zeros(len(small), np.bool_))
    views = viewpoint_cells(reachable, grid, blacklist.tried_near)
    if screen_stride > 1:
        coarse = views[np.all(views % (VIEWPOINT_STRIDE * screen_stride) == 0, axis=1)]
        screened = best_looks(grid, small, chosen, regions, coarse, config, least_m2 / 2)
        chosen = sorted(i for members in screened.values() for i in members)
    return _looks_at(small, best_looks(grid, small, chosen, regions, views, config, least_m2), pose)


def spent_looks(
    grid: OccupancyGrid, pose: Pose, reachable: NDArray[np.bool_], config: SimConfig, blacklist: Blacklist
) -> Frontiers:
    """The frontiers a robot at ``pose`` can reach (``reachable``; larger than the drop size) but
    those visited twice (``blacklist``), each at the viewpoint that sees most of the unknown it opens
    onto, if more than a speck (:func:`spent_look_min_gain_m2`), away from the views had and the
    goals that used up the audit's budget (``Blacklist.spent_near``: a look whose leg aborted is
    offered again, as a leg to a frontier is retried); the frontiers one viewpoint is best for make
    one. Asked when no candidate is left, so that each is a frontier given up after the audit's
    tries: a last look from elsewhere at one the robot could not get to (through a gap narrower
    than itself, with a room seen through it)."""
    reach = min(config.frontier_goal_reach, config.mapping_range)
    drop = config.drop_cells(grid.resolution)
    given_up = detect_frontiers(grid, pose, reachable, drop, config.frontier_segment_length, reach)
    chosen = [
        i
        for i in range(len(given_up))
        if not blacklist.history_of(grid.cells_to_world(given_up.cells_of(i)))[1]  # not visited twice
    ]
    if not chosen:
        return given_up.subset(np.zeros(0, np.int64))
    labels, areas = unknown_regions(grid)
    views = viewpoint_cells(reachable, grid, blacklist.spent_near)
    least = spent_look_min_gain_m2(config, grid.resolution)
    return _looks_at(given_up, best_looks(grid, given_up, chosen, (labels, areas), views, config, least), pose)


def spent_look_min_gain_m2(config: SimConfig, resolution: float) -> float:
    """The least unknown area (m²) a look at a frontier given up must promise on a map of
    ``resolution`` m cells: one cell more than a speck (``config.speck_cells``), the unseen space
    beside a frontier left that ends an episode ``unreachable``. Not :data:`LOOK_MIN_GAIN_M2`: a
    frontier the robot failed to reach is its own evidence of space, and left unlooked-at with a
    path it is space given up."""
    return (config.speck_cells(resolution) + 1) * resolution * resolution


def _looks_at(small: Frontiers, groups: dict[tuple[int, int], list[int]], pose: Pose) -> Frontiers:
    """One frontier per viewpoint of ``groups``: the clusters of ``small`` it is the best look at,
    together (their cells, their size, their size-weighted centre), its goal the viewpoint."""
    flat: list[NDArray[np.int64]] = []
    spans: list[tuple[int, int]] = []
    centres: list[NDArray[np.float64]] = []
    sizes: list[int] = []
    nearest: list[float] = []
    for members in groups.values():
        start = sum(len(cells) for cells in flat)
        flat.extend(small.flat_cells[small.spans[i, 0] : small.spans[i, 1]] for i in members)
        spans.append((start, start + int(small.sizes[members].sum())))
        weights = small.sizes[members].astype(np.float64)
        centres.append(weights @ small.centers[members] / weights.sum())
        sizes.append(int(weights.sum()))
        nearest.append(float(small.min_distances[members].min()))
    xy = np.asarray(centres, np.float64).reshape(-1, 2)
    return Frontiers(
        small.grid,
        xy,
        np.asarray(sizes, np.int64),
        np.hypot(xy[:, 0] - pose.x, xy[:, 1] - pose.y),
        np.asarray(nearest, np.float64),
        np.concatenate(flat) if flat else np.zeros(0, np.int64),
        np.asarray(spans, np.int64).reshape(-1, 2),
        np.asarray(list(groups), np.int64).reshape(-1, 2),
    )


def floor_seen_beyond(grid: OccupancyGrid, reachable: NDArray[np.bool_]) -> NDArray[np.int64]:
    """(k, 2) the cells (row, col) of floor seen farther than :data:`LOOK_BEYOND_M` from every
    ``reachable`` cell: free cells whose eight neighbours are free too (not the single rays of a
    streak through glass), on a wall's far side."""
    reach = LOOK_BEYOND_M / grid.resolution
    # the taxicab distance is never shorter: cells it puts within reach need no Euclidean one, nor
    # the erosion (on the office's maps, where every episode ends asking, none is left by then)
    free = grid.data == CellState.FREE
    floor = free & (np.asarray(ndimage.distance_transform_cdt(~reachable, "taxicab")) > reach)
    if floor.any():
        floor &= ndimage.binary_erosion(free, np.ones((3, 3), np.bool_))
        floor &= np.asarray(ndimage.distance_transform_edt(~reachable)) > reach
    return np.argwhere(floor).astype(np.int64)


def _regions_seen_beyond(
    grid: OccupancyGrid, reachable: NDArray[np.bool_], labels: NDArray[np.int32]
) -> NDArray[np.int64]:
    """The labels of the unknown regions that border free space seen farther than
    :data:`LOOK_BEYOND_M` from every ``reachable`` cell: what the robot saw through a gap."""
    beyond = np.asarray(ndimage.distance_transform_edt(~reachable)) * grid.resolution > LOOK_BEYOND_M
    seen = ndimage.binary_dilation(beyond & (grid.data == CellState.FREE), np.ones((3, 3), np.bool_))
    found = np.unique(labels[seen])
    return found[found > 0].astype(np.int64)
