"""The privileged lookahead teachers of models 5 and 7 (:mod:`frontier_rl.rl.teacher`)."""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest

from frontier_rl.core.sim.episode import decision_context
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.core.world.worlds import World, make_world
from frontier_rl.envs.frontier_env import FrontierChoiceEnv
from frontier_rl.io.ros_map import save_ros_map
from frontier_rl.policies.tour import FrontierTour
from frontier_rl.rl.teacher import (
    LOOKAHEAD_WIDTH,
    TOUR_TEACHER,
    Teacher,
    candidate_slots,
    cheapest_slots,
    expert_action,
    finish,
    greedy_finish,
    lookahead_slot,
    take_slot,
    take_tour_stop,
    teacher_slot,
)

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


def _tour_ends(sim: ExplorationSimulator, teacher: Teacher) -> tuple[list[int], list[float]]:
    """The tour teacher's candidate slots and each one's end time, worked out as it must: every
    copy on the fresh stream the teacher's next spawn gives, finished with ``tour``."""
    noise = copy.deepcopy(sim).rng.spawn(1)[0].bit_generator.state
    slots = [int(s) for s in candidate_slots(sim, TOP_K, teacher)]
    ends = []
    for slot in slots:
        trial = copy.deepcopy(sim)
        trial.rng.bit_generator.state = noise
        take_slot(trial, slot, TOP_K)
        ends.append(finish(trial, take_tour_stop))
    return slots, ends


def test_tour_teacher_starts_from_the_tours_first_stop_and_leaves_the_noise_stream_alone() -> None:
    sim = ExplorationSimulator(_world(), rng=np.random.default_rng(np.random.SeedSequence(4)))
    for _ in range(3):
        slots = cheapest_slots(sim, TOP_K)
        tour = FrontierTour().rank(decision_context(sim), np.random.default_rng(0)).order
        candidates = candidate_slots(sim, TOP_K, TOUR_TEACHER)
        assert [int(slots[c]) for c in candidates] == [int(f) for f in tour[: len(candidates)]]
        assert len(candidates) == min(LOOKAHEAD_WIDTH, len(tour))
        before = (sim.sim_time, sim.pose, sim.coverage, sim.rng.bit_generator.state)
        assert teacher_slot(sim, TOP_K, Teacher(base="tour", width=1, fresh_noise=True)) == candidates[0]
        teacher_slot(sim, TOP_K, TOUR_TEACHER)
        assert (sim.sim_time, sim.pose, sim.coverage, sim.rng.bit_generator.state) == before
        take_tour_stop(sim)


def test_tour_teacher_names_another_stop_only_past_its_margin() -> None:
    sim = ExplorationSimulator(_world(), rng=np.random.default_rng(np.random.SeedSequence(6)))
    for _ in range(3):
        for margin in (0.0, 0.1, 0.5):
            teacher = Teacher(base="tour", margin=margin, fresh_noise=True)
            probe = copy.deepcopy(sim)
            slots, ends = _tour_ends(probe, teacher)
            faster = [i for i in range(1, len(ends)) if ends[i] < ends[0] * (1 - margin)]
            want = slots[min(faster, key=lambda i: (ends[i], i))] if faster else slots[0]
            assert teacher_slot(probe, TOP_K, teacher) == want
        take_tour_stop(sim)


def test_model_7s_env_asks_the_tour_teacher_and_model_5s_the_greedy_one(tmp_path: Path) -> None:
    map_file = save_ros_map(_rooms(), tmp_path / "rooms.yaml")
    for tour in (False, True):
        env = FrontierChoiceEnv(worlds=(str(map_file),), max_decisions=24, tour=tour)
        env.reset(seed=3)
        env.step(0)
        probe = copy.deepcopy(env.sim)
        want = teacher_slot(probe, env.top_k, TOUR_TEACHER) if tour else lookahead_slot(probe, env.top_k, margin=0.02)
        assert expert_action(env) == want


@pytest.mark.parametrize(
    ("changes", "message"), [({"base": "oracle"}, "base"), ({"width": 0}, "width"), ({"margin": 1.0}, "margin")]
)
def test_teacher_settings_are_checked(changes: dict[str, object], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        Teacher(**changes)  # type: ignore[arg-type]
