"""Privileged teachers for frontier choice: one step of lookahead on copies of the simulator, and
the labels they give a frontier-choice env for imitation (:func:`expert_action`, :class:`TeacherLabels`).

At a decision a teacher tries ``width`` candidate frontiers, each on a copy of the whole simulator
(true world, map, pose, clock), finishes each copy with a *base* policy, and names the candidate
whose copy explored the map first: a rollout policy (Bertsekas), one step of policy improvement
over the base. It sees what no exploring robot can (the simulator's future), so it is a teacher
for imitation (:mod:`frontier_rl.rl.imitation`) and a reference, never a method. A copy that is
already slower than the best finished one is stopped there (branch and bound), so a label costs
about ``width`` rest-of-episodes at most and usually much less.

Two teachers (:class:`Teacher`):

- model 5's, :data:`GREEDY_TEACHER`: the ``width`` cheapest slots (by planner path cost, the rows
  of model 5's table), finished greedily (always the cheapest slot), each copy on the episode's own
  noise stream;
- model 7's, :data:`TOUR_TEACHER`: the first ``width`` stops of the ``tour`` policy's tour,
  finished with ``tour``, each copy on a *fresh* noise stream (the same for every candidate of a
  decision). On the episode's own stream a copy foresees the noise of the scans to come, and a
  label then names the candidate that was lucky as often as the one that was better; a fresh
  stream keeps only what the true map decides.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import gymnasium as gym
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.sim.episode import decision_context
from frontier_rl.core.sim.metrics import EndReason
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.envs.frontier_env import FrontierChoiceEnv
from frontier_rl.observation.frontier_table import frontier_path_costs, slot_order
from frontier_rl.policies.tour import FrontierTour

LOOKAHEAD_WIDTH = 4
"""Candidate slots tried at a decision: each costs up to one rest-of-episode."""

BASES = ("greedy", "tour")


@dataclass(frozen=True)
class Teacher:
    """A lookahead teacher's settings.

    Attributes:
        base: the policy that finishes every copy and whose own choice is the default label:
            "greedy" (the cheapest slot) or "tour" (the first stop of ``tour``'s tour).
        width: candidates tried at a decision (the base's own first, then the next ones).
        margin: another candidate than the base's is named only if its copy explored the map
            sooner by more than this share of the base candidate's time, in [0, 1).
        fresh_noise: each decision's copies run on a fresh noise stream, spawned from the
            simulator's (which it does not advance), instead of a copy of the episode's own.
    """

    base: str = "greedy"
    width: int = LOOKAHEAD_WIDTH
    margin: float = 0.0
    fresh_noise: bool = False

    def __post_init__(self) -> None:
        if self.base not in BASES:
            raise ValueError(f"base must be one of {', '.join(BASES)}, got {self.base!r}")
        if self.width < 1:
            raise ValueError(f"width must be at least 1, got {self.width!r}")
        if not 0.0 <= self.margin < 1.0:
            raise ValueError(f"margin must be in [0, 1), got {self.margin!r}")


GREEDY_TEACHER = Teacher(margin=0.02)
"""Model 5's teacher for ``train --algo dagger``: a 2 % margin, since smaller gains come from one
rollout's luck (one draw of the noise, one path) as much as from the choice."""

TOUR_TEACHER = Teacher(base="tour", margin=0.10, fresh_noise=True)
"""Model 7's teacher for ``train --algo dagger``. With fresh noise and no margin, one rollout per
candidate is too noisy a judge (a prototype left the tour at half its decisions and was slower than
``tour`` on 7 of 10 worlds); the 10 % margin keeps the few decisions where another stop saves
clearly more. Measured (README, "A teacher that sees the true map"): 12.5 % less time than ``tour``
on 6 DungeonMaps easy maps, but slower on 2 of them, so its labels are still partly noise."""

_TOUR = FrontierTour()


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


def tour_order(sim: ExplorationSimulator) -> NDArray[np.int64]:
    """The ``tour`` policy's ranking of the robot's frontiers: its tour's stops first, in order
    (``tour`` draws nothing from its generator)."""
    return _TOUR.rank(decision_context(sim), np.random.default_rng(0)).order


def take_tour_stop(sim: ExplorationSimulator) -> None:
    """Drive as the ``tour`` policy does: to its tour's first stop, the next ones if it fails."""
    sim.execute(tour_order(sim))


def finish(sim: ExplorationSimulator, step: Callable[[ExplorationSimulator], None], bound_s: float = math.inf) -> float:
    """Explore on with ``step`` taking every decision; the sim time (s) at which the map is
    explored, inf if the episode ends otherwise (it must not win by giving up) or passes ``bound_s``."""
    while not sim.truncated and not sim.finished:
        if sim.sim_time >= bound_s:
            return math.inf
        step(sim)
    return sim.sim_time if sim.end_reason() is EndReason.EXPLORED else math.inf


def greedy_finish(sim: ExplorationSimulator, top_k: int, bound_s: float = math.inf) -> float:
    """:func:`finish`, always to the cheapest slot."""
    return finish(sim, lambda s: take_slot(s, 0, top_k), bound_s)


def candidate_slots(sim: ExplorationSimulator, top_k: int, teacher: Teacher) -> NDArray[np.int64]:
    """The slots ``teacher`` tries, its base's choice first: the cheapest ``width`` (greedy), or
    the slots of the tour's first ``width`` stops that are among the ``top_k`` cheapest (tour)."""
    slots = cheapest_slots(sim, top_k)
    if teacher.base == "greedy" or len(slots) == 0:
        return np.arange(min(teacher.width, len(slots)), dtype=np.int64)
    slot_of = {int(frontier): slot for slot, frontier in enumerate(slots)}
    picked = [slot_of[int(f)] for f in tour_order(sim) if int(f) in slot_of][: teacher.width]
    return np.asarray(picked, np.int64)


def teacher_slot(sim: ExplorationSimulator, top_k: int, teacher: Teacher) -> int:
    """The slot (0 = cheapest) that ``teacher`` names for ``sim``'s decision: the candidate whose
    copy, finished by the base, explores the map first; ties and all-inf go to the base's choice.
    ``sim`` is not changed (with ``fresh_noise`` its generator spawns one child)."""
    candidates = candidate_slots(sim, top_k, teacher)
    if len(candidates) == 0:
        return 0
    step = (lambda s: take_slot(s, 0, top_k)) if teacher.base == "greedy" else take_tour_stop
    noise = sim.rng.spawn(1)[0].bit_generator.state if teacher.fresh_noise else None
    best, bound = int(candidates[0]), math.inf  # a copy must end before ``bound`` to be named
    for k, slot in enumerate(candidates):
        trial = copy.deepcopy(sim)
        if noise is not None:
            trial.rng.bit_generator.state = noise
        take_slot(trial, int(slot), top_k)
        end = finish(trial, step, bound)
        if k == 0:
            bound = end * (1.0 - teacher.margin)
        elif end < bound:
            best, bound = int(slot), end
    return best


def lookahead_slot(sim: ExplorationSimulator, top_k: int, width: int = LOOKAHEAD_WIDTH, margin: float = 0.0) -> int:
    """Model 5's teacher (:func:`teacher_slot` with the greedy base on the episode's own noise):
    the slot among the ``width`` cheapest whose copy, finished greedily, explores the map first."""
    return teacher_slot(sim, top_k, Teacher(width=width, margin=margin))


def expert_action(env: gym.Env[Any, Any], teacher: Teacher | None = None) -> int:
    """The privileged teacher's action for the current decision of ``env`` (a frontier-choice env,
    :class:`~frontier_rl.envs.frontier_env.FrontierChoiceEnv`, however wrapped): one step of
    lookahead on copies of its simulator (:func:`teacher_slot`; it sees the true world).
    ``teacher`` defaults to the model's: :data:`TOUR_TEACHER` with the tour column (model 7),
    else :data:`GREEDY_TEACHER`."""
    choice = env.unwrapped
    if not isinstance(choice, FrontierChoiceEnv):
        raise TypeError(f"a teacher labels frontier-choice decisions, not those of {type(choice).__name__}")
    if teacher is None:
        teacher = TOUR_TEACHER if choice.tour else GREEDY_TEACHER
    return teacher_slot(choice.sim, choice.top_k, teacher)


class TeacherLabels(gym.Wrapper[Any, Any, Any, Any]):
    """A frontier-choice env whose ``expert_action()`` is its teacher's label (:func:`expert_action`):
    what DAgger asks each env of a vectorised set for (``env_method("expert_action")``)."""

    def expert_action(self) -> int:
        """The teacher's action for the current decision."""
        return expert_action(self.env)
