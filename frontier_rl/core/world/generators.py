"""Procedural building layouts (office maze, BSP rooms) as wall masks (``True`` = wall), row 0 at bottom.

Lengths are in metres, turned into cells with the resolution (m/cell); randomness only from the
caller's ``numpy.random.Generator``. Every layout is bordered by walls, its walls are at least 2
cells thick (0.10-0.15 m: no LiDAR ray slips through a one-cell wall) and its doors and hallways
are at least MIN_GAP_M wide, so the 0.21 m robot passes with room for costmap inflation.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from frontier_rl.errors import ConfigError

BoolGrid = NDArray[np.bool_]

WALL_M = (0.10, 0.15)  # wall thickness range (m)
MIN_GAP_M = 0.8  # narrowest door or gap between obstacles (m)
DOOR_M = (0.8, 1.0)  # office door width range (m)
OFFICE_CELL_M = 1.3  # narrowest clear width of an office maze cell, i.e. of a hallway (m)
PILLAR_M = (0.2, 0.4)  # square pillar edge range (m)
ROOM_MIN_M = 2.5  # narrowest room of the BSP layout (m)
ROOM_DOOR_M = (0.8, 1.2)  # BSP door width range (m)
CORRIDOR_M = (1.2, 1.8)  # BSP corridor width range (m)


class Rect(NamedTuple):
    """Half-open cell rectangle: rows [r0, r1), columns [c0, c1)."""

    r0: int
    r1: int
    c0: int
    c1: int

    def overlaps(self, other: Rect, margin: int = 0) -> bool:
        """Whether the two rectangles, this one grown by ``margin`` cells, share a cell."""
        m = margin
        return self.r0 - m < other.r1 and other.r0 < self.r1 + m and self.c0 - m < other.c1 and other.c0 < self.c1 + m


def cells(length_m: float, resolution: float) -> int:
    """Number of cells (at least 1) closest to ``length_m`` metres at ``resolution`` m/cell."""
    return max(1, round(length_m / resolution))


def wall_cells(rng: np.random.Generator, resolution: float) -> int:
    """A random wall thickness in cells: 0.10-0.15 m, never fewer than 2 cells."""
    return max(2, cells(rng.uniform(*WALL_M), resolution))


def bordered(shape: tuple[int, int], thickness: int) -> BoolGrid:
    """Empty wall mask of ``shape`` with a wall ``thickness`` cells thick around the edge."""
    occ = np.zeros(shape, dtype=np.bool_)
    occ[:thickness, :] = occ[-thickness:, :] = True
    occ[:, :thickness] = occ[:, -thickness:] = True
    return occ


def pick_start(
    rng: np.random.Generator,
    lo: int,
    hi: int,
    width: int,
    forbidden: Sequence[tuple[int, int]] = (),
    margin: int = 0,
) -> int | None:
    """Random start s of a span [s, s + width) inside [lo, hi) that stays ``margin`` cells clear of
    every ``forbidden`` half-open interval; ``None`` when no such span exists."""
    starts = np.arange(lo, hi - width + 1)
    ok = np.ones(starts.size, dtype=np.bool_)
    for a, b in forbidden:
        ok &= (starts + width + margin <= a) | (starts >= b + margin)
    if not ok.any():
        return None
    return int(rng.choice(starts[ok]))


# --------------------------------------------------------------------------------------- office
def _band_edges(rng: np.random.Generator, lo: int, hi: int, t: int, res: float) -> list[int]:
    """Edges lo = e_0 < ... < e_n = hi of n maze bands about 2 m wide (each >= OFFICE_CELL_M clear
    plus a wall); band k > 0 starts with its wall, cells [e_k, e_k + t)."""
    span, band_min = hi - lo, cells(OFFICE_CELL_M, res) + t
    if span < band_min:
        raise ConfigError(f"office floor of {span * res:.2f} m is narrower than one {OFFICE_CELL_M} m hallway")
    n0, n_max = max(1, round(span * res / 2.0)), span // band_min
    n = int(rng.integers(min(max(1, n0 - 1), n_max), min(n0 + 1, n_max) + 1))
    spare = span - n * band_min
    extra = np.floor(rng.dirichlet(np.full(n, 4.0)) * spare).astype(np.int64)
    extra[-1] += spare - int(extra.sum())
    return [lo, *(lo + np.cumsum(band_min + extra)).tolist()]


def _maze_regions(rng: np.random.Generator, n_rows: int, n_cols: int) -> tuple[NDArray[np.int64], set[int], BoolGrid]:
    """Group the maze cells into regions: rooms of 1x1 to 2x2 cells, solid cores and hallway cells.

    Returns (region id per cell, ids of the rooms, solid mask)."""
    region = np.arange(n_rows * n_cols).reshape(n_rows, n_cols)
    taken, solid, rooms = np.zeros(region.shape, np.bool_), np.zeros(region.shape, np.bool_), set()
    shapes = [(1, 1), (1, 2), (2, 1), (2, 2)]
    for idx in rng.permutation(region.size):
        i, j = divmod(int(idx), n_cols)
        if taken[i, j]:
            continue
        u = rng.random()
        h, w = shapes[int(rng.choice(4, p=[0.3, 0.25, 0.25, 0.2]))]
        if u < 0.08:
            solid[i, j] = True
        elif u < 0.55 and taken[i : i + h, j : j + w].shape == (h, w) and not taken[i : i + h, j : j + w].any():
            region[i : i + h, j : j + w] = region[i, j]
            taken[i : i + h, j : j + w] = True
            rooms.add(int(region[i, j]))
        taken[i, j] = True
    if ndimage.label(~solid)[1] > 1:  # a solid core must never cut the floor in two
        solid[:] = False
    return region, rooms, solid


def _maze_links(
    rng: np.random.Generator, region: NDArray[np.int64], rooms: set[int], solid: BoolGrid
) -> dict[tuple[int, int, int, int], str]:
    """State ("open", "door" or "wall") of the boundary between each pair of 4-adjacent maze cells.

    A random spanning tree over the regions keeps everything connected: its hallway-hallway links
    are open, its links to rooms are doors; a few extra links make loops, the rest are walls."""
    n_rows, n_cols = region.shape
    parent = list(range(region.size))

    def root(a: int) -> int:
        while parent[a] != a:
            a = parent[a]
        return a

    pairs = [(i, j, i, j + 1) for i in range(n_rows) for j in range(n_cols - 1)]
    pairs += [(i, j, i + 1, j) for i in range(n_rows - 1) for j in range(n_cols)]
    links: dict[tuple[int, int, int, int], str] = {}
    for idx in rng.permutation(len(pairs)):
        i, j, k, m = pair = pairs[int(idx)]
        ra, rb = int(region[i, j]), int(region[k, m])
        if solid[i, j] or solid[k, m]:
            links[pair] = "wall"
        elif ra == rb:
            links[pair] = "open"
        else:
            room = ra in rooms or rb in rooms
            if root(ra) != root(rb):
                parent[root(ra)] = root(rb)
                links[pair] = "door" if room else "open"
            else:
                links[pair] = (
                    ("door" if rng.random() < 0.1 else "wall") if room else ("open" if rng.random() < 0.1 else "wall")
                )
    return links


def place_pillars(
    rng: np.random.Generator, occ: BoolGrid, centres: Sequence[tuple[int, int]], count: int, resolution: float
) -> None:
    """Add up to ``count`` 0.2-0.4 m square pillars, tried at ``centres`` (cells) in random order,
    each kept MIN_GAP_M from every wall and pillar."""
    gap, placed = cells(MIN_GAP_M, resolution), 0
    for idx in rng.permutation(len(centres)):
        (r, c), size = centres[int(idx)], cells(rng.uniform(*PILLAR_M), resolution)
        reach = gap + size / math.sqrt(2.0) + 1.0  # no wall may lie this close (cells) to the centre
        k = math.ceil(reach)
        r0, r1, c0, c1 = (
            max(r - k, 0),
            min(r + k + 1, occ.shape[0]),
            max(c - k, 0),
            min(c + k + 1, occ.shape[1]),
        )
        dy, dx = np.ogrid[r0 - r : r1 - r, c0 - c : c1 - c]
        if np.any(occ[r0:r1, c0:c1] & (dy * dy + dx * dx < reach * reach)):
            continue
        occ[r - size // 2 : r - size // 2 + size, c - size // 2 : c - size // 2 + size] = True
        placed += 1
        if placed == count:
            return


def office_layout(rng: np.random.Generator, n_rows: int, n_cols: int, resolution: float) -> BoolGrid:
    """Office maze: a grid of ~2 m maze cells grouped into hallways, rooms (1x1 to 2x2 cells, with
    0.8-1.0 m doors) and solid cores, linked by a random spanning tree (so hallways branch and end
    in dead ends), with square pillars at the free wall-grid crossings."""
    t = wall_cells(rng, resolution)
    occ = bordered((n_rows, n_cols), t)
    ye, xe = _band_edges(rng, t, n_rows - t, t, resolution), _band_edges(rng, t, n_cols - t, t, resolution)
    ys, xs = [ye[0]] + [e + t for e in ye[1:-1]], [xe[0]] + [e + t for e in xe[1:-1]]  # clear starts
    region, rooms, solid = _maze_regions(rng, len(ys), len(xs))
    for i, j in zip(*np.nonzero(solid), strict=True):
        occ[ye[i] : ye[i + 1], xe[j] : xe[j + 1]] = True
    m = cells(0.1, resolution)
    walled = np.zeros((len(ys) + 1, len(xs) + 1), dtype=np.bool_)  # wall-grid crossings next to a wall
    doors: list[Rect] = []
    # pillar spots: the middles of the maze cells, of open cell borders and of free wall-grid crossings
    centres = [((ys[i] + ye[i + 1]) // 2, (xs[j] + xe[j + 1]) // 2) for i, j in np.ndindex(region.shape)]
    for (i, j, k, n), state in _maze_links(rng, region, rooms, solid).items():
        dw = cells(rng.uniform(*DOOR_M), resolution)
        lo, hi = (ys[i], ye[i + 1]) if k == i else (xs[j], xe[j + 1])  # the wall's extent along it
        d = pick_start(rng, lo + m, hi - m, dw)
        # vertical wall between columns j and n = j + 1, or horizontal one between rows i and k = i + 1
        wall = Rect(lo, hi, xe[n], xe[n] + t) if k == i else Rect(ye[k], ye[k] + t, lo, hi)
        if state == "open" or (state == "door" and d is None):
            centres.append(((wall.r0 + wall.r1) // 2, (wall.c0 + wall.c1) // 2))  # where cells merge
            continue
        walled[k, n] = walled[k + (k == i), n + (n == j)] = True  # the crossings at both ends
        occ[wall.r0 : wall.r1, wall.c0 : wall.c1] = True
        if state == "door" and d is not None:
            door = wall._replace(r0=d, r1=d + dw) if k == i else wall._replace(c0=d, c1=d + dw)
            occ[door.r0 : door.r1, door.c0 : door.c1] = False
            doors.append(door)
    for k in range(1, len(ys)):
        for n in range(1, len(xs)):
            if walled[k, n]:
                occ[ye[k] : ye[k] + t, xe[n] : xe[n] + t] = True
                size = max(t + 2, cells(rng.uniform(*PILLAR_M), resolution))  # a column in the wall
                r, c = ye[k] + t // 2 - size // 2, xe[n] + t // 2 - size // 2
                if rng.random() < 0.6 and not any(d.overlaps(Rect(r, r + size, c, c + size), 2) for d in doors):
                    occ[r : r + size, c : c + size] = True
            else:
                centres.append((ye[k] + t // 2, xe[n] + t // 2))
    place_pillars(rng, occ, centres, int(rng.integers(4, 10)), resolution)
    return occ


# ---------------------------------------------------------------------------------------- rooms
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
