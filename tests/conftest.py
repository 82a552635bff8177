"""Shared test fixtures."""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from frontier_rl.core.frontiers.detection import Frontiers
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.io.catalogue import MAPS_DIR

if "PYTEST_XDIST_WORKER" in os.environ:
    # pytest -n runs a worker per core: each keeps torch to one thread (its pool reads this when
    # torch is first imported, after this file), where two threads each made two workers share a
    # core (a training test took 35 s, 5 s alone).
    os.environ.setdefault("OMP_NUM_THREADS", "1")


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Mark every test that reads the real maps ``slow`` (the other slow tests say so in their own
    file, with ``pytestmark``): the tests ``make test-fast`` (``pytest -m "not slow"``) leaves out."""
    for item in items:
        if "real_maps" in getattr(item, "fixturenames", ()):
            item.add_marker(pytest.mark.slow)


@pytest.fixture(scope="session")
def real_maps() -> Path:
    """The folder of the real maps the package ships (``frontier_rl/data/maps``, one sub-folder
    per origin; :mod:`frontier_rl.io.catalogue` names them)."""
    return MAPS_DIR


# ----------------------------------------------------------------------------- hand-made grids
#: Characters of :func:`grid_from_text`: free, occupied, unknown.
_TEXT_CELLS = {".": CellState.FREE.value, "#": CellState.OCCUPIED.value, "?": CellState.UNKNOWN.value}


def _grid_from_text(
    rows: list[str], resolution: float = 0.05, origin: tuple[float, float] = (0.0, 0.0)
) -> OccupancyGrid:
    """Grid from text rows, *top row first* (the last string is row 0): '.' free, '#' occupied,
    '?' unknown."""
    data = np.array([[_TEXT_CELLS[ch] for ch in row] for row in reversed(rows)], dtype=np.int8)
    return OccupancyGrid(data, resolution, origin)


@pytest.fixture(scope="session")
def grid_from_text() -> Callable[..., OccupancyGrid]:
    """``grid_from_text(rows, resolution=0.05, origin=(0, 0))``: an :class:`OccupancyGrid` drawn as
    text, top row first, '.' free, '#' occupied, '?' unknown."""
    return _grid_from_text


def _frontiers_from(
    grid: OccupancyGrid,
    centers: object,
    sizes: object,
    distances: object | None = None,
    min_distances: object | None = None,
) -> Frontiers:
    """A :class:`Frontiers` with the given centres (m) and sizes (cells), distances defaulting to
    zeros, and placeholder cells (cell 0 repeated): for checks of ranking and information gain."""
    c = np.asarray(centers, dtype=np.float64).reshape(-1, 2)
    s = np.asarray(sizes, dtype=np.int64)
    n = len(s)
    d = np.zeros(n) if distances is None else np.asarray(distances, dtype=np.float64)
    md = d.copy() if min_distances is None else np.asarray(min_distances, dtype=np.float64)
    ends = np.cumsum(s)
    spans = np.column_stack((ends - s, ends)).astype(np.int64).reshape(-1, 2)
    goals = np.array([grid.world_to_cell(float(x), float(y)) for x, y in c], np.int64).reshape(-1, 2)
    return Frontiers(grid, c, s, d, md, np.zeros(int(s.sum()), np.int64), spans, goals)


@pytest.fixture(scope="session")
def frontiers_from() -> Callable[..., Frontiers]:
    """``frontiers_from(grid, centers, sizes, distances=None, min_distances=None)``: a hand-made
    :class:`Frontiers` (placeholder cells) for ranking and information-gain tests."""
    return _frontiers_from
