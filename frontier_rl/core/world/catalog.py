"""The named procedural worlds (``office``, ``rooms``, ``cluttered``, ``building``, ``cave``,
``slam_building``) and the registry that draws one from a seed."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from types import MappingProxyType

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.world import layout
from frontier_rl.core.world.building import building_layout
from frontier_rl.core.world.cave import CAVE_BLOCK_M, cave_layout
from frontier_rl.core.world.grid import FREE_I8, OCCUPIED_I8, OccupancyGrid
from frontier_rl.core.world.names import GENERATOR_NAMES
from frontier_rl.core.world.office import office_layout
from frontier_rl.core.world.rooms import rooms_layout
from frontier_rl.core.world.rubble import RUBBLE_GAP_M, close_diagonal_contacts, rubble_layout, upsample
from frontier_rl.core.world.slam_artefacts import SlamArtefacts, with_slam_artefacts
from frontier_rl.core.world.worlds import World, dilate, make_world
from frontier_rl.errors import ConfigError, MapError, UnknownNameError


def _layout_grid(occ: NDArray[np.bool_], resolution: float) -> OccupancyGrid:
    return OccupancyGrid(np.where(occ, OCCUPIED_I8, FREE_I8).astype(np.int8), resolution)


def _check_size(what: str, value: float) -> None:
    if not (math.isfinite(value) and value > 0):
        raise ConfigError(f"{what} must be a positive number of metres, got {value!r}")


def office_world(rng: np.random.Generator, size_m: float = 12.5, resolution: float = 0.05) -> World:
    """The thesis world: a ``size_m`` x ``size_m`` (m) office maze of branching hallways (>= 1.3 m)
    with dead ends, rooms with 0.8-1.0 m doors, solid cores and 0.2-0.4 m square pillars."""
    _check_size("office size_m", size_m)
    _check_size("office resolution", resolution)
    n = layout.cells(size_m, resolution)
    return make_world(_layout_grid(office_layout(rng, n, n, resolution), resolution), "office", rng=rng)


def rooms_world(
    rng: np.random.Generator, size_m: tuple[float, float] = (16.0, 12.0), resolution: float = 0.05
) -> World:
    """Rooms of 2.5 m and more joined by doors (0.8-1.2 m) and 1.2-1.8 m corridors, in a
    ``size_m`` = (width x, height y) (m) building."""
    _check_size("rooms width", size_m[0])
    _check_size("rooms height", size_m[1])
    _check_size("rooms resolution", resolution)
    rows, cols = layout.cells(size_m[1], resolution), layout.cells(size_m[0], resolution)
    return make_world(_layout_grid(rooms_layout(rng, rows, cols, resolution), resolution), "rooms", rng=rng)


def cluttered_world(rng: np.random.Generator, size_m: float = 12.0, resolution: float = 0.05) -> World:
    """USAR rubble field, ``size_m`` x ``size_m`` (m): ruined walls and heaps of 0.1-0.8 m rubble.

    Drawn on 2 x 2-cell blocks, so no wall is one cell thin. A closing fills the slots narrower than
    RUBBLE_GAP_M; then every cell that a robot RUBBLE_GAP_M wide cannot get near is filled in, so
    the whole floor is reached through passages at least that wide. A layout that would lose over
    10 % of its free space so is redrawn (at most 5 times)."""
    _check_size("cluttered size_m", size_m)
    _check_size("cluttered resolution", resolution)
    block, wide = 2, RUBBLE_GAP_M / 2  # wide: radius (m) of the robot every passage must admit
    n, radius = layout.cells(size_m, block * resolution), wide / (block * resolution)
    for _ in range(5):
        raw = rubble_layout(rng, n, n, block * resolution)
        coarse = close_diagonal_contacts(np.asarray(~dilate(~dilate(raw, radius), radius)))  # closing
        world = make_world(_layout_grid(upsample(coarse, block), resolution), "cluttered", rng=rng, robot_radius=wide)
        if world.explorable_count >= 0.9 * block * block * np.count_nonzero(~coarse):
            break
    kept = world.explorable.reshape(n, block, n, block).all(axis=(1, 3))
    grid = _layout_grid(upsample(close_diagonal_contacts(np.asarray(~kept)), block), resolution)
    try:
        return make_world(grid, "cluttered", start=world.start)
    except MapError:  # the start lost its clearance to a filled pocket: draw another one
        return make_world(grid, "cluttered", rng=rng)


BUILDING_MIN_M = 12.0
"""The shortest side (m) of a building: the main corridor and a zone of 4 m on each side of it."""


def building_world(
    rng: np.random.Generator, size_m: tuple[float, float] | None = None, resolution: float = 0.05
) -> World:
    """A large building (:mod:`frontier_rl.core.world.building`) of ``size_m`` = (width x, height
    y) (m); by default the longer side is drawn from 30-60 m and the shorter from 20-35 m (never
    longer than the other), in either orientation."""
    layout = _building_layout(rng, size_m, resolution)
    return make_world(_layout_grid(layout, resolution), "building", rng=rng)


def slam_building_world(
    rng: np.random.Generator,
    size_m: tuple[float, float] | None = None,
    resolution: float = 0.05,
    artefacts: SlamArtefacts | None = None,
) -> World:
    """A :func:`building_world` layout as a SLAM map would draw it: with radial streaks through
    walls, clutter specks and rough walls (:mod:`frontier_rl.core.world.slam_artefacts`), drawn
    with the same ``rng`` after the layout."""
    layout = with_slam_artefacts(_building_layout(rng, size_m, resolution), rng, resolution, artefacts)
    return make_world(_layout_grid(layout, resolution), "slam_building", rng=rng)


def _building_layout(
    rng: np.random.Generator, size_m: tuple[float, float] | None, resolution: float
) -> NDArray[np.bool_]:
    """The occupancy of a building of ``size_m`` (drawn with ``rng`` when None; see :func:`building_world`)."""
    if size_m is None:
        long_m = float(rng.uniform(30.0, 60.0))
        short_m = min(float(rng.uniform(20.0, 35.0)), long_m)
        size_m = (long_m, short_m) if rng.random() < 0.5 else (short_m, long_m)
    _check_size("building width", size_m[0])
    _check_size("building height", size_m[1])
    _check_size("building resolution", resolution)
    if min(size_m) < BUILDING_MIN_M:
        raise ConfigError(
            f"a building needs both sides of at least {BUILDING_MIN_M:g} m (a corridor with a zone of "
            f"4 m on each side), got {size_m[0]!r} x {size_m[1]!r}"
        )
    rows, cols = layout.cells(size_m[1], resolution), layout.cells(size_m[0], resolution)
    return building_layout(rng, rows, cols, resolution)


CAVE_MIN_M = 4.0
"""The shortest side (m) of a cave's drawing area."""


def cave_world(rng: np.random.Generator, size_m: tuple[float, float] = (26.0, 20.0), resolution: float = 0.05) -> World:
    """A natural cave (:mod:`frontier_rl.core.world.cave`): tunnels and chambers drawn on an area
    of ``size_m`` = (width x, height y) (m), the map cropped to the cave system with a rock
    border of one block (0.25 m); no passage is narrower than 0.5 m."""
    _check_size("cave width", size_m[0])
    _check_size("cave height", size_m[1])
    _check_size("cave resolution", resolution)
    if min(size_m) < CAVE_MIN_M:
        raise ConfigError(f"a cave needs both sides of at least {CAVE_MIN_M:g} m, got {size_m[0]!r} x {size_m[1]!r}")
    block = layout.cells(CAVE_BLOCK_M, resolution)  # cells per block: 2 or more at any cell a world admits (<= 0.105 m)
    rows, cols = layout.cells(size_m[1], block * resolution), layout.cells(size_m[0], block * resolution)
    return make_world(_layout_grid(upsample(cave_layout(rng, rows, cols), block), resolution), "cave", rng=rng)


WORLD_GENERATORS: Mapping[str, Callable[[np.random.Generator], World]] = MappingProxyType(
    dict(
        zip(
            GENERATOR_NAMES,
            (office_world, rooms_world, cluttered_world, building_world, cave_world, slam_building_world),
            strict=True,
        )
    )
)
"""Procedural worlds by name; each takes a ``numpy.random.Generator`` and uses default sizes."""


def generate_world(name: str, seed: int | np.random.Generator) -> World:
    """The procedural world ``name`` drawn from ``seed`` (an int or a Generator).

    Raises:
        UnknownNameError: ``name`` is not a key of :data:`WORLD_GENERATORS`.
    """
    if name not in WORLD_GENERATORS:
        raise UnknownNameError(f"unknown world {name!r}; valid worlds: {', '.join(sorted(WORLD_GENERATORS))}")
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    return WORLD_GENERATORS[name](rng)
