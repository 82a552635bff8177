"""What a map built by SLAM has and a drawn floor plan has not, added to a layout with a seed.

Real SLAM maps of offices (the harder survey's, issue 58) differ from drawn ones in three ways that
make exploration hard, and :func:`with_slam_artefacts` draws each onto a layout:

- **Radial streaks**: a laser ray that passed through glass or a gap in clutter is recorded as free
  cells far into a wall's mass, a line one cell wide pointing back at where the scan was taken.
  Here the layout gets a band of solid wall round it (what lies beyond the outer walls), and from a
  few scan points in the free space rays run on through the first wall they meet for a random
  length, clearing the cells they cross (4-connected, so the line stays one region with the room it
  starts from): through an outer wall into the band, a streak; through an inner one, a slit (glass).
- **Clutter specks**: chair legs and table feet, one or two occupied cells in open floor.
- **Rough walls**: a wall drawn by a noisy sensor is a cell thicker here and there, which narrows
  doorways and corridors by a cell.

The band is wider than the longest streak and its outermost cells stay occupied, so a world built
from the layout stays closed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

BoolGrid = NDArray[np.bool_]
"""A layout: True where occupied, (rows, cols)."""

_NEIGHBOURS_4 = ((1, 0), (-1, 0), (0, 1), (0, -1))


@dataclass(frozen=True)
class SlamArtefacts:
    """How much of each artefact :func:`with_slam_artefacts` adds.

    Attributes:
        scans_per_100m2: scan points whose rays leave streaks, per 100 m² of free space.
        rays_per_scan: rays each scan point sends on through the first wall they meet.
        streak_m: the shortest and longest run (m) of a ray through a wall's mass.
        specks_per_100m2: clutter specks (one or two occupied cells) per 100 m² of free space.
        rough_wall_share: the share of the free cells beside a wall that become wall.
        band_m: the solid band (m) added round the layout; wider than the longest streak.
    """

    scans_per_100m2: float = 2.0
    rays_per_scan: int = 12
    streak_m: tuple[float, float] = (0.5, 2.5)
    specks_per_100m2: float = 15.0
    rough_wall_share: float = 0.05
    band_m: float = 3.0


def with_slam_artefacts(
    layout: BoolGrid, rng: np.random.Generator, resolution: float, artefacts: SlamArtefacts | None = None
) -> BoolGrid:
    """``layout`` (True where occupied; cells of ``resolution`` m) in a solid band of
    ``artefacts.band_m`` on every side, with ``artefacts``' streaks, specks and rough walls, drawn
    with ``rng``."""
    artefacts = artefacts or SlamArtefacts()
    band = math.ceil(artefacts.band_m / resolution)
    occupied = np.pad(layout, band, constant_values=True)
    free_m2 = float(np.count_nonzero(~layout)) * resolution * resolution
    _rough_walls(occupied, rng, artefacts.rough_wall_share)
    _specks(occupied, rng, _count(rng, artefacts.specks_per_100m2 * free_m2 / 100.0))
    for _ in range(_count(rng, artefacts.scans_per_100m2 * free_m2 / 100.0)):
        free = np.flatnonzero(~occupied)
        row, col = np.divmod(int(rng.choice(free)), occupied.shape[1])
        for angle in rng.uniform(-math.pi, math.pi, artefacts.rays_per_scan):
            length = float(rng.uniform(*artefacts.streak_m)) / resolution
            _streak(occupied, row + 0.5, col + 0.5, float(angle), length)
    occupied[[0, -1], :] = True
    occupied[:, [0, -1]] = True
    return occupied


def _count(rng: np.random.Generator, mean: float) -> int:
    """A Poisson count of mean ``mean``."""
    return int(rng.poisson(max(mean, 0.0)))


def _rough_walls(occupied: BoolGrid, rng: np.random.Generator, share: float) -> None:
    """Occupy ``share`` of the free cells 4-adjacent to a wall."""
    beside = np.zeros_like(occupied)
    beside[1:, :] |= occupied[:-1, :]
    beside[:-1, :] |= occupied[1:, :]
    beside[:, 1:] |= occupied[:, :-1]
    beside[:, :-1] |= occupied[:, 1:]
    beside &= ~occupied
    occupied |= beside & (rng.random(occupied.shape) < share)


def _specks(occupied: BoolGrid, rng: np.random.Generator, count: int) -> None:
    """Occupy ``count`` free cells away from walls, each with a 4-neighbour half the time."""
    rows, cols = occupied.shape
    for _ in range(count):
        row, col = int(rng.integers(1, rows - 1)), int(rng.integers(1, cols - 1))
        if occupied[row - 1 : row + 2, col - 1 : col + 2].any():
            continue  # a speck in open floor, not a bump on a wall
        occupied[row, col] = True
        if rng.random() < 0.5:
            dr, dc = _NEIGHBOURS_4[int(rng.integers(4))]
            occupied[row + dr, col + dc] = True


def _streak(occupied: BoolGrid, y: float, x: float, angle: float, length: float) -> None:
    """March from (``y``, ``x``) (cells) along ``angle`` through free cells to the first wall, then
    clear ``length`` cells more of wall, 4-connected; stop at the layout's border."""
    rows, cols = occupied.shape
    dy, dx = math.sin(angle) * 0.5, math.cos(angle) * 0.5  # half-cell steps
    row, col = int(y), int(x)
    cleared = 0.0
    in_wall = False
    while True:
        y, x = y + dy, x + dx
        nrow, ncol = int(math.floor(y)), int(math.floor(x))
        if not (1 <= nrow < rows - 1 and 1 <= ncol < cols - 1):
            return
        if (nrow, ncol) == (row, col):
            continue
        in_wall = in_wall or bool(occupied[nrow, ncol])
        if in_wall:
            if nrow != row and ncol != col:  # a diagonal step: clear a side cell so the line stays 4-connected
                occupied[row, ncol] = False
            occupied[nrow, ncol] = False
            cleared += 1.0
            if cleared >= length:
                return
        row, col = nrow, ncol
