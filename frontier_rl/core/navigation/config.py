"""Navigation settings: the costmap, planner and controller (TurtleBot3 / move_base / explore_lite
flavoured)."""

from __future__ import annotations

import math
from collections.abc import Callable
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
        recovery_detour_factor: the detour limit's factor for a leg planned on the narrow-passage
            recovery's costmap, whose walls are peeled: a gap it plans through may not be there,
            and replanning from one peeled gap to the next toured SLAM maps' fans of rays for
            100-540 s per leg (``yujin_rnd_hokuyo``) to the episode's time cap...
        recovery_detour_slack: ... and its slack (m).
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
    recovery_detour_factor: float = 2.0
    recovery_detour_slack: float = 5.0
    blacklist_radius: float = 0.25
    max_goal_failures: int = 2
    frontier_check_period: float = 1.0
    teammate_margin: float = 0.1
    teammate_range: float = 1.5
    teammate_patience: float = 5.0

    def __post_init__(self) -> None:
        positive = (
            "inflation_radius",
            "goal_tolerance",
            "lookahead",
            "heading_gain",
            "control_dt",
            "progress_timeout",
            "frontier_check_period",
            "teammate_patience",
            "teammate_range",
        )
        self._require(positive, lambda v: math.isfinite(v) and v > 0, "be positive")
        non_negative = (
            "cost_scaling",
            "progress_distance",
            "oscillation_distance",
            "blacklist_radius",
            "teammate_margin",
            "detour_slack",
            "recovery_detour_slack",
        )
        self._require(non_negative, lambda v: math.isfinite(v) and v >= 0, "be >= 0")
        self._require(
            ("inflation_radius",), lambda v: v <= MAX_INFLATION_RADIUS_M, f"be at most {MAX_INFLATION_RADIUS_M:g} m"
        )
        extra = f"be within [0, {MAX_EXTRA_COST:g}]"
        self._require(("inflation_cost", "unknown_cost"), lambda v: 0 <= v <= MAX_EXTRA_COST, extra)
        self._require(("control_dt",), lambda v: v >= MIN_CONTROL_DT, f"be >= {MIN_CONTROL_DT:g} s")
        self._require(("max_goal_failures",), lambda v: v >= 1, "be >= 1")
        self._require(("detour_factor", "recovery_detour_factor"), lambda v: math.isfinite(v) and v >= 1, "be >= 1")
        self._require(("max_recoveries",), lambda v: v >= 0, "be >= 0")

    def _require(self, names: tuple[str, ...], holds: Callable[[float], bool], what: str) -> None:
        """Raise :class:`ConfigError` naming the first of ``names`` whose value ``holds`` refuses:
        it must ``what``."""
        for name in names:
            value = getattr(self, name)
            if not holds(value):
                raise ConfigError(f"NavigationConfig.{name} must {what}, got {value!r}")

    def detour_limit(self, first_plan: float, on_recovery: bool) -> float:
        """How far (m) a leg whose first plan was ``first_plan`` m long may drive before it is
        aborted as a detour: ``recovery_detour_*`` on the narrow-passage recovery's costmap
        (``on_recovery``), else ``detour_*``."""
        if on_recovery:
            return self.recovery_detour_factor * first_plan + self.recovery_detour_slack
        return self.detour_factor * first_plan + self.detour_slack
