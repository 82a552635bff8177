"""Natural caves: tunnels and chambers grown by a cellular automaton, the kind of site an
underground rescue (a mine, a cave: the DARPA Subterranean Challenge's) explores.

The automaton works on blocks of ``CAVE_BLOCK_M``: rock is drawn at random, then each block
becomes rock when most of its 3 x 3 neighbourhood is rock, a few times over (the rule of Johnson,
Yannakakis and Togelius 2010, "Cellular automata for real-time generation of infinite cave
levels"). Passages narrower than ``CAVE_NARROWEST_BLOCKS`` blocks (0.5 m) are closed, the largest
cave system is kept, and the map is cropped to it.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from frontier_rl.core.world.rubble import close_diagonal_contacts

BoolGrid = NDArray[np.bool_]

CAVE_BLOCK_M = 0.25  # the automaton's cell (m)
CAVE_FILL = 0.47  # share of rock in the automaton's first draw
CAVE_STEPS = 5  # smoothing steps of the automaton
CAVE_NARROWEST_BLOCKS = 2  # passages narrower than this many blocks (0.5 m) are closed
CAVE_MIN_FLOOR = 0.5  # the kept cave system fills at least this share of its bounding box
CAVE_DRAWS = 20  # draws before the last one is taken whatever its share of floor
_NEIGHBOURHOOD = np.ones((3, 3), np.int8)


def _automaton(rng: np.random.Generator, n_rows: int, n_cols: int) -> BoolGrid:
    """Rock blocks after the smoothing steps; beyond the edge is rock."""
    rock = rng.random((n_rows, n_cols)) < CAVE_FILL
    for _ in range(CAVE_STEPS):
        rock = ndimage.convolve(rock.astype(np.int8), _NEIGHBOURHOOD, mode="constant", cval=1) >= 5
    return rock


def _largest_system(floor: BoolGrid) -> BoolGrid:
    """The largest 4-connected part of ``floor`` (the planner moves in 4 directions)."""
    labels, count = ndimage.label(floor)
    if count == 0:
        return floor
    return np.asarray(labels == 1 + int(np.argmax(np.bincount(labels.ravel())[1:])))


def _one_system(rock: BoolGrid) -> BoolGrid:
    """``rock`` with every passage narrower than ``CAVE_NARROWEST_BLOCKS`` closed, all but the
    largest cave system filled, and no two rock blocks touching only at a corner."""
    square = np.ones((CAVE_NARROWEST_BLOCKS, CAVE_NARROWEST_BLOCKS), np.bool_)
    floor = ~rock
    while True:  # closing a corner can narrow a passage, filling one can make a corner; floor only shrinks
        opened = ndimage.binary_opening(floor, square) & floor
        closed = ~close_diagonal_contacts(~_largest_system(opened))
        if np.array_equal(closed, floor):
            return np.asarray(~floor)
        floor = closed


def _cropped(rock: BoolGrid) -> BoolGrid:
    """``rock`` cut to the bounding box of its floor, with one block of rock around it."""
    rows, cols = np.flatnonzero((~rock).any(axis=1)), np.flatnonzero((~rock).any(axis=0))
    if rows.size == 0:
        return rock
    return np.pad(rock[rows[0] : rows[-1] + 1, cols[0] : cols[-1] + 1], 1, constant_values=True)


def cave_layout(rng: np.random.Generator, n_rows: int, n_cols: int) -> BoolGrid:
    """Rock (True) per block of one cave system drawn on ``n_rows`` x ``n_cols`` blocks, cropped
    to it with a rock border of one block.

    The system fills at least ``CAVE_MIN_FLOOR`` of its map: a draw whose largest system is
    sparser is drawn again (about one in five is), up to ``CAVE_DRAWS`` times."""
    for _ in range(CAVE_DRAWS):
        rock = _cropped(_one_system(_automaton(rng, n_rows, n_cols)))
        if np.count_nonzero(~rock) >= CAVE_MIN_FLOOR * rock.size:
            break
    return rock
