"""A privileged teacher for frontier choice: one step of lookahead on copies of the simulator.

At a decision it tries each of the ``width`` cheapest candidate frontiers (by planner path cost,
the slots of model 5's table) on a copy of the whole simulator (true world, map, pose, clock and
noise stream), finishes each copy with the *greedy* policy that always takes the cheapest slot,
and names the slot whose copy explored the map first: a rollout policy (Bertsekas), one step of
policy improvement over the greedy one. It sees what no exploring robot can (the simulator's
future), so it is a teacher for imitation (:mod:`frontier_rl.rl.imitation`) and a reference, never
a method. A copy that is already slower than the best finished one is stopped there (branch and
bound), so a label costs about ``width`` rest-of-episodes at most and usually much less.
"""

from __future__ import annotations

import copy
import math

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.sim.episode_log import EndReason
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.observation.frontier_table import frontier_path_costs, slot_order

LOOKAHEAD_WIDTH = 4
"""Candidate slots tried at a decision (the cheapest four): each costs up to one rest-of-episode."""


def cheapest_slots(sim: ExplorationSimulator, top_k: int) -> NDArray[np.int64]:
    """Indices of the robot's ``top_k`` candidate frontiers with the lowest planner path cost,
    cheapest first (the slots of model 5's table, :func:`frontier_observation`)."""
    cand = sim.candidates()
    if len(cand.frontiers) == 0:
        return np.zeros(0, np.int64)
    costs = frontier_path_costs(cand.costmap, sim.pose, cand.frontiers, sim.config.robot.radius, want=top_k)
    return np.argsort(costs, kind="stable")[:top_k].astype(np.int64)


def take_slot(sim: ExplorationSimulator, slot: int, top_k: int) -> None:
    """Drive to the frontier of ``slot`` (as model 5's env does), the next cheapest if it fails."""
    slots = cheapest_slots(sim, top_k)
    sim.execute(slot_order(slots, slot) if len(slots) else slots)


def greedy_finish(sim: ExplorationSimulator, top_k: int, bound_s: float = math.inf) -> float:
    """Explore on, always to the cheapest slot; the sim time (s) at which the map is explored,
    inf if the episode ends otherwise (it must not win by giving up) or passes ``bound_s``."""
    while not sim.truncated and not sim.finished:
        if sim.sim_time >= bound_s:
            return math.inf
        take_slot(sim, 0, top_k)
    return sim.sim_time if sim.end_reason() is EndReason.EXPLORED else math.inf


def lookahead_slot(sim: ExplorationSimulator, top_k: int, width: int = LOOKAHEAD_WIDTH, margin: float = 0.0) -> int:
    """The slot (0 = cheapest) among the ``width`` cheapest whose copy of ``sim``, finished
    greedily, explores the map first; ties and all-inf go to the cheaper slot. Another slot than
    the cheapest is named only if its copy is faster by more than ``margin`` (a share of the
    cheapest slot's time). ``sim`` is not changed."""
    if not 0.0 <= margin < 1.0:
        raise ValueError(f"margin must be in [0, 1), got {margin!r}")
    n = min(width, len(cheapest_slots(sim, top_k)))
    best, bound = 0, math.inf  # a copy must end before ``bound`` to be named
    for slot in range(n):
        trial = copy.deepcopy(sim)
        take_slot(trial, slot, top_k)
        end = greedy_finish(trial, top_k, bound)
        if slot == 0:
            bound = end * (1.0 - margin)
        elif end < bound:
            best, bound = slot, end
    return best
