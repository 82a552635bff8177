"""A team of robots exploring one world on one shared clock.

Every robot is an :class:`~frontier_rl.core.sim.simulator.ExplorationSimulator` with its own LiDAR,
noise stream and map; they share the ground truth. The scheduler always advances the robot whose
clock is furthest behind by one step of its leg (up to its next map update, about 0.5 s), so the
robots' clocks never drift apart by more than a step. Before its step a robot is told where the
others are: its follower collides with them and its planner goes around them. After a map update
it shares the scan's window with every teammate in communication range (a pair that comes into
range first merges whole maps), a cell taken from the map that has looked at it more often
(:meth:`~frontier_rl.core.mapping.mapper.LogOddsMapper.merge_from`).
"""

from __future__ import annotations

import math
import time
from collections.abc import Generator
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.mapping.mapper import LogOddsMapper
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import DecisionContext, Ranking, decision_context
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.grid import OccupancyGrid
from frontier_rl.core.world.worlds import World
from frontier_rl.swarm.config import Strategy, TeamConfig
from frontier_rl.swarm.coordination import coordinated_order
from frontier_rl.swarm.knowledge import TeamKnowledge
from frontier_rl.swarm.rendezvous import Phase, RendezvousCycle
from frontier_rl.swarm.result import TeamResult
from frontier_rl.swarm.starts import team_starts
from frontier_rl.swarm.team_result import team_result

_MAX_STALLED_DECISIONS = 1000

Leg = Generator[None, None, object]


@dataclass(eq=False)
class TeamRobot:
    """One robot of a team.

    Attributes:
        index: its id, 0 to robots - 1.
        sim: its simulator (pose, clock, map).
        fail_at: sim time (s) at which it fails; inf if never.
        failed_at: when it did fail (s), None while it works.
        leg: the leg under way, None when it needs a decision.
        phase: its rendezvous phase.
    """

    index: int
    sim: ExplorationSimulator
    fail_at: float = math.inf
    failed_at: float | None = None
    leg: Leg | None = None
    phase: Phase = Phase.EXPLORE
    stalled: int = 0

    @property
    def alive(self) -> bool:
        """Whether it still works."""
        return self.failed_at is None

    @property
    def xy(self) -> tuple[float, float]:
        """Its position (m)."""
        return self.sim.pose.x, self.sim.pose.y

    def drop_leg(self) -> None:
        """Abandon the leg under way (the robot stops where it is)."""
        if self.leg is not None:
            self.leg.close()
            self.leg = None


class TeamSimulator:
    """Several robots exploring one world; drive it with :meth:`next_decision` and :meth:`assign`.

    Args:
        world: the ground truth; robot 0 starts on its start pose, the others beside it.
        config: simulation settings, the same for every robot.
        team: team size, strategy, communication range, failures.
        rng: robot 0's noise stream; the other robots' and the random failures' are spawned from
            it, so a one-robot team reproduces the single-robot episode bit for bit.
    """

    def __init__(
        self,
        world: World,
        config: SimConfig | None = None,
        team: TeamConfig | None = None,
        rng: np.random.Generator | None = None,
    ) -> None:
        self.config = config or SimConfig()
        self.world = world = self.config.fit_world(world)
        self.team = team or TeamConfig()
        rng = rng if rng is not None else np.random.default_rng(0)
        n = self.team.robots
        starts = team_starts(world, n, self.config.robot.radius, self.team.spacing_for(self.config.robot.radius))
        streams = [rng, *rng.spawn(n - 1)]
        xy = np.array([(pose.x, pose.y) for pose in starts])
        self.robots = [
            TeamRobot(i, ExplorationSimulator(replace(world, start=pose), self.config, stream, np.delete(xy, i, 0)))
            for i, (pose, stream) in enumerate(zip(starts, streams, strict=True))
        ]
        self._draw_failures(rng.spawn(1)[0])
        self._range = self.team.range_m
        self._contact = np.zeros((n, n), np.bool_)
        mapper_cfg = self.config.mapper
        self._reach = int(math.ceil(mapper_cfg.usable_range / world.grid.resolution)) + 2
        self._knowledge = TeamKnowledge(world.explorable)
        self._over = False
        self._done = False
        self._started = time.perf_counter()
        self.rendezvous = RendezvousCycle(self) if self.team.strategy is Strategy.RENDEZVOUS else None
        for robot in self.robots:
            self._share(robot, full=True)
        self._recount()

    # ------------------------------------------------------------------ state
    @property
    def alive(self) -> list[TeamRobot]:
        """The robots that still work."""
        return [r for r in self.robots if r.alive]

    @property
    def sim_time(self) -> float:
        """The team's clock (s): the furthest any robot has got."""
        return max(r.sim.sim_time for r in self.robots)

    @property
    def over(self) -> bool:
        """Whether the episode has ended (explored, cut off at the cap, or no robot left)."""
        return self._over

    @property
    def done(self) -> bool:
        """Whether the team ended by itself: no surviving robot has a frontier left."""
        return self._done

    @property
    def truncated(self) -> bool:
        """Whether the sim-time cap ended the episode."""
        return self._over and not self._done and any(r.alive and r.sim.truncated for r in self.robots)

    @property
    def known_cells(self) -> int:
        """Explorable cells the surviving robots know."""
        return self._knowledge.count

    @property
    def known(self) -> NDArray[np.bool_]:
        """The cells a surviving robot knows (the world's shape; read only)."""
        return self._knowledge.known

    @property
    def coverage(self) -> float:
        """Share of the explorable cells the surviving robots know."""
        return self.known_cells / max(self.world.explorable_count, 1)

    # ------------------------------------------------------------- decisions
    def next_decision(self) -> int | None:
        """Run the shared clock until a robot needs a decision: its index, or None at the end."""
        while not self._over:
            alive = self.alive
            if not alive:
                self._over = True
                break
            if self.rendezvous is not None:
                commander = self.rendezvous.commander_to_decide()
                if commander is not None:
                    return commander.index
            robot = min(alive, key=lambda r: (r.sim.sim_time, r.index))
            if robot.sim.truncated:
                self._over = True
                break
            if robot.sim.sim_time >= robot.fail_at:
                self.fail(robot)
                continue
            if self.rendezvous is not None:
                self.rendezvous.before_step(robot)
                if self.rendezvous.needs_point:  # a meeting was just held: the commander decides first
                    continue
            if robot.leg is None:
                if len(robot.sim.frontiers()):
                    return robot.index
                if all(len(r.sim.frontiers()) == 0 for r in alive):
                    self._over = self._done = True
                    break
                robot.leg = robot.sim.wait_steps()  # nothing left here: wait for news from the others
            self._step(robot)
        return None

    def context(self, index: int) -> DecisionContext:
        """What robot ``index``'s policy sees at its decision."""
        return decision_context(self.robots[index].sim)

    def claims(self, index: int) -> NDArray[np.float64]:
        """(k, 2) goals (m) of the working teammates robot ``index`` is in contact with."""
        goals = [
            r.sim.target
            for r in self.robots
            if r.index != index and r.alive and r.sim.target is not None and self._contact[index, r.index]
        ]
        return np.asarray(goals, dtype=np.float64).reshape(-1, 2)

    def assign(self, index: int, ranking: Ranking) -> None:
        """Start robot ``index``'s leg for ``ranking`` (coordinated by the team's strategy) and take
        its first step, so that its goal is known to the others before they decide."""
        robot = self.robots[index]
        sim = robot.sim
        before = sim.sim_time
        if ranking.goal is not None:
            robot.leg = sim.go_to_steps(*ranking.goal, ranking.weight)
        else:
            order = ranking.order
            if self.team.strategy is not Strategy.UNCOORDINATED:
                order = coordinated_order(
                    sim.frontiers().goals,
                    order,
                    self.claims(index),
                    self.team.claim_radius,
                    self.team.coordination_range,
                )
            robot.leg = sim.execute_steps(order, ranking.weight)
        self._step(robot)
        if self.rendezvous is not None:
            self.rendezvous.decided(robot)
        robot.stalled = robot.stalled + 1 if sim.sim_time == before and robot.leg is None else 0
        if robot.stalled > _MAX_STALLED_DECISIONS:
            raise RuntimeError(
                f"team episode on {self.world.name!r} stalled: robot {index} took {robot.stalled} decisions in a "
                f"row without simulated time at t = {sim.sim_time:.1f} s"
            )

    # ------------------------------------------------------------- the clock
    def _step(self, robot: TeamRobot) -> None:
        """Advance ``robot``'s leg by one step, then share its new scan."""
        if robot.leg is None:
            return
        sim = robot.sim
        others = [r for r in self.robots if r is not robot]
        sim.set_teammates(np.asarray([r.xy for r in others]).reshape(-1, 2), np.array([r.alive for r in others]))
        last = sim.mapper.last_update
        try:
            next(robot.leg)
        except StopIteration:
            robot.leg = None
        if sim.mapper.last_update is not last:
            self._share(robot, full=False)

    def _share(self, robot: TeamRobot, full: bool) -> None:
        """Merge ``robot``'s new scan (or whole map) with the teammates in range, and add it to what
        the team knows (:meth:`~frontier_rl.core.mapping.mapper.LogOddsMapper.merge_both_ways`).
        The scan's window is the square its range reaches, which also passes on what the robot had
        from teammates there; with an unlimited range every teammate had that directly, and the
        window is only the cells the robot's own scans (and bumps) changed since it last shared:
        the same merge, at about half the cells."""
        mapper = robot.sim.mapper
        changed = mapper.take_changed()
        if math.isinf(self._range):
            window = changed or (0, 0, 0, 0)
        else:
            row, col = self.world.grid.world_to_cell(*robot.xy)
            reach = self._reach
            window = (row - reach, row + reach + 1, col - reach, col + reach + 1)
        near = []
        for other in self.robots:
            if other is robot or not other.alive:
                continue
            i, j = robot.index, other.index
            in_range = math.dist(robot.xy, other.xy) <= self._range
            if in_range:
                near.append((other, window if (self._contact[i, j] and not full) else None))
            self._contact[i, j] = self._contact[j, i] = in_range
        mapper.merge_both_ways([other.sim.mapper for other, _ in near], [part for _, part in near])
        for other, _ in near:
            other.sim.refresh()
        robot.sim.refresh()
        if full:  # whole maps were merged
            window = (0, mapper.state.shape[0], 0, mapper.state.shape[1])
        r0, c0 = max(window[0], 0), max(window[2], 0)
        self._knowledge.add(mapper.seen, slice(r0, window[1]), slice(c0, window[3]), robot.sim.sim_time)
        self._knowledge_updated(robot.sim.sim_time)

    def _recount(self) -> None:
        """Rebuild what the team knows from the surviving robots' maps."""
        self._knowledge.rebuild([robot.sim.mapper.seen for robot in self.alive], self.sim_time)
        self._knowledge_updated(self.sim_time)

    def _knowledge_updated(self, time_s: float) -> None:
        """What the team knows was updated at ``time_s`` (s): a hook for recorders of other figures."""

    # -------------------------------------------------------------- failures
    def _draw_failures(self, rng: np.random.Generator) -> None:
        named = {f.robot for f in self.team.failures if f.robot is not None}
        for failure in self.team.failures:
            index = failure.robot
            if index is None:
                free = [r.index for r in self.robots if r.index not in named]
                index = int(rng.choice(free))
                named.add(index)
            at = failure.time_s
            self.robots[index].fail_at = float(rng.uniform(0, self.team.random_failure_horizon)) if at is None else at

    def fail(self, robot: TeamRobot) -> None:
        """``robot`` stops for good where it is (still an obstacle); what it had not shared is lost."""
        robot.drop_leg()
        robot.failed_at = robot.sim.sim_time
        self._contact[robot.index, :] = self._contact[:, robot.index] = False
        self._recount()

    # ---------------------------------------------------------------- results
    def coverage_curve(self) -> tuple[list[float], list[int]]:
        """When (s) the count of explorable cells the team knows changed, and the count then."""
        return self._knowledge.times, self._knowledge.curve

    def team_map(self) -> OccupancyGrid:
        """The surviving robots' maps merged (robot 0's if none survived)."""
        alive = self.alive or self.robots[:1]
        merged = LogOddsMapper(self.world.grid, self.config.mapper, self.world.explorable)
        for robot in alive:
            merged.merge_from(robot.sim.mapper)
        return merged.occupancy_grid()

    def result(self, wall_time_s: float | None = None) -> TeamResult:
        """The team's metrics so far (:func:`~frontier_rl.swarm.team_result.team_result`);
        ``wall_time_s`` defaults to the time since construction."""
        return team_result(self, time.perf_counter() - self._started if wall_time_s is None else wall_time_s)
