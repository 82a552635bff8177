"""Tests of frontier_rl.core.navigation.distance against scipy.ndimage: chamfer, exact EDT, flood fill."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.typing import NDArray
from scipy import ndimage

from frontier_rl.core.navigation.distance import chamfer_distance, flood_known
from frontier_rl.core.world.grid import CellState

#: Worst overestimate of the 3 x 3 chamfer (steps 1, sqrt 2) over the Euclidean distance, at 22.5 deg.
CHAMFER_MAX_RATIO = math.sqrt(4.0 - 2.0 * math.sqrt(2.0))  # 1.0824
EIGHT = np.ones((3, 3), dtype=bool)


def random_seeds(shape: tuple[int, int], density: float, seed: int) -> NDArray[np.bool_]:
    return np.random.default_rng(seed).random(shape) < density


CASES = [((40, 60), 0.01, 0), ((73, 31), 0.002, 1), ((100, 100), 0.0005, 2), ((25, 25), 0.2, 3), ((1, 50), 0.05, 4)]


# ------------------------------------------------------------------------------------- chamfer
@pytest.mark.parametrize(("shape", "density", "seed"), CASES)
def test_chamfer_is_within_the_octagonal_bound_of_the_exact_distance(
    shape: tuple[int, int], density: float, seed: int
) -> None:
    seeds = random_seeds(shape, density, seed)
    seeds[seed % shape[0], 0] = True  # at least one seed
    exact = ndimage.distance_transform_edt(~seeds)
    d = chamfer_distance(seeds, 1e9)
    assert d.shape == shape
    assert np.all(d >= exact - 1e-9)  # never underestimates
    assert np.all(d <= exact * CHAMFER_MAX_RATIO + 1e-9)  # at most ~8.3 % over
    assert np.all(d[seeds] == 0.0)


def test_chamfer_is_exact_along_axes_and_diagonals_and_worst_at_22_5_degrees() -> None:
    seeds = np.zeros((61, 61), bool)
    seeds[30, 30] = True
    d = chamfer_distance(seeds, 1e9)
    for k in range(1, 30):
        assert d[30, 30 + k] == pytest.approx(k)
        assert d[30 - k, 30] == pytest.approx(k)
        assert d[30 + k, 30 + k] == pytest.approx(k * math.sqrt(2))
    # offset (2, 1): 1 + sqrt 2 instead of sqrt 5; the ratio approaches 1.0824 near 22.5 degrees
    assert d[32, 31] == pytest.approx(1 + math.sqrt(2))
    ratio = d[30 + 12, 30 + 29] / math.hypot(12, 29)  # 22.48 degrees
    assert ratio == pytest.approx(CHAMFER_MAX_RATIO, abs=2e-3)


@pytest.mark.parametrize("cap", [0.5, 2.0, 7.3, 30.0])
def test_chamfer_is_capped(cap: float) -> None:
    seeds = random_seeds((50, 70), 0.003, 5)
    seeds[10, 10] = True
    d = chamfer_distance(seeds, cap)
    uncapped = chamfer_distance(seeds, 1e9)
    assert d.max() <= cap
    np.testing.assert_allclose(d, np.minimum(uncapped, cap), rtol=0, atol=1e-12)
    exact = ndimage.distance_transform_edt(~seeds)
    assert np.all(d[exact >= cap] == cap)


def test_chamfer_without_seeds_is_the_cap_everywhere() -> None:
    d = chamfer_distance(np.zeros((20, 30), bool), 4.5)
    assert np.all(d == 4.5)


# --------------------------------------------------------------------------------- squared EDT
def flood_fill(mask: NDArray[np.bool_], row: int, col: int) -> NDArray[np.bool_]:
    """flood_known on a plain mask: every cell open, FREE where the mask is True."""
    state = np.where(mask, CellState.FREE, CellState.OCCUPIED).astype(np.int8)
    return flood_known(np.pad(np.ones(mask.shape, bool), 1, constant_values=False), state, row, col)


@pytest.mark.parametrize("seed", range(8))
@pytest.mark.parametrize("density", [0.45, 0.6, 0.75])
def test_flood_fill_equals_the_4_connected_scipy_component(seed: int, density: float) -> None:
    """The planner's 8 steps may not cut corners, which connects exactly what 4 steps do."""
    rng = np.random.default_rng(seed)
    mask = rng.random((37, 53)) < density
    labels, n = ndimage.label(mask)
    assert n > 0
    for r, c in np.argwhere(mask)[rng.integers(np.count_nonzero(mask), size=5)]:
        out = flood_fill(mask, int(r), int(c))
        assert out.dtype == np.bool_ and out.shape == mask.shape
        np.testing.assert_array_equal(out, labels == labels[r, c])


def test_flood_fill_does_not_cross_diagonal_contacts() -> None:
    mask = np.eye(6, dtype=bool)  # the planner cannot cut these corners either
    expected = np.zeros_like(mask)
    expected[0, 0] = True
    np.testing.assert_array_equal(flood_fill(mask, 0, 0), expected)


@pytest.mark.parametrize(("row", "col"), [(0, 1), (-1, 0), (0, -1), (6, 0), (0, 6), (100, 100)])
def test_flood_fill_from_outside_the_mask_is_empty(row: int, col: int) -> None:
    mask = np.eye(6, dtype=bool)
    out = flood_fill(mask, row, col)
    assert out.shape == mask.shape and not out.any()


def test_flood_fill_does_not_modify_its_input() -> None:
    mask = np.ones((5, 5), bool)
    before = mask.copy()
    assert flood_fill(mask, 2, 2).all()
    np.testing.assert_array_equal(mask, before)


@pytest.mark.parametrize("seed", range(5))
def test_flood_known_is_the_free_open_component_of_the_start(seed: int) -> None:
    rng = np.random.default_rng(seed)
    state = rng.choice(
        np.array([CellState.FREE, CellState.UNKNOWN, CellState.OCCUPIED], np.int8), size=(40, 50), p=[0.7, 0.2, 0.1]
    )
    open_ = rng.random((40, 50)) < 0.9
    open_padded = np.pad(open_, 1, constant_values=False)
    mask = open_ & (state == CellState.FREE)
    start = tuple(np.argwhere(mask)[0])
    labels, _ = ndimage.label(mask)
    np.testing.assert_array_equal(flood_known(open_padded, state, *start), labels == labels[start])
    blocked = tuple(np.argwhere(~mask)[0])
    assert not flood_known(open_padded, state, *blocked).any()
