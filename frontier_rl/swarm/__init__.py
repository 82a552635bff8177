"""Multi-robot exploration: teams, map merging, coordination, rendezvous and failures.

The names below load their module on first use: ``frontier_rl.swarm.config`` (how a team is written)
loads no engine."""

from __future__ import annotations

from typing import TYPE_CHECKING

from frontier_rl.lazy_exports import lazy_exports

_NAMES = {
    **dict.fromkeys(("Failure", "Strategy", "TeamConfig", "TeamMethod", "parse_strategy"), "frontier_rl.swarm.config"),
    **dict.fromkeys(("FrontierList", "frontier_request", "run_team_episode"), "frontier_rl.swarm.episode"),
    **dict.fromkeys(("TeamResult", "TeamSummary"), "frontier_rl.swarm.result"),
    **dict.fromkeys(("TeamRobot", "TeamSimulator"), "frontier_rl.swarm.team"),
}
"""Each public name and the module that defines it."""

__all__ = [
    "Failure",
    "FrontierList",
    "Strategy",
    "TeamConfig",
    "TeamMethod",
    "TeamResult",
    "TeamRobot",
    "TeamSimulator",
    "TeamSummary",
    "frontier_request",
    "parse_strategy",
    "run_team_episode",
]
__getattr__, __dir__ = lazy_exports(__name__, _NAMES)

if TYPE_CHECKING:
    from frontier_rl.swarm.config import Failure, Strategy, TeamConfig, TeamMethod, parse_strategy
    from frontier_rl.swarm.episode import FrontierList, frontier_request, run_team_episode
    from frontier_rl.swarm.result import TeamResult, TeamSummary
    from frontier_rl.swarm.team import TeamRobot, TeamSimulator
