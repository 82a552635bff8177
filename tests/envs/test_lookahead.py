"""The privileged lookahead teacher of model 5 (:mod:`frontier_rl.envs.lookahead`)."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.core.world.worlds import World, make_world
from frontier_rl.envs.lookahead import LOOKAHEAD_WIDTH, cheapest_slots, greedy_finish, lookahead_slot, take_slot

TOP_K = 16


def _rooms() -> OccupancyGrid:
    """A 4 m x 3 m floor: a corridor along the bottom and three rooms above it with doors."""
    data = np.full((60, 80), CellState.FREE, np.int8)
    data[[0, -1], :] = CellState.OCCUPIED
    data[:, [0, -1]] = CellState.OCCUPIED
    data[20, :] = CellState.OCCUPIED
    for wall in (27, 54):
        data[20:, wall] = CellState.OCCUPIED
    for door in (10, 40, 66):
        data[20, door : door + 8] = CellState.FREE
    return OccupancyGrid(data, 0.05)


def _world() -> World:
    return make_world(_rooms(), "rooms", start=Pose(0.5, 0.5, 0.0))


def test_teacher_leaves_the_simulator_as_it_was_and_is_never_slower_than_greedy() -> None:
    sim = ExplorationSimulator(_world(), rng=np.random.default_rng(3))
    checked = 0
    while not sim.finished and not sim.truncated and checked < 6:
        before = (sim.sim_time, sim.pose, sim.coverage)
        slot = lookahead_slot(sim, TOP_K)
        assert (sim.sim_time, sim.pose, sim.coverage) == before
        n = len(cheapest_slots(sim, TOP_K))
        assert 0 <= slot < max(n, 1)
        assert lookahead_slot(sim, TOP_K, width=1) == 0
        ends = []
        for choice in (0, slot):  # a copy replays the same noise: the teacher's pick finishes no later
            trial = copy.deepcopy(sim)
            take_slot(trial, choice, TOP_K)
            ends.append(greedy_finish(trial, TOP_K))
        assert ends[1] <= ends[0]
        take_slot(sim, slot, TOP_K)
        checked += 1
    assert checked == 6


def test_teacher_names_another_slot_only_past_its_margin() -> None:
    sim = ExplorationSimulator(_world(), rng=np.random.default_rng(5))
    for _ in range(4):
        ends = []
        for slot in range(min(LOOKAHEAD_WIDTH, len(cheapest_slots(sim, TOP_K)))):
            trial = copy.deepcopy(sim)
            take_slot(trial, slot, TOP_K)
            ends.append(greedy_finish(trial, TOP_K))
        for margin in (0.0, 0.02, 0.5):
            faster = [i for i in range(1, len(ends)) if ends[i] < ends[0] * (1 - margin)]
            want = min(faster, key=lambda i: (ends[i], i)) if faster else 0
            assert lookahead_slot(sim, TOP_K, margin=margin) == want
        take_slot(sim, 0, TOP_K)
    with pytest.raises(ValueError, match="margin"):
        lookahead_slot(sim, TOP_K, margin=1.0)


def test_greedy_finish_gives_up_past_its_bound() -> None:
    sim = ExplorationSimulator(_world(), rng=np.random.default_rng(0))
    assert greedy_finish(copy.deepcopy(sim), TOP_K, bound_s=1.0) == float("inf")
    end = greedy_finish(sim, TOP_K)
    assert np.isfinite(end) and end == sim.sim_time
