"""Rooms from a recursive binary space partition as a wall mask: a door in every splitting wall,
corridors near the top of the tree and extra doors from rooms onto corridors (lengths and
randomness as in :mod:`frontier_rl.core.world.layout`)."""

from __future__ import annotations

import numpy as np

from frontier_rl.core.world.layout import ROOM_DOOR_M, BoolGrid, Rect, bordered, cells, pick_start, wall_cells
from frontier_rl.errors import ConfigError

ROOM_MIN_M = 2.5  # narrowest room of the BSP layout (m)
CORRIDOR_M = (1.2, 1.8)  # BSP corridor width range (m)


def _cut_door(rng: np.random.Generator, occ: BoolGrid, wall: Rect, axis: int, res: float, doors: list[Rect]) -> None:
    """Cut a 0.8-1.2 m door through ``wall`` (runs along columns if axis == 0, else along rows)."""
    dw, m = cells(rng.uniform(*ROOM_DOOR_M), res), cells(0.1, res)
    lo, hi = (wall.c0, wall.c1) if axis == 0 else (wall.r0, wall.r1)
    d = pick_start(rng, lo + m, hi - m, dw)
    if d is None:
        raise ConfigError(f"a wall of {(hi - lo) * res:.2f} m is too short for a door")
    door = Rect(wall.r0, wall.r1, d, d + dw) if axis == 0 else Rect(d, d + dw, wall.c0, wall.c1)
    occ[door.r0 : door.r1, door.c0 : door.c1] = False
    doors.append(door)


def _split(
    rng: np.random.Generator,
    occ: BoolGrid,
    rect: Rect,
    depth: int,
    t: int,
    res: float,
    doors: list[Rect],
    corridors: list[Rect],
) -> list[Rect] | None:
    """Split ``rect`` by a wall with a door (or, near the top of the tree, by a corridor between two
    walls with a door each); return the two parts, or ``None`` if ``rect`` stays one room."""
    r0, r1, c0, c1 = rect
    h, w = r1 - r0, c1 - c0
    min_room = cells(ROOM_MIN_M, res)
    if depth >= 6 or (depth >= 2 and max(h, w) < cells(5.0, res) and rng.random() < 0.5):
        return None
    corridor = depth <= 1 and rng.random() < 0.7
    cw = cells(rng.uniform(*CORRIDOR_M), res) if corridor else 0
    band = 2 * t + cw if corridor else t
    axes = [ax for ax, length in ((0, h), (1, w)) if length >= 2 * min_room + band]
    if not axes:
        return None
    longer = 0 if h >= w else 1
    axis = axes[0] if len(axes) == 1 else (longer if rng.random() < 0.8 else 1 - longer)
    m = t + cells(0.1, res)
    if axis == 0:  # a band across the columns must not end in a door of the walls left/right of rect
        forbidden = [(d.r0, d.r1) for d in doors if d.c1 == c0 or d.c0 == c1]
        s = pick_start(rng, r0 + min_room, r1 - min_room, band, forbidden, m)
    else:
        forbidden = [(d.c0, d.c1) for d in doors if d.r1 == r0 or d.r0 == r1]
        s = pick_start(rng, c0 + min_room, c1 - min_room, band, forbidden, m)
    if s is None:
        return None
    for a in [s, s + band - t] if corridor else [s]:
        wall = Rect(a, a + t, c0, c1) if axis == 0 else Rect(r0, r1, a, a + t)
        occ[wall.r0 : wall.r1, wall.c0 : wall.c1] = True
        _cut_door(rng, occ, wall, axis, res, doors)
    if corridor:
        corridors.append(Rect(s + t, s + t + cw, c0, c1) if axis == 0 else Rect(r0, r1, s + t, s + t + cw))
    if axis == 0:
        return [Rect(r0, s, c0, c1), Rect(s + band, r1, c0, c1)]
    return [Rect(r0, r1, c0, s), Rect(r0, r1, s + band, c1)]


def _shared_wall(room: Rect, cor: Rect, t: int) -> tuple[Rect, int] | None:
    """The wall (and its axis) between a room and a corridor that run side by side, if any."""
    rows = (max(room.r0, cor.r0), min(room.r1, cor.r1))
    cols = (max(room.c0, cor.c0), min(room.c1, cor.c1))
    if cols[1] > cols[0] and room.r1 + t == cor.r0:
        return Rect(room.r1, cor.r0, *cols), 0
    if cols[1] > cols[0] and cor.r1 + t == room.r0:
        return Rect(cor.r1, room.r0, *cols), 0
    if rows[1] > rows[0] and room.c1 + t == cor.c0:
        return Rect(*rows, room.c1, cor.c0), 1
    if rows[1] > rows[0] and cor.c1 + t == room.c0:
        return Rect(*rows, cor.c1, room.c0), 1
    return None


def rooms_layout(rng: np.random.Generator, n_rows: int, n_cols: int, resolution: float) -> BoolGrid:
    """Rooms (at least ROOM_MIN_M wide) from a recursive binary space partition, with a door in every
    splitting wall, corridors near the top of the tree and extra doors from rooms onto corridors."""
    t = wall_cells(rng, resolution)
    occ = bordered((n_rows, n_cols), t)
    doors: list[Rect] = []
    corridors: list[Rect] = []
    leaves: list[Rect] = []
    stack = [(Rect(t, n_rows - t, t, n_cols - t), 0)]
    while stack:
        rect, depth = stack.pop()
        parts = _split(rng, occ, rect, depth, t, resolution, doors, corridors)
        if parts is None:
            leaves.append(rect)
        else:
            stack += [(part, depth + 1) for part in parts]
    for room in leaves:  # extra doors from rooms onto the corridors they line
        for cor in corridors:
            shared = _shared_wall(room, cor, t)
            if shared is None or rng.random() > 0.7 or any(d.overlaps(shared[0]) for d in doors):
                continue
            (r0, r1, c0, c1), axis = shared
            if max(r1 - r0, c1 - c0) >= cells(ROOM_DOOR_M[1], resolution) + 2 * t + 4:  # room for a door
                inner = Rect(r0, r1, c0 + t, c1 - t) if axis == 0 else Rect(r0 + t, r1 - t, c0, c1)
                _cut_door(rng, occ, inner, axis, resolution, doors)
    return occ
