"""Burgard-style coordination on top of a policy's ranking."""

from __future__ import annotations

import numpy as np

from frontier_rl.swarm.coordination import coordinated_order

CENTRES = np.array([[0.0, 0.0], [5.0, 0.0], [10.0, 0.0], [0.5, 0.0]])


def test_without_claims_the_policy_order_stands() -> None:
    order = np.array([3, 0, 2, 1])
    assert np.array_equal(coordinated_order(CENTRES, order, np.zeros((0, 2)), 1.0, 3.0), order)


def test_a_claimed_frontier_goes_last_and_its_neighbours_drop() -> None:
    order = np.array([0, 3, 1, 2])  # the policy likes 0 and its neighbour 3 best
    out = coordinated_order(CENTRES, order, np.array([[0.0, 0.0]]), claim_radius=0.2, coordination_range=3.0)
    assert out[-1] == 0  # taken by a teammate
    assert list(out[:2]) == [1, 2]  # 3 lies 0.5 m from the claim: its utility drops below 1 and 2's
    assert sorted(out) == sorted(order)


def test_a_claimed_frontier_is_taken_when_nothing_else_is_left() -> None:
    out = coordinated_order(CENTRES[:1], np.array([0]), np.array([[0.0, 0.0]]), 1.0, 3.0)
    assert list(out) == [0]


def test_every_frontier_claimed_keeps_the_policy_order() -> None:
    claims = CENTRES.copy()
    order = np.array([2, 0, 1, 3])
    out = coordinated_order(CENTRES, order, claims, claim_radius=0.1, coordination_range=0.1)
    assert list(out) == [2, 0, 1, 3]
