"""Navigation settings: the costmap, planner and controller (TurtleBot3 / move_base / explore_lite
flavoured)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from frontier_rl.errors import ConfigError

MAX_EXTRA_COST = 100.0
"""Largest ``inflation_cost`` and ``unknown_cost`` (extra step cost factors): the planners' bucket
queues hold one bucket per unit of the largest step cost, so a factor of 1e12 would ask for
terabytes. 100 already makes a cell cost 101 free steps."""

MAX_INFLATION_RADIUS_M = 10.0
"""Largest ``inflation_radius`` (m): the costmap's inflation table spans it, so 1e7 m asked for
more memory than any machine has (nav2's default is 0.55 m)."""

MIN_CONTROL_DT = 1e-3
"""Shortest ``control_dt`` (s): a 1 kHz control loop, far above move_base's 20 Hz; a step of 1e-9 s
would take an episode years of wall time."""


MAX_STOPS = 16
"""The most stops a tour may have (``tour:N``): Held-Karp's table has 2ⁿ·n entries."""


@dataclass(frozen=True)
class NavigationConfig:
    """Costmap, planner and controller settings (TurtleBot3 / move_base / explore_lite flavoured).

    Attributes:
        inflation_radius: distance from obstacles (m) over which the extra cost decays.
        cost_scaling: exponential decay rate of the inflation cost (1/m).
        inflation_cost: extra cost factor of a cell at the robot radius from an obstacle.
        unknown_cost: extra cost factor of an unknown cell (unknown is passable).
        goal_tolerance: distance to the goal (m) at which it counts as reached.
        lookahead: distance (m) of the path point the controller steers toward.
        heading_gain: angular speed per rad of heading error (1/s) while driving.
        control_dt: integration step of the robot motion (s).
        progress_timeout: a goal without progress for this long (s) is aborted and blacklisted.
        progress_distance: the remaining path must shrink by this much (m) to count as progress...
        oscillation_distance: ... or the robot must move this far (m) (move_base's setting).
        max_recoveries: in-place rotations tried when stuck before the goal is aborted.
        detour_factor: a leg that has driven more than this many times its first plan's length...
        detour_slack: ... and this much more (m) is aborted and its goal blacklisted. A safety net:
            replanning through unknown space that keeps turning out walled can tour a building on
            a leg to a goal 2 m away (81 m in one such leg, on 0.1 m cells). The bound is loose on
            purpose, since a way around found on the road is exploration too: legs of 33-38 m
            whose first plan was 4-6 m, on building floors, ended with their frontier seen.
        blacklist_radius: frontiers whose goal lies this close (m) to a failed goal are skipped
            (until the map around it changes, or it is retried before the episode would end).
        max_goal_failures: a goal that failed this often is given up for good.
        frontier_check_period: how often (s) the goal's frontier is checked for being explored.
        teammate_margin: in a team, paths keep this much room (m) from other robots when they can.
        teammate_range: ... from the robots within this distance (m); farther ones will have moved
            by the time the robot gets there.
        teammate_patience: in a team, a robot blocked by another one waits this long (s) for it
            to move on; then it has reached its goal if it or that teammate stands by it, drives
            round the teammate where there is room, or else gives way: its leg ends, and it
            chooses again with that teammate as an obstacle.
    """

    inflation_radius: float = 0.55
    cost_scaling: float = 5.0
    inflation_cost: float = 3.0
    unknown_cost: float = 1.0
    goal_tolerance: float = 0.15
    lookahead: float = 0.3
    heading_gain: float = 3.0
    control_dt: float = 0.05
    progress_timeout: float = 30.0
    progress_distance: float = 0.1
    oscillation_distance: float = 0.5
    max_recoveries: int = 2
    detour_factor: float = 10.0
    detour_slack: float = 30.0
    blacklist_radius: float = 0.25
    max_goal_failures: int = 2
    frontier_check_period: float = 1.0
    teammate_margin: float = 0.1
    teammate_range: float = 1.5
    teammate_patience: float = 5.0

    def __post_init__(self) -> None:
        for name in (
            "inflation_radius",
            "goal_tolerance",
            "lookahead",
            "heading_gain",
            "control_dt",
            "progress_timeout",
            "frontier_check_period",
            "teammate_patience",
            "teammate_range",
        ):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ConfigError(f"NavigationConfig.{name} must be positive, got {value!r}")
        for name in (
            "cost_scaling",
            "progress_distance",
            "oscillation_distance",
            "blacklist_radius",
            "teammate_margin",
            "detour_slack",
        ):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise ConfigError(f"NavigationConfig.{name} must be >= 0, got {value!r}")
        if self.inflation_radius > MAX_INFLATION_RADIUS_M:
            raise ConfigError(
                f"NavigationConfig.inflation_radius must be at most {MAX_INFLATION_RADIUS_M:g} m, "
                f"got {self.inflation_radius!r}"
            )
        for name in ("inflation_cost", "unknown_cost"):
            value = getattr(self, name)
            if not (0 <= value <= MAX_EXTRA_COST):
                raise ConfigError(f"NavigationConfig.{name} must be within [0, {MAX_EXTRA_COST:g}], got {value!r}")
        if self.control_dt < MIN_CONTROL_DT:
            raise ConfigError(f"NavigationConfig.control_dt must be >= {MIN_CONTROL_DT:g} s, got {self.control_dt!r}")
        if self.max_goal_failures < 1:
            raise ConfigError(f"NavigationConfig.max_goal_failures must be >= 1, got {self.max_goal_failures!r}")
        if not (math.isfinite(self.detour_factor) and self.detour_factor >= 1):
            raise ConfigError(f"NavigationConfig.detour_factor must be >= 1, got {self.detour_factor!r}")
        if self.max_recoveries < 0:
            raise ConfigError(f"NavigationConfig.max_recoveries must be >= 0, got {self.max_recoveries!r}")
