"""What the procedural building layouts share: wall masks (``True`` = wall, row 0 at bottom), cell
rectangles, lengths in cells, walls round a floor, spans placed at random and pillars.

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

BoolGrid = NDArray[np.bool_]

WALL_M = (0.10, 0.15)  # wall thickness range (m)
MIN_GAP_M = 0.8  # narrowest door or gap between obstacles (m)
PILLAR_M = (0.2, 0.4)  # square pillar edge range (m)
ROOM_DOOR_M = (0.8, 1.2)  # the door width range (m) of the BSP rooms and of the building's rooms


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
