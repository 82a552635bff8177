"""A team episode's result: the team's metrics, the frontiers its surviving robots left, and why it ended."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from frontier_rl.core.sim.episode_log import aborts_by_cause, completion_reason
from frontier_rl.core.sim.metrics import EndReason, FrontierLeft, time_to_coverage, unseen_area_m2
from frontier_rl.core.world.grid import CellState
from frontier_rl.swarm.result import TeamResult, overlap_share

if TYPE_CHECKING:
    from frontier_rl.swarm.team import TeamSimulator


def team_result(team: TeamSimulator, wall_time_s: float) -> TeamResult:
    """``team``'s metrics so far, its episode loop having taken ``wall_time_s`` (s)."""
    world = team.world
    total = max(world.explorable_count, 1)
    changed_at, counts = team.coverage_curve()
    times = np.asarray(changed_at, dtype=np.float64)
    curve = np.asarray(counts, dtype=np.float64) / total
    sims = [r.sim for r in team.robots]
    explorable = world.explorable
    first = sims[0].result(wall_time_s)
    left = frontiers_left(team)
    reason = end_reason(team, left)
    return TeamResult(
        sim_time_s=team.sim_time,
        path_length_m=sum(s.path_length for s in sims),
        coverage=team.coverage,
        t90_s=time_to_coverage(times, curve, 0.90),
        t99_s=time_to_coverage(times, curve, 0.99),
        decisions=sum(len(s.log.decisions) for s in sims),
        aborts=sum(s.log.aborts for s in sims),
        aborts_by_cause=aborts_by_cause([s.log.aborts_by_cause for s in sims]),
        done=team.done and reason is EndReason.EXPLORED,
        truncated=team.truncated,
        wall_time_s=wall_time_s,
        end_reason=reason,
        free_coverage=free_coverage(team),
        unknown_left_m2=unseen_area_m2(left, world.grid.resolution),
        explorable_m2=world.explorable_count * world.grid.resolution**2,
        coverage_times_s=times,
        coverage_curve=curve,
        trajectory=first.trajectory,
        decision_log=tuple(sorted((d for s in sims for d in s.log.decisions), key=lambda d: d.time_s)),
        final_map=first.final_map,
        robots=len(team.robots),
        strategy=team.team.strategy,
        overlap=overlap_share([s.mapper.observed for s in sims], explorable),
        robot_path_lengths_m=tuple(s.path_length for s in sims),
        robot_coverage=tuple(int(np.count_nonzero(s.mapper.observed & explorable)) / total for s in sims),
        failed_at_s=tuple(r.failed_at for r in team.robots),
        trajectories=tuple(s.trajectory() for s in sims),
        team_map=team.team_map(),
        frontiers_left=left,
    )


def frontiers_left(team: TeamSimulator) -> tuple[FrontierLeft, ...]:
    """The frontiers ``team``'s surviving robots left at the end or the time cap (none before),
    each once (robots that shared their maps see the same frontier), with the space unseen by the
    whole team beside and behind it: a robot's frontier whose cells a teammate mapped after their
    last share is no space left."""
    if not (team.done or team.truncated):
        return ()
    left: dict[tuple[float, float, int], FrontierLeft] = {}
    for robot in team.alive:
        for frontier in robot.sim.frontiers_left(team.known):
            if frontier.unknown_cells:  # else a teammate saw all round it
                left.setdefault((frontier.x, frontier.y, frontier.cells), frontier)
    return tuple(left.values())


def end_reason(team: TeamSimulator, left: tuple[FrontierLeft, ...]) -> EndReason | None:
    """Why ``team``'s episode ended (None while it goes on): ``FAILED`` when no robot is left."""
    if team.truncated:
        return EndReason.TIME_CAP
    if not team.over:
        return None
    if not team.alive:
        return EndReason.FAILED
    return completion_reason(left)


def free_coverage(team: TeamSimulator) -> float:
    """Share of the world's free cells ``team``'s surviving robots know."""
    free = team.world.grid.data == CellState.FREE
    return int(np.count_nonzero(team.known & free)) / max(int(np.count_nonzero(free)), 1)
