"""The thesis's office maze as a wall mask: a grid of ~2 m maze cells grouped into hallways, rooms
and solid cores, linked by a random spanning tree, with pillars (lengths and randomness as in
:mod:`frontier_rl.core.world.layout`)."""

from __future__ import annotations

from enum import Enum

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from frontier_rl.core.world.layout import (
    PILLAR_M,
    BoolGrid,
    Rect,
    bordered,
    cells,
    pick_start,
    place_pillars,
    wall_cells,
)
from frontier_rl.errors import ConfigError

DOOR_M = (0.8, 1.0)  # office door width range (m)
OFFICE_CELL_M = 1.3  # narrowest clear width of an office maze cell, i.e. of a hallway (m)


class Link(Enum):
    """What lies between two 4-adjacent maze cells."""

    OPEN = "open"  # nothing: the cells are one space
    DOOR = "door"  # a wall with a door
    WALL = "wall"


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
) -> dict[tuple[int, int, int, int], Link]:
    """The :class:`Link` between each pair of 4-adjacent maze cells.

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
    links: dict[tuple[int, int, int, int], Link] = {}
    for idx in rng.permutation(len(pairs)):
        i, j, k, m = pair = pairs[int(idx)]
        ra, rb = int(region[i, j]), int(region[k, m])
        if solid[i, j] or solid[k, m]:
            links[pair] = Link.WALL
        elif ra == rb:
            links[pair] = Link.OPEN
        else:
            room = ra in rooms or rb in rooms
            if root(ra) != root(rb):
                parent[root(ra)] = root(rb)
                links[pair] = Link.DOOR if room else Link.OPEN
            else:
                links[pair] = (
                    (Link.DOOR if rng.random() < 0.1 else Link.WALL)
                    if room
                    else (Link.OPEN if rng.random() < 0.1 else Link.WALL)
                )
    return links


def office_layout(rng: np.random.Generator, n_rows: int, n_cols: int, resolution: float) -> BoolGrid:
    """Office maze: a grid of ~2 m maze cells grouped into hallways, rooms (1x1 to 2x2 cells, with
    0.8-1.0 m doors) and solid cores, linked by a random spanning tree (so hallways branch and end
    in dead ends), with square pillars at the free wall-grid crossings."""
    thick = wall_cells(rng, resolution)
    occ = bordered((n_rows, n_cols), thick)
    row_edges = _band_edges(rng, thick, n_rows - thick, thick, resolution)  # the maze cells' bands
    col_edges = _band_edges(rng, thick, n_cols - thick, thick, resolution)
    row_starts = [row_edges[0]] + [e + thick for e in row_edges[1:-1]]  # where each band's clear part starts
    col_starts = [col_edges[0]] + [e + thick for e in col_edges[1:-1]]
    region, rooms, solid = _maze_regions(rng, len(row_starts), len(col_starts))
    for i, j in zip(*np.nonzero(solid), strict=True):
        occ[row_edges[i] : row_edges[i + 1], col_edges[j] : col_edges[j + 1]] = True
    margin = cells(0.1, resolution)  # no door closer to a wall's end
    walled = np.zeros((len(row_starts) + 1, len(col_starts) + 1), dtype=np.bool_)  # crossings beside a wall
    doors: list[Rect] = []
    # pillar spots: the middles of the maze cells, of open cell borders and of free wall-grid crossings
    centres = [
        ((row_starts[i] + row_edges[i + 1]) // 2, (col_starts[j] + col_edges[j + 1]) // 2)
        for i, j in np.ndindex(region.shape)
    ]
    for (i, j, k, n), state in _maze_links(rng, region, rooms, solid).items():
        door_w = cells(rng.uniform(*DOOR_M), resolution)
        # the wall's extent along it
        lo, hi = (row_starts[i], row_edges[i + 1]) if k == i else (col_starts[j], col_edges[j + 1])
        door_at = pick_start(rng, lo + margin, hi - margin, door_w)
        # vertical wall between columns j and n = j + 1, or horizontal one between rows i and k = i + 1
        if k == i:
            wall = Rect(lo, hi, col_edges[n], col_edges[n] + thick)
        else:
            wall = Rect(row_edges[k], row_edges[k] + thick, lo, hi)
        if state is Link.OPEN or (state is Link.DOOR and door_at is None):
            centres.append(((wall.r0 + wall.r1) // 2, (wall.c0 + wall.c1) // 2))  # where cells merge
            continue
        walled[k, n] = walled[k + (k == i), n + (n == j)] = True  # the crossings at both ends
        occ[wall.r0 : wall.r1, wall.c0 : wall.c1] = True
        if state is Link.DOOR and door_at is not None:
            span = (door_at, door_at + door_w)
            door = wall._replace(r0=span[0], r1=span[1]) if k == i else wall._replace(c0=span[0], c1=span[1])
            occ[door.r0 : door.r1, door.c0 : door.c1] = False
            doors.append(door)
    for k in range(1, len(row_starts)):
        for n in range(1, len(col_starts)):
            if walled[k, n]:
                occ[row_edges[k] : row_edges[k] + thick, col_edges[n] : col_edges[n] + thick] = True
                size = max(thick + 2, cells(rng.uniform(*PILLAR_M), resolution))  # a column in the wall
                r, c = row_edges[k] + thick // 2 - size // 2, col_edges[n] + thick // 2 - size // 2
                if rng.random() < 0.6 and not any(cut.overlaps(Rect(r, r + size, c, c + size), 2) for cut in doors):
                    occ[r : r + size, c : c + size] = True
            else:
                centres.append((row_edges[k] + thick // 2, col_edges[n] + thick // 2))
    place_pillars(rng, occ, centres, int(rng.integers(4, 10)), resolution)
    return occ
