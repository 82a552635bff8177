"""Large buildings (30-60 m floors) as wall masks (``True`` = wall): a long main corridor, wings
along it, and on each side of the corridor in each wing a row of rooms, an open hall with pillars
or a warehouse with rows of shelving; some wings are split by a cross corridor.

Rescue sites are larger than the 12.5 m office maze: this is what a learned policy must hold on
when the frontiers are tens of metres apart. Lengths in metres, turned into cells with the
resolution; walls and doors follow :mod:`frontier_rl.core.world.layout` (walls at least 2
cells thick, every gap at least MIN_GAP_M wide); every zone opens onto the main corridor, so the
whole floor is connected.
"""

from __future__ import annotations

import numpy as np

from frontier_rl.core.world.layout import (
    MIN_GAP_M,
    ROOM_DOOR_M,
    BoolGrid,
    Rect,
    bordered,
    cells,
    pick_start,
    place_pillars,
    wall_cells,
)

CORRIDOR_M = (1.6, 2.4)  # main corridor clear width range (m)
CROSS_CORRIDOR_M = (1.4, 2.0)  # cross corridor clear width range (m)
WING_M = (8.0, 16.0)  # wing length range along the corridor (m)
ROOM_WIDTH_M = (3.0, 6.0)  # room width along the corridor (m)
BACK_ROOMS_FROM_M = 9.0  # zones deeper than this get a second row of rooms behind the first (m)
OPENING_M = (2.0, 4.0)  # width of a hall's or warehouse's opening onto the corridor (m)
SHELF_DEPTH_M = (0.6, 1.0)  # shelving row depth (m)
AISLE_M = (1.2, 2.2)  # aisle between shelving rows (m)
SHELF_END_M = 1.5  # free aisle at each end of a shelving row and across it (m)
PILLAR_SPACING_M = (4.0, 6.0)  # hall pillar grid spacing (m)
ZONE_KINDS = ("rooms", "hall", "warehouse")
ZONE_WEIGHTS = (0.5, 0.25, 0.25)


def _door(rng: np.random.Generator, occ: BoolGrid, wall: Rect, along_cols: bool, width: int, res: float) -> bool:
    """Open a gap ``width`` cells wide in ``wall`` (which runs along columns if ``along_cols``);
    False where the wall is too short for it."""
    m = cells(0.1, res)
    lo, hi = (wall.c0, wall.c1) if along_cols else (wall.r0, wall.r1)
    d = pick_start(rng, lo + m, hi - m, width)
    if d is None:
        return False
    if along_cols:
        occ[wall.r0 : wall.r1, d : d + width] = False
    else:
        occ[d : d + width, wall.c0 : wall.c1] = False
    return True


def _room_door(rng: np.random.Generator, occ: BoolGrid, wall: Rect, along_cols: bool, res: float) -> bool:
    return _door(rng, occ, wall, along_cols, cells(rng.uniform(*ROOM_DOOR_M), res), res)


def _rooms(rng: np.random.Generator, occ: BoolGrid, zone: Rect, front: Rect, t: int, res: float) -> None:
    """A row of rooms across ``zone`` (columns), each with a door in the ``front`` wall, some with a
    door to the next; a deep zone gets a second row behind, entered from the first."""
    bounds = [zone.c0]
    while zone.c1 - bounds[-1] > cells(2 * ROOM_WIDTH_M[0], res) + t:
        bounds.append(bounds[-1] + cells(rng.uniform(*ROOM_WIDTH_M), res))
        if zone.c1 - bounds[-1] < cells(ROOM_WIDTH_M[0], res) + t:
            bounds.pop()
            break
    bounds.append(zone.c1)
    depth = zone.r1 - zone.r0
    split = None
    if depth * res > BACK_ROOMS_FROM_M:
        half = zone.r0 + depth // 2 + int(rng.integers(-depth // 8, depth // 8 + 1))
        split = Rect(half, half + t, zone.c0, zone.c1)
        occ[split.r0 : split.r1, split.c0 : split.c1] = True
    for k in range(1, len(bounds) - 1):  # walls between neighbouring rooms
        occ[zone.r0 : zone.r1, bounds[k] : bounds[k] + t] = True
    for k in range(len(bounds) - 1):
        c0, c1 = bounds[k] + (t if k else 0), bounds[k + 1]
        _room_door(rng, occ, Rect(front.r0, front.r1, c0, c1), True, res)
        if split is not None:
            _room_door(rng, occ, Rect(split.r0, split.r1, c0, c1), True, res)
        if k + 1 < len(bounds) - 1 and rng.random() < 0.3:
            rows = (zone.r0, zone.r1) if split is None else (zone.r0, split.r0)
            _room_door(rng, occ, Rect(rows[0], rows[1], bounds[k + 1], bounds[k + 1] + t), False, res)


def _hall(rng: np.random.Generator, occ: BoolGrid, zone: Rect, front: Rect, res: float) -> None:
    """An open hall: one or two wide openings onto the corridor and a grid of pillars."""
    for _ in range(int(rng.integers(1, 3))):
        _door(rng, occ, front, True, cells(rng.uniform(*OPENING_M), res), res)
    step = cells(rng.uniform(*PILLAR_SPACING_M), res)
    centres = [
        (r, c) for r in range(zone.r0 + step // 2, zone.r1, step) for c in range(zone.c0 + step // 2, zone.c1, step)
    ]
    place_pillars(rng, occ, centres, len(centres), res)


def _warehouse(rng: np.random.Generator, occ: BoolGrid, zone: Rect, front: Rect, res: float) -> None:
    """Rows of shelving along the zone with aisles between, free aisles at their ends and, in long
    rows, a cross aisle; an opening onto the corridor."""
    _door(rng, occ, front, True, cells(rng.uniform(*OPENING_M), res), res)
    end, gap = cells(SHELF_END_M, res), cells(MIN_GAP_M, res)
    c0, c1 = zone.c0 + end, zone.c1 - end
    if c1 - c0 < cells(2.0, res):
        return
    cross = None
    if (c1 - c0) * res > 8.0:
        mid = int(rng.integers(c0 + (c1 - c0) // 3, c1 - (c1 - c0) // 3))
        cross = (mid, mid + end)
    r = zone.r0 + cells(rng.uniform(*AISLE_M), res)
    while True:
        depth = cells(rng.uniform(*SHELF_DEPTH_M), res)
        if r + depth + max(gap, cells(AISLE_M[0], res)) > zone.r1:
            break
        occ[r : r + depth, c0:c1] = True
        if cross is not None:
            occ[r : r + depth, cross[0] : cross[1]] = False
        r += depth + cells(rng.uniform(*AISLE_M), res)


def _zone(rng: np.random.Generator, occ: BoolGrid, zone: Rect, front: Rect, t: int, res: float) -> None:
    kind = ZONE_KINDS[int(rng.choice(len(ZONE_KINDS), p=ZONE_WEIGHTS))]
    if kind == "rooms":
        _rooms(rng, occ, zone, front, t, res)
    elif kind == "hall":
        _hall(rng, occ, zone, front, res)
    else:
        _warehouse(rng, occ, zone, front, res)


def _wing_edges(rng: np.random.Generator, lo: int, hi: int, t: int, res: float) -> list[int]:
    """Column edges lo = e_0 < ... < e_n = hi of wings WING_M long; wing k > 0 starts with a wall."""
    edges = [lo]
    while hi - edges[-1] > cells(WING_M[0] + WING_M[1], res):
        edges.append(edges[-1] + cells(rng.uniform(*WING_M), res) + t)
    edges.append(hi)
    return edges


def building_layout(rng: np.random.Generator, n_rows: int, n_cols: int, resolution: float) -> BoolGrid:
    """A large building of ``n_rows`` x ``n_cols`` cells: a main corridor along the longer side,
    wings along it (some divided by a cross corridor), and rooms, halls or warehouses on both
    sides of the corridor in each wing. The layout is drawn with the corridor along the columns
    and turned when the rows are the longer side."""
    if n_rows > n_cols:
        return np.ascontiguousarray(building_layout(rng, n_cols, n_rows, resolution).T)
    res, t = resolution, wall_cells(rng, resolution)
    occ = bordered((n_rows, n_cols), t)
    cw = cells(rng.uniform(*CORRIDOR_M), res)
    side_min = cells(4.0, res)
    lo, hi = t + side_min + t, n_rows - t - side_min - t - cw
    c_r0 = int(rng.integers(lo, hi + 1)) if hi >= lo else (n_rows - cw) // 2
    below = Rect(c_r0 - t, c_r0, t, n_cols - t)  # the corridor's walls
    above = Rect(c_r0 + cw, c_r0 + cw + t, t, n_cols - t)
    for wall in (below, above):
        occ[wall.r0 : wall.r1, wall.c0 : wall.c1] = True
    edges = _wing_edges(rng, t, n_cols - t, t, res)
    for k in range(len(edges) - 1):
        start = edges[k] + (t if k else 0)
        if k and rng.random() < 0.3:  # a cross corridor in place of the wall between two wings
            xw = cells(rng.uniform(*CROSS_CORRIDOR_M), res)
            band = Rect(t, n_rows - t, edges[k], edges[k] + xw + 2 * t)
            occ[band.r0 : band.r1, band.c0 : band.c1] = True
            occ[band.r0 : band.r1, band.c0 + t : band.c1 - t] = False
            occ[c_r0 : c_r0 + cw, band.c0 : band.c1] = False  # the main corridor crosses it
            for rows in ((t, below.r0), (above.r1, n_rows - t)):  # doors from the wings beside it
                for cols in ((band.c0, band.c0 + t), (band.c1 - t, band.c1)):
                    if rng.random() < 0.5:
                        _room_door(rng, occ, Rect(*rows, *cols), False, res)
            start = band.c1
        elif k:
            occ[t : n_rows - t, edges[k] : edges[k] + t] = True
            occ[c_r0 : c_r0 + cw, edges[k] : edges[k] + t] = False  # the main corridor runs through
        for zone, front in (
            (Rect(t, below.r0, start, edges[k + 1]), below),
            (Rect(above.r1, n_rows - t, start, edges[k + 1]), above),
        ):
            if zone.r1 - zone.r0 < cells(2.0, res) or zone.c1 - zone.c0 < cells(3.0, res):
                continue
            _zone(rng, occ, zone, Rect(front.r0, front.r1, zone.c0, zone.c1), t, res)
            if k and start == edges[k] + t and rng.random() < 0.5:  # a door to the previous wing
                _room_door(rng, occ, Rect(zone.r0, zone.r1, edges[k], edges[k] + t), False, res)
    return occ
