"""The decision interface between policies and the simulator, and the single-robot episode loop."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

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

_MAX_STALLED_DECISIONS = 1000


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
    """

    grid: OccupancyGrid
    frontiers: Frontiers
    pose: Pose
    sim_time: float
    sensor_range: float
    costmap: Costmap | None = None


@dataclass(frozen=True)
class Ranking:
    """A policy's answer: frontier indices best first, and the weight it used (if any); or, for
    point-goal policies, a ``goal`` (x, y) in m to drive to instead (``order`` is then ignored)."""

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
    return DecisionContext(cand.grid, cand.frontiers, sim.pose, sim.sim_time, sim.config.lidar.max_range, cand.costmap)


def run_episode(
    world: World,
    policy: ExplorationPolicy,
    config: SimConfig | None = None,
    seed: int | np.random.Generator = 0,
    on_decision: Callable[[ExplorationSimulator, DecisionContext, Ranking], None] | None = None,
) -> EpisodeResult:
    """Explore ``world`` with ``policy`` until no frontier is left or the sim-time cap.

    ``seed`` drives the sensor noise and any randomness of the policy (two independent streams
    spawned from it), so the same seed gives the same episode bit for bit. ``on_decision`` is
    called at every decision, before the robot drives (to record frames, log weights, ...); its
    time is not counted in the episode's wall time.
    """
    root = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    sim_rng, policy_rng = root.spawn(2)
    started = time.perf_counter()
    hook_time = 0.0
    sim = ExplorationSimulator(world, config, sim_rng)
    if isinstance(policy, EpisodeAwarePolicy):
        policy.begin_episode(world, sim.config)
    stalled = 0  # decisions in a row that took no simulated time: a bug guard, never a hang
    while not sim.truncated and not sim.finished:
        if stalled > _MAX_STALLED_DECISIONS:
            raise RuntimeError(
                f"episode on {world.name!r} stalled: {stalled} decisions in a row took no simulated time "
                f"at t = {sim.sim_time:.1f} s"
            )
        before = sim.sim_time
        context = decision_context(sim)
        ranking = policy.rank(context, policy_rng)
        if on_decision is not None:
            hook_started = time.perf_counter()
            on_decision(sim, context, ranking)
            hook_time += time.perf_counter() - hook_started
        if ranking.goal is not None:
            sim.go_to(*ranking.goal, ranking.weight)
        else:
            sim.execute(ranking.order, ranking.weight)
        stalled = stalled + 1 if sim.sim_time == before else 0
    return sim.result(time.perf_counter() - started - hook_time)


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
