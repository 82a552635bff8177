"""The team episode loop, and the thesis's frontier request for one robot of a team."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from frontier_rl.core.frontiers.thesis import THESIS_WEIGHT
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import EpisodeAwarePolicy, ExplorationPolicy, drive_episode
from frontier_rl.core.world.worlds import World
from frontier_rl.errors import ConfigError
from frontier_rl.policies.baselines import FixedWeight
from frontier_rl.robot.ranking import RankedFrontier
from frontier_rl.swarm.config import TeamConfig
from frontier_rl.swarm.result import TeamResult
from frontier_rl.swarm.team import TeamSimulator


def run_team_episode(
    world: World,
    policy: ExplorationPolicy,
    config: SimConfig | None = None,
    team: TeamConfig | None = None,
    seed: int | np.random.Generator = 0,
) -> TeamResult:
    """Explore ``world`` with a team whose every robot ranks with ``policy``, until no surviving
    robot has a frontier left, the sim-time cap, or no robot is left.

    ``seed`` is used as :func:`~frontier_rl.core.sim.episode.run_episode` uses it (robot 0 gets the
    same noise and policy streams; the others' are spawned from them), so a one-robot team
    explores exactly as the single robot does.
    """
    team = team or TeamConfig()
    check_team_policy(policy, team.robots)
    loop, wall_time = drive_episode(
        lambda rng: TeamSimulator(world, config, team, rng), world, policy, seed, team.robots
    )
    return loop.result(wall_time)


def check_team_policy(policy: ExplorationPolicy, robots: int) -> None:
    """Refuse a policy that plans one robot's tour of the true map (the oracle) for a team.

    Raises:
        ConfigError: naming the policy.
    """
    if isinstance(policy, EpisodeAwarePolicy) and robots > 1:
        raise ConfigError(f"policy {policy.name!r} plans one robot's tour of the true map; it cannot run in a team")


@dataclass(frozen=True)
class FrontierList:
    """The answer to a frontier request: a robot's best frontiers in its own map frame.

    Attributes:
        robot: the robot asked about.
        frame: the frame the centres are in, ``robot_<i>/map``: origin at the robot's start pose,
            x along its start heading (the frame its own SLAM map would have).
        frontiers: best first.
        weight: the ranking weight the policy used, if it has one.
    """

    robot: int
    frame: str
    frontiers: tuple[RankedFrontier, ...]
    weight: float | None


def frontier_request(
    team: TeamSimulator,
    robot: int,
    policy: ExplorationPolicy | None = None,
    top_k: int = 10,
    rng: np.random.Generator | None = None,
) -> FrontierList:
    """The thesis's ``/frontier_request``: the ``top_k`` frontiers of robot ``robot``'s current
    (merged) map, ranked by ``policy`` (default: the thesis's fixed w = 0.75), in that robot's map
    frame."""
    if not 0 <= robot < len(team.robots):
        raise ConfigError(f"no robot {robot!r}: the team has robots 0..{len(team.robots) - 1}")
    if top_k < 1:
        raise ConfigError(f"top_k must be >= 1, got {top_k!r}")
    member = team.robots[robot]
    if not member.alive:
        raise ConfigError(f"robot {robot} failed at t = {member.failed_at:.1f} s and cannot answer")
    context = team.context(robot)
    frame = f"robot_{robot}/map"
    if len(context.frontiers) == 0:
        return FrontierList(robot, frame, (), None)
    ranking = (policy or FixedWeight(THESIS_WEIGHT)).rank(context, rng or np.random.default_rng(0))
    start = member.sim.world.start
    cos_t, sin_t = math.cos(start.theta), math.sin(start.theta)
    answer = []
    for index in ranking.order[:top_k]:
        x, y = context.frontiers.centers[int(index)]
        dx, dy = x - start.x, y - start.y
        answer.append(
            RankedFrontier(cos_t * dx + sin_t * dy, -sin_t * dx + cos_t * dy, int(context.frontiers.sizes[int(index)]))
        )
    return FrontierList(robot, frame, tuple(answer), ranking.weight)
