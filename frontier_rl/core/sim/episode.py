"""The decision interface between policies and the simulator, and the single-robot episode loop."""

from __future__ import annotations

import math
import numbers
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import NoReturn, Protocol, TypeVar, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.frontiers.detection import Frontiers
from frontier_rl.core.navigation.costmap import Costmap
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.metrics import EpisodeResult
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.grid import OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.core.world.worlds import World
from frontier_rl.errors import PolicyError, short_repr

_MAX_STALLED_DECISIONS = 1000
_SHORT_ORDER = 64
"""Up to this many indices, an order is checked in Python; beyond, in NumPy (faster on long ones)."""


@dataclass(frozen=True)
class DecisionContext:
    """What a policy sees at a decision.

    Attributes:
        grid: the robot's current map.
        frontiers: the candidate frontiers (reachable, not blacklisted, at least one).
        pose: the robot's pose (m, rad).
        sim_time: sim time of the decision (s).
        sensor_range: the LiDAR's maximum range (m), for information-gain estimates.
        costmap: the navigator's costmap of ``grid``, when the caller has one (the simulator does).
        robot_radius: the robot's radius (m), which sets the blocks a large map's path costs are
            searched on; the run's, so that a policy never assumes the default robot.
    """

    grid: OccupancyGrid
    frontiers: Frontiers
    pose: Pose
    sim_time: float
    sensor_range: float
    costmap: Costmap | None = None
    robot_radius: float = field(kw_only=True)


@dataclass(frozen=True)
class Ranking:
    """A policy's answer: frontier indices best first, and the weight w in [0, 1] of the cost it
    ranked by (if any: ``w·d + (1−w)·(1−g)``, for the reports' weight plots); or, for
    point-goal policies, a ``goal`` (x, y) in m to drive to instead (``order`` is then ignored).

    ``order`` is a 1-D NumPy array of distinct candidate indices (any integer type), at least one
    unless ``goal`` is set; the episode runner refuses anything else (:func:`checked_ranking`)."""

    order: NDArray[np.int64]
    weight: float | None = None
    goal: tuple[float, float] | None = None


class ExplorationPolicy(Protocol):
    """Anything that ranks the candidate frontiers of a decision."""

    @property
    def name(self) -> str:
        """The policy's name, as given on the command line."""
        ...

    def rank(self, context: DecisionContext, rng: np.random.Generator) -> Ranking:
        """Order the candidates of ``context``, best first."""
        ...


@runtime_checkable
class EpisodeAwarePolicy(Protocol):
    """A policy that must know the episode before its first decision: :func:`run_episode` calls
    ``begin_episode`` with the ground-truth world and the settings. Only reference methods that are
    allowed to see the true map (the full-knowledge ``oracle``) implement it."""

    def begin_episode(self, world: World, config: SimConfig) -> None:
        """Prepare for an episode on ``world`` under ``config``."""
        ...


def decision_context(sim: ExplorationSimulator) -> DecisionContext:
    """The policy's view of the simulator's current state."""
    cand = sim.candidates()
    config = sim.config
    return DecisionContext(
        cand.grid,
        cand.frontiers,
        sim.pose,
        sim.sim_time,
        config.lidar.max_range,
        cand.costmap,
        robot_radius=config.robot.radius,
    )


class DecisionLoop(Protocol):
    """A simulation as the episode runner drives it: one robot (:class:`SingleRobotLoop`) or a
    team (:class:`~frontier_rl.swarm.team.TeamSimulator`). Each guards against decisions that take
    no simulated time in its own way (a team's robots may decide at one instant)."""

    @property
    def config(self) -> SimConfig:
        """The settings the simulation runs with (after fitting the world)."""
        ...

    def next_decision(self) -> int | None:
        """Run the clock until a robot must decide: its index, or None when the episode is over."""
        ...

    def context(self, index: int) -> DecisionContext:
        """What robot ``index``'s policy sees."""
        ...

    def assign(self, index: int, ranking: Ranking) -> None:
        """Start robot ``index`` on ``ranking``'s choice."""
        ...


LoopT = TypeVar("LoopT", bound=DecisionLoop)


def drive_episode(
    make_loop: Callable[[np.random.Generator], LoopT],
    world: World,
    policy: ExplorationPolicy,
    seed: int | np.random.Generator = 0,
    robots: int = 1,
    on_decision: Callable[[LoopT, DecisionContext, Ranking], None] | None = None,
) -> tuple[LoopT, float]:
    """The episode runner of single robots and teams: ask ``policy`` at every decision of the loop
    ``make_loop`` builds, until the loop ends. Returns the loop and the wall time (s), less the
    hook's time, for the loop's result.

    ``seed`` gives two independent streams, the simulation's (handed to ``make_loop``) and the
    policy's; robot 0 ranks with the policy's stream and the others with streams spawned from it,
    so the same seed gives the same episode bit for bit, and a one-robot team the single robot's.
    ``on_decision`` is called at every decision, before the robot drives.
    """
    root = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    sim_rng, policy_rng = root.spawn(2)
    started = time.perf_counter()
    hook_time = 0.0
    loop = make_loop(sim_rng)
    if isinstance(policy, EpisodeAwarePolicy):
        policy.begin_episode(world, loop.config)
    policy_rngs = [policy_rng, *policy_rng.spawn(robots - 1)]
    while (index := loop.next_decision()) is not None:
        context = loop.context(index)
        ranking = checked_ranking(policy.rank(context, policy_rngs[index]), len(context.frontiers), policy)
        if on_decision is not None:
            hook_started = time.perf_counter()
            on_decision(loop, context, ranking)
            hook_time += time.perf_counter() - hook_started
        loop.assign(index, ranking)
    return loop, time.perf_counter() - started - hook_time


def checked_ranking(ranking: object, candidates: int, policy: ExplorationPolicy) -> Ranking:
    """``ranking``, the answer of ``policy`` to a decision among ``candidates`` frontiers, if the
    simulator can follow it: a :class:`Ranking` whose ``order`` is a 1-D integer array of distinct
    candidate indices, empty only where it sets a ``goal`` (or there is no candidate), whose ``goal``
    is two finite numbers (m) and whose ``weight`` a finite number, where they are set.

    Raises:
        PolicyError: what is wrong, naming the policy, in one line.
    """
    if not isinstance(ranking, Ranking):
        _refuse(policy, f"rank() returned {_described(ranking)}, not a Ranking")
    order = ranking.order
    if not isinstance(order, np.ndarray) or order.ndim != 1 or order.dtype.kind not in "iu":
        _refuse(policy, f"its Ranking's order is {_described(order)}, not a 1-D integer array of candidate indices")
    if order.size and (problem := _order_problem(order, candidates)):
        _refuse(policy, f"its Ranking's order {problem}")
    if not order.size and ranking.goal is None and candidates:
        _refuse(policy, f"its Ranking's order is empty and it sets no goal: rank the {candidates} candidate(s)")
    if ranking.goal is not None and not _is_point(ranking.goal):
        _refuse(policy, f"its Ranking's goal is {_described(ranking.goal)}, not a point (x, y) of finite metres")
    if ranking.weight is not None and not (_is_finite_number(ranking.weight) and 0 <= ranking.weight <= 1):
        _refuse(policy, f"its Ranking's weight is {_described(ranking.weight)}, not a number in [0, 1]")
    return ranking


def _order_problem(order: NDArray[np.integer], candidates: int) -> str | None:
    """What is wrong with a non-empty ``order`` of indices among ``candidates`` frontiers, or None."""
    distinct: bool | None = None
    if order.size <= _SHORT_ORDER:  # a few Python calls: cheaper than NumPy's on a short order
        indices = order.tolist()
        low, high, distinct = min(indices), max(indices), len(set(indices)) == len(indices)
    else:
        low, high = int(order.min()), int(order.max())
    if low < 0 or high >= candidates:
        among = f"0 to {candidates - 1}" if candidates else "there is none"
        return f"holds {low if low < 0 else high}, not a candidate's index ({among})"
    if distinct is None:
        seen = np.zeros(candidates, np.bool_)
        seen[order] = True
        distinct = np.count_nonzero(seen) == order.size
    if not distinct:
        values, counts = np.unique(order, return_counts=True)
        return f"lists candidate {values[counts > 1][0]} more than once"
    return None


def _refuse(policy: ExplorationPolicy, problem: str) -> NoReturn:
    name = getattr(policy, "name", None)
    raise PolicyError(f"policy {short_repr(name if isinstance(name, str) else type(policy).__name__)}: {problem}")


def _described(value: object) -> str:
    """A value for a message: an array's type and shape, another value's repr (cut short) and type."""
    if isinstance(value, np.ndarray):
        return f"an array of {value.dtype} with shape {value.shape}"
    return f"{short_repr(value, 40)} (type {type(value).__name__})"


def _is_finite_number(value: object) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool) and math.isfinite(value)


def _is_point(value: object) -> bool:
    """Whether ``value`` is a pair of finite numbers."""
    if isinstance(value, np.ndarray) and value.ndim != 1:
        return False
    return isinstance(value, tuple | list | np.ndarray) and len(value) == 2 and all(map(_is_finite_number, value))


class SingleRobotLoop:
    """One robot's simulator as a :class:`DecisionLoop`."""

    def __init__(self, sim: ExplorationSimulator) -> None:
        self.sim = sim
        self._stalled = 0  # decisions in a row that took no simulated time: a bug guard, never a hang

    @property
    def config(self) -> SimConfig:
        """The simulator's settings."""
        return self.sim.config

    def next_decision(self) -> int | None:
        """0 while the robot has frontiers left and time, else None."""
        return None if self.sim.truncated or self.sim.finished else 0

    def context(self, index: int) -> DecisionContext:
        """The robot's view (:func:`decision_context`)."""
        return decision_context(self.sim)

    def assign(self, index: int, ranking: Ranking) -> None:
        """Drive the leg ``ranking`` chooses to its end.

        Raises:
            RuntimeError: more than 1000 decisions in a row took no simulated time, and the
                episode is not over.
        """
        before = self.sim.sim_time
        if ranking.goal is not None:
            self.sim.go_to(*ranking.goal, ranking.weight)
        else:
            self.sim.execute(ranking.order, ranking.weight)
        self._stalled = self._stalled + 1 if self.sim.sim_time == before else 0
        if self._stalled > _MAX_STALLED_DECISIONS and self.next_decision() is not None:
            raise RuntimeError(
                f"episode on {self.sim.world.name!r} stalled: {self._stalled} decisions in a row took no "
                f"simulated time at t = {self.sim.sim_time:.1f} s"
            )


def run_episode(
    world: World,
    policy: ExplorationPolicy,
    config: SimConfig | None = None,
    seed: int | np.random.Generator = 0,
    on_decision: Callable[[ExplorationSimulator, DecisionContext, Ranking], None] | None = None,
) -> EpisodeResult:
    """Explore ``world`` with ``policy`` until no frontier is left or the sim-time cap.

    ``seed`` drives the sensor noise and any randomness of the policy (two independent streams
    spawned from it, :func:`drive_episode`), so the same seed gives the same episode bit for bit.
    ``on_decision`` is called at every decision, before the robot drives (to record frames, log
    weights, ...); its time is not counted in the episode's wall time.
    """

    def single_robot(rng: np.random.Generator) -> SingleRobotLoop:
        return SingleRobotLoop(ExplorationSimulator(world, config, rng))

    def hook(loop: SingleRobotLoop, context: DecisionContext, ranking: Ranking) -> None:
        assert on_decision is not None
        on_decision(loop.sim, context, ranking)

    loop, wall_time = drive_episode(
        single_robot, world, policy, seed, on_decision=None if on_decision is None else hook
    )
    return loop.sim.result(wall_time)


def warm_up(policy: ExplorationPolicy | None = None) -> None:
    """Run a tiny episode so that every compiled kernel is loaded (or compiled) before timing;
    with ``policy`` instead of the nearest frontier, its kernels too."""
    from frontier_rl.core.world.grid import CellState, OccupancyGrid
    from frontier_rl.core.world.worlds import make_world

    data = np.full((40, 40), CellState.FREE, np.int8)
    data[[0, -1], :] = CellState.OCCUPIED
    data[:, [0, -1]] = CellState.OCCUPIED
    data[20:22, :28] = CellState.OCCUPIED
    world = make_world(OccupancyGrid(data, 0.05), "warm-up", start=Pose(0.5, 0.5, 0.0))

    class _Nearest:
        name = "nearest"

        def rank(self, context: DecisionContext, rng: np.random.Generator) -> Ranking:
            context.frontiers.information_gain(context.sensor_range)  # compiles its kernel too
            return Ranking(np.argsort(context.frontiers.distances, kind="stable"))

    run_episode(world, policy or _Nearest(), seed=0)
