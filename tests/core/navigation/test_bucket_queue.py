"""The bucket queue shared by the planner's Dijkstra searches: its ring and its relaxation step."""

from __future__ import annotations

import math

import numpy as np
import pytest

from frontier_rl.core.navigation.bucket_queue import bucket_ring_mask, neighbour_steps, relax_neighbours


@pytest.mark.parametrize("factor", [0.5, 1.0, 3.0, 7.9, 100.0])
def test_the_ring_spans_more_buckets_than_a_step_and_its_size_is_a_power_of_two(factor: float) -> None:
    mask = bucket_ring_mask(factor)
    assert (mask + 1) & mask == 0  # 2^k - 1
    assert mask + 1 >= math.sqrt(2.0) * max(factor, 1.0) + 2


def test_relaxing_a_cell_pushes_its_open_neighbours_and_never_cuts_a_corner() -> None:
    # a padded 3 x 3 grid (5 x 5 with its closed border); the cell north of the centre is a wall
    open_padded = np.zeros((5, 5), np.bool_)
    open_padded[1:4, 1:4] = True
    open_padded[1, 2] = False
    cost = np.ones(25) * 2.0
    g, closed = np.full(25, np.inf), np.zeros(25, np.bool_)
    centre = 2 * 5 + 2
    g[centre], closed[centre] = 0.0, True
    mask = bucket_ring_mask(2.0)
    head, node, link = np.full(mask + 1, -1, np.int64), np.empty(64, np.int64), np.empty(64, np.int64)
    touched = np.empty(25, np.int64)
    used, pushed, n_touched = relax_neighbours(
        centre, g, closed, open_padded.reshape(-1), cost, neighbour_steps(5), (head, node, link), mask, 0, touched, 0
    )
    reached = {int(c): float(g[c]) for c in touched[:n_touched]}
    # three sides at 2 (length 1 x factor 2) and the two southern diagonals at 2√2; not the wall,
    # nor the northern diagonals, which would pass its corner
    assert used == pushed == n_touched == 5
    assert reached == {
        3 * 5 + 2: 2.0,
        2 * 5 + 1: 2.0,
        2 * 5 + 3: 2.0,
        3 * 5 + 1: pytest.approx(2 * math.sqrt(2.0)),
        3 * 5 + 3: pytest.approx(2 * math.sqrt(2.0)),
    }
    # one entry each, in the bucket of its integer cost: 2 and 2√2 ≈ 2.83 both fall in bucket 2
    assert sorted(_bucket(head, node, link, 2)) == sorted(reached)


def _bucket(head: np.ndarray, node: np.ndarray, link: np.ndarray, slot: int) -> list[int]:
    found, entry = [], int(head[slot])
    while entry >= 0:
        found.append(int(node[entry]))
        entry = int(link[entry])
    return found
