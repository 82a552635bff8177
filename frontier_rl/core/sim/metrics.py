"""Per-episode metrics: time, distance, coverage curve, decisions."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from enum import StrEnum
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from frontier_rl.core.sim.leg_result import AbortCause, LegOutcome
from frontier_rl.core.world.grid import OccupancyGrid


class EndReason(StrEnum):
    """Why an episode ended; its value is the name results files and reports write."""

    EXPLORED = "explored"  # no frontier left with free space behind it
    UNREACHABLE = "unreachable"  # frontiers left with free space behind: every attempt failed, or no reachable view
    TIME_CAP = "time_cap"  # the sim-time cap
    FAILED = "failed"  # a team's: no robot left

    @property
    def label(self) -> str:
        """The reason in words, as the reports write it ("time cap")."""
        return self.value.replace("_", " ")


@dataclass(frozen=True)
class DecisionRecord:
    """One decision: when, where the robot was, the goal it chose and the weight (if any).

    Attributes:
        time_s: sim time of the decision (s).
        x, y: robot position (m).
        goal_x, goal_y: chosen goal (m); NaN when no goal could be planned.
        weight: the ranking weight in use, None for policies without one.
        outcome: how the leg ended.
    """

    time_s: float
    x: float
    y: float
    goal_x: float
    goal_y: float
    weight: float | None
    outcome: LegOutcome


@dataclass(frozen=True)
class FrontierLeft:
    """A frontier the episode ended without exploring.

    Attributes:
        x, y: its centre (m).
        cells: its fringe cells.
        unknown_cells: the unknown cells next to its cells (8-neighbours; in a team, unknown to
            every surviving robot).
        unseen_free_cells: those of them that are free in the true world: space left unseen (the
            others are walls no beam reached, or noise).
        unknown_m2: the area of the unseen free cells (m²).
        failures: how often a leg to a goal of it failed (0: no reachable cell sees it, e.g. it lies
            behind a gap narrower than the robot).
        unseen_behind_m2: the unseen free region its unseen free cells open onto (m²): the cells
            unknown in the map and free in the true world, 4-connected to them.
        unseen_cells: the unseen free cells' flat indices in the world's grid (row-major), so that
            a cell beside two frontiers is counted once in an episode's ``unknown_left_m2``.
        has_path: the audit: the robot's final map, planned afresh from where it stands (a new
            costmap, no blacklist, normal or narrow-passage recovery), has a path to it: it was
            given up on after its failed attempts, not for want of a way (unless ``unrevealable``).
        path_on_map: the audit found that path on the normal costmap, through the walls as the robot
            mapped them; with ``has_path`` but not this, only through walls the narrow-passage
            recovery thinned, which may not be there (a streak in a wall's mass, a gap in clutter).
        unrevealable: the robot reached a goal of it as often as a goal may fail, and it stayed: the
            view it was chosen for revealed nothing (:mod:`~frontier_rl.core.frontiers.blacklist`);
            or, with ``has_path``, no cell the audit found it can reach would see more than a speck
            of the unknown it opens onto (its expected gain: a look from anywhere would reveal
            nothing that leaves space; :func:`~frontier_rl.core.sim.look_views.look_promise_cells`).
        leaves_space: it leaves space to explore, the end reason's test: more unseen free cells
            beside it than a speck has (``SimConfig.speck_cells``), or more than ``UNSEEN_ROOM_M2``
            behind it; one whose unknown side is wall (cells no beam reached) leaves none.
        explorable_behind: of the unseen free regions behind it, the part a robot of this size can
            see from where it can go on the true map (its explorable space), in m², by region
            (keys: the regions' labels in the episode's end, so that a region behind two frontiers
            is counted once; :func:`explorable_given_up_m2`).
    """

    x: float
    y: float
    cells: int
    unknown_cells: int
    unseen_free_cells: int
    unknown_m2: float
    failures: int
    unseen_behind_m2: float
    unseen_cells: NDArray[np.int64] = field(repr=False, compare=False, default_factory=lambda: np.zeros(0, np.int64))
    has_path: bool = False
    path_on_map: bool = False
    unrevealable: bool = False
    leaves_space: bool = False
    explorable_behind: Mapping[int, float] = field(repr=False, compare=False, default_factory=dict)

    def summary(self) -> dict[str, Any]:
        """A JSON-ready dict."""
        return {
            "x": round(self.x, 3),
            "y": round(self.y, 3),
            "cells": self.cells,
            "unknown_cells": self.unknown_cells,
            "unseen_free_cells": self.unseen_free_cells,
            "unknown_m2": round(self.unknown_m2, 4),
            "failures": self.failures,
            "unseen_behind_m2": round(self.unseen_behind_m2, 4),
            "has_path": self.has_path,
            "path_on_map": self.path_on_map,
            "unrevealable": self.unrevealable,
            "leaves_space": self.leaves_space,
            "explorable_behind_m2": round(sum(self.explorable_behind.values()), 4),
        }


def explorable_given_up_m2(left: Sequence[FrontierLeft]) -> float:
    """The audit on the true map: the explorable area (m²) behind the frontiers ``left`` that the
    robot's final map had a path to (:attr:`FrontierLeft.has_path`, not unrevealable): space the
    robot could have seen on the true map and gave up on after its tries; each region once."""
    regions: dict[int, float] = {}
    for frontier in left:
        if frontier.has_path and not frontier.unrevealable:
            regions.update(frontier.explorable_behind)
    return float(sum(regions.values()))


def unseen_area_m2(left: Sequence[FrontierLeft], resolution: float) -> float:
    """The unseen free area (m²) beside the frontiers ``left`` (of maps on one world grid with
    ``resolution`` m cells), each cell once: segments of one frontier, or one frontier in two
    robots' maps, border the same cells."""
    if not left:
        return 0.0
    cells = np.unique(np.concatenate([f.unseen_cells for f in left]))
    return float(cells.size * resolution * resolution)


@dataclass(frozen=True)
class EpisodeResult:
    """What one exploration episode did.

    Attributes:
        sim_time_s: simulated time until exploration ended or was cut off (s).
        path_length_m: distance driven (m).
        coverage: final fraction of the explorable free space that is mapped.
        t90_s, t99_s: sim time at which coverage first reached 90 % / 99 % (s); None if never.
        decisions: number of decisions taken.
        aborts: goals given up (no progress, unreachable) and blacklisted.
        explorable_m2: the world's explorable area (m²): what a robot of this size can see from the
            poses it can reach on the true map, the denominator of ``coverage``.
        aborts_by_cause: ``aborts`` by why each goal was given up (the values of
            :class:`~frontier_rl.core.sim.leg_result.AbortCause`: ``not_planned``, ``no_progress``,
            ``detour``, ``no_path``); a team's summed over its robots.
        done: the map is explored: no frontier is left that the robot could see from where it can go
            (``end_reason is EndReason.EXPLORED``).
        truncated: the sim-time cap ended the episode.
        wall_time_s: wall-clock time of the episode loop (s), without set-up and compilation.
        end_reason: ``EXPLORED``, ``UNREACHABLE`` (frontiers are left, each failed its attempts or
            has no reachable cell that sees it: see ``frontiers_left``), ``TIME_CAP`` or a team's
            ``FAILED``; None while the episode goes on.
        free_coverage: share of all the world's free cells (connected to the start) that are
            mapped, explorable or not.
        unknown_left_m2: the unseen free area (m²) beside the frontiers left: free in the true
            world, unknown in the map; a cell beside several of them counted once
            (:func:`unseen_area_m2`).
        coverage_times_s, coverage_curve: coverage after every map update, and when (s).
        coverage_path_m: the distance driven (m) by each map update of ``coverage_curve`` (a
            single robot's episode; None for a team).
        trajectory: (n, 3) robot pose (x, y, theta) at every LiDAR tick.
        decision_log: every decision, in order.
        final_map: the robot's map at the end.
        frontiers_left: the frontiers left at the end (none when explored).
    """

    sim_time_s: float
    path_length_m: float
    coverage: float
    t90_s: float | None
    t99_s: float | None
    decisions: int
    aborts: int
    done: bool
    truncated: bool
    wall_time_s: float
    end_reason: EndReason | None
    free_coverage: float
    unknown_left_m2: float
    coverage_times_s: NDArray[np.float64] = field(repr=False)
    coverage_curve: NDArray[np.float64] = field(repr=False)
    trajectory: NDArray[np.float64] = field(repr=False)
    decision_log: tuple[DecisionRecord, ...] = field(repr=False, default=())
    final_map: OccupancyGrid | None = field(repr=False, default=None)
    frontiers_left: tuple[FrontierLeft, ...] = field(repr=False, default=())
    coverage_path_m: NDArray[np.float64] | None = field(repr=False, default=None)
    aborts_by_cause: Mapping[AbortCause, int] = field(default_factory=dict)
    explorable_m2: float = 0.0

    @property
    def explorable_left_m2(self) -> float:
        """The explorable area (m²) the episode left unmapped: what the robot gave up (or had no time
        for) of the space it could have seen on the true map."""
        return (1.0 - self.coverage) * self.explorable_m2

    @property
    def frontiers_with_path_left(self) -> int:
        """The audit's count: frontiers left to which the robot's final map has a path
        (:attr:`FrontierLeft.has_path`), given up on after their failed attempts; not the
        unrevealable ones (:attr:`frontiers_unrevealable_left`)."""
        return sum(f.has_path and not f.unrevealable for f in self.frontiers_left)

    @property
    def frontiers_with_path_to_space_left(self) -> int:
        """Of :attr:`frontiers_with_path_left`, those that leave space to explore
        (:attr:`FrontierLeft.leaves_space`): space given up though the map had a way to it. The
        others' unknown side is wall on the true map, which the robot cannot know."""
        return sum(f.has_path and f.leaves_space and not f.unrevealable for f in self.frontiers_left)

    @property
    def explorable_given_up_m2(self) -> float:
        """The explorable area (m²) behind the frontiers left with a path: given up after their
        tries, though the robot could have seen it on the true map (:func:`explorable_given_up_m2`)."""
        return explorable_given_up_m2(self.frontiers_left)

    @property
    def frontiers_with_path_on_map_left(self) -> int:
        """Of :attr:`frontiers_with_path_left`, those with a path on the normal costmap, through the
        walls as mapped (:attr:`FrontierLeft.path_on_map`); the others have one only through walls
        the narrow-passage recovery thinned."""
        return sum(f.path_on_map and not f.unrevealable for f in self.frontiers_left)

    @property
    def frontiers_unrevealable_left(self) -> int:
        """Frontiers left that the robot reached as often as a goal may fail and that stayed
        (:attr:`FrontierLeft.unrevealable`)."""
        return sum(f.unrevealable for f in self.frontiers_left)

    @property
    def real_time_factor(self) -> float:
        """Simulated seconds per wall-clock second."""
        return self.sim_time_s / self.wall_time_s if self.wall_time_s > 0 else float("inf")

    def summary(self) -> EpisodeSummary:
        """The scalar metrics, rounded as the result files and ``explore --json`` keep them."""
        return EpisodeSummary(
            sim_time_s=round(self.sim_time_s, 3),
            path_length_m=round(self.path_length_m, 3),
            coverage=round(self.coverage, 5),
            t90_s=None if self.t90_s is None else round(self.t90_s, 3),
            t99_s=None if self.t99_s is None else round(self.t99_s, 3),
            decisions=self.decisions,
            aborts=self.aborts,
            aborts_by_cause=dict(self.aborts_by_cause),
            done=self.done,
            truncated=self.truncated,
            end_reason=self.end_reason,
            free_coverage=round(self.free_coverage, 5),
            unknown_left_m2=round(self.unknown_left_m2, 4),
            explorable_left_m2=round(self.explorable_left_m2, 4),
            frontiers_with_path_left=self.frontiers_with_path_left,
            frontiers_with_path_to_space_left=self.frontiers_with_path_to_space_left,
            explorable_given_up_m2=round(self.explorable_given_up_m2, 4),
            frontiers_with_path_on_map_left=self.frontiers_with_path_on_map_left,
            frontiers_unrevealable_left=self.frontiers_unrevealable_left,
            wall_time_s=round(self.wall_time_s, 4),
            real_time_factor=round(self.real_time_factor, 1),
        )


@dataclass(frozen=True)
class EpisodeSummary:
    """An episode's scalar metrics (:meth:`EpisodeResult.summary`), rounded: times to the
    millisecond, shares to 10⁻⁵, areas to 10⁻⁴ m². Each field is the :class:`EpisodeResult`
    attribute or property of the same name."""

    sim_time_s: float
    path_length_m: float
    coverage: float
    t90_s: float | None
    t99_s: float | None
    decisions: int
    aborts: int
    aborts_by_cause: dict[AbortCause, int]
    done: bool
    truncated: bool
    end_reason: EndReason | None
    free_coverage: float
    unknown_left_m2: float
    explorable_left_m2: float
    frontiers_with_path_left: int
    frontiers_with_path_to_space_left: int
    explorable_given_up_m2: float
    frontiers_with_path_on_map_left: int
    frontiers_unrevealable_left: int
    wall_time_s: float
    real_time_factor: float

    def to_json(self) -> dict[str, Any]:
        """The summary as a JSON-ready dict, its keys the field names."""
        return dataclasses.asdict(self)


def time_to_coverage(times: NDArray[np.float64], curve: NDArray[np.float64], level: float) -> float | None:
    """First time (s) at which ``curve`` reaches ``level``; None if it never does."""
    reached = np.flatnonzero(curve >= level - 1e-12)
    return float(times[reached[0]]) if reached.size else None


def sample_step(times: ArrayLike, values: ArrayLike, at: ArrayLike) -> NDArray[np.float64]:
    """A step function that takes ``values[i]`` from ``times[i]`` (s, increasing) on, sampled at
    ``at``: 0 before the first time, the last value after the last."""
    t = np.asarray(times, dtype=np.float64)
    v = np.asarray(values, dtype=np.float64)
    where = np.asarray(at, dtype=np.float64)
    if t.size == 0:
        return np.zeros_like(where)
    index = np.searchsorted(t, where, side="right") - 1
    return np.where(index >= 0, v[np.maximum(index, 0)], 0.0)
