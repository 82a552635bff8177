"""The large-building generator: floor sizes, one connected floor, and every kind of zone."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

from frontier_rl.core.world.building import ZONE_KINDS, building_layout
from frontier_rl.core.world.catalog import building_world
from frontier_rl.errors import ConfigError

SEEDS = range(6)


@pytest.mark.parametrize("seed", SEEDS)
def test_floor_size_and_orientation(seed: int) -> None:
    world = building_world(np.random.default_rng(seed))
    rows, cols = world.grid.shape
    long_m, short_m = max(rows, cols) * 0.05, min(rows, cols) * 0.05
    assert 30.0 <= long_m <= 60.0 and 20.0 <= short_m <= 35.0


@pytest.mark.parametrize("seed", SEEDS)
def test_the_whole_floor_is_one_connected_building(seed: int) -> None:
    """Every zone opens onto the main corridor: nearly all free cells of the layout are in one
    4-connected piece, and the world's explorable space is most of the floor."""
    occ = building_layout(np.random.default_rng(seed), 600, 900, 0.05)
    labels, _n = ndimage.label(~occ)
    sizes = np.bincount(labels.ravel())[1:]
    assert sizes.max() >= 0.97 * sizes.sum()
    world = building_world(np.random.default_rng(seed), (45.0, 30.0))
    assert world.explorable_count * 0.05**2 >= 0.9 * 45.0 * 30.0 * 0.85


def test_layout_is_turned_when_the_rows_are_the_longer_side() -> None:
    wide = building_layout(np.random.default_rng(3), 500, 800, 0.05)
    tall = building_layout(np.random.default_rng(3), 800, 500, 0.05)
    assert np.array_equal(wide.T, tall)


def test_every_kind_of_zone_is_drawn() -> None:
    """Across a few floors: rows of rooms (many small pieces of wall), halls (pillars: small
    square wall pieces) and warehouses (shelving: long thin wall pieces)."""
    pieces = {"pillar": 0, "shelf": 0}
    for seed in range(6):
        occ = building_layout(np.random.default_rng(seed), 600, 1000, 0.05)
        labels, _n = ndimage.label(occ)
        for box in ndimage.find_objects(labels):
            h, w = box[0].stop - box[0].start, box[1].stop - box[1].start
            if max(h, w) <= 8:
                pieces["pillar"] += 1
            elif min(h, w) <= 20 and max(h, w) >= 60 and h * w < 0.05 * occ.size:
                pieces["shelf"] += 1
    assert pieces["pillar"] > 0 and pieces["shelf"] > 0
    assert set(ZONE_KINDS) == {"rooms", "hall", "warehouse"}


@pytest.mark.parametrize("size", [(0.0, 30.0), (40.0, float("nan")), (-5.0, 20.0)])
def test_bad_size_is_refused(size: tuple[float, float]) -> None:
    with pytest.raises(ConfigError, match="building"):
        building_world(np.random.default_rng(0), size)
