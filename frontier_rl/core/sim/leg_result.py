"""What a leg ends with: how it ended, why a goal was given up, and the drive's record."""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum


class LegOutcome(StrEnum):
    """How a drive toward a goal ended."""

    REACHED = "reached"
    EXPLORED = "explored"  # the goal's frontier was seen before the robot got there
    ABORTED = "aborted"  # no progress, no path, stuck, or a detour far longer than planned: the goal is blacklisted
    GAVE_WAY = "gave_way"  # a teammate blocked the way, with no way round it: another goal is chosen
    TIMEOUT = "timeout"  # the episode's sim-time cap
    NONE = "none"  # no candidate could be planned to


class AbortCause(StrEnum):
    """Why a goal was given up (a leg ABORTED, or no path to it at the decision)."""

    NOT_PLANNED = "not_planned"  # no path to the goal on the costmap at the decision
    NO_PROGRESS = "no_progress"  # the way left did not get shorter for progress_timeout
    DETOUR = "detour"  # the robot drove farther than detour_factor times its first plan
    NO_PATH = "no_path"  # a wall turned up on the path, and no new path after the recovery rotations


@dataclass(frozen=True)
class LegResult:
    """One decision's drive.

    Attributes:
        outcome: how it ended.
        frontier: index of the frontier driven to (in the candidates), -1 for a point goal or none.
        goal: the goal (m).
        duration_s: sim time the leg took (s).
        distance_m: distance driven (m).
        new_free, new_occupied: cells first mapped free / occupied during the leg.
        start_s: sim time of the decision (s).
        start_xy: where the robot was at the decision (m).
    """

    outcome: LegOutcome
    frontier: int
    goal: tuple[float, float]
    duration_s: float
    distance_m: float
    new_free: int
    new_occupied: int
    start_s: float
    start_xy: tuple[float, float]
