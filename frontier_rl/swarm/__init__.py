"""Multi-robot exploration: teams, map merging, coordination, rendezvous and failures."""

from frontier_rl.swarm.config import Failure, Strategy, TeamConfig, TeamMethod, parse_strategy
from frontier_rl.swarm.episode import FrontierList, frontier_request, run_team_episode
from frontier_rl.swarm.result import TeamResult
from frontier_rl.swarm.team import TeamRobot, TeamSimulator

__all__ = [
    "Failure",
    "FrontierList",
    "Strategy",
    "TeamConfig",
    "TeamMethod",
    "TeamResult",
    "TeamRobot",
    "TeamSimulator",
    "frontier_request",
    "parse_strategy",
    "run_team_episode",
]
