"""Goals the robot failed to reach or to resolve, and when to try them again.

explore_lite blacklists a failed frontier for good, and every frontier whose centre lies near it;
on real maps that swallows whole rings and arcs of frontier and ends exploration with rooms unseen.
Here a failure blacklists only the failed goal's own neighbourhood (the frontiers whose *goal*
lies within ``radius`` of it), and the entry is lifted

- when the map around it changes (as paulbovbel/frontier_exploration does after its PR #25): the
  robot saw something new there, so the way or the view may have opened;
- once, before the episode would end with that frontier unexplored: the robot retries it from
  wherever it then is, another approach;
- and when that too would leave nothing to go to, for a goal the robot's map still has a way to
  (it is found among the reachable frontiers again), as many tries again as it had: the audit
  before giving up, with a bounded budget (``AUDIT_BUDGET`` times ``max_failures`` in all).

A goal that has used up that budget stays blacklisted: the episode can then end, and names it
among the frontiers it could not explore.

A goal the robot *reached* whose frontier stayed (it stood at the viewpoint chosen to see it, closed
in on the goal cell, waited for a map update, and nothing was revealed: a streak of free cells
drawn by rays through glass, a slot narrower than a beam's spacing) is a visit, not a failure to get
there. A goal visited ``max_failures`` times without its frontier going away is *unrevealable*: the
view it was chosen for has been had, twice, and revealed nothing. The audit does not lift it, so
such frontiers are not chased again and again (the harder survey's SLAM maps had 86-146 such legs
an episode); the episode names them apart from the frontiers it gave up on with a path left. The
goals reached are kept as *views had* (:meth:`Blacklist.views_had`): the robot stood there and its
scan showed what it could, so that the audit does not count a look from there as one still to have.

A frontier keeps its history where it reappears: on a SLAM map a streak's frontier comes back a cell
further on, or split, its goal elsewhere. A failure whose frontier touches (within a cell and a half)
the cells of an entry's failed frontiers counts towards that entry, and the entry blocks its new goal
too, so that the frontier's failures add up however its goal moves.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from frontier_rl.core.world.grid import UNKNOWN_I8

AUDIT_BUDGET = 2
"""A goal is given up for good after this many times ``max_failures`` failed legs."""


@dataclass
class BlacklistEntry:
    """A place whose goals failed.

    Attributes:
        x, y: the first goal that failed there (m), in the map's frame; the window of ``known``.
        failures: how often a leg to one of its goals failed, visits included.
        known: known cells in the window around (x, y) when a goal last failed (the map's state there).
        active: whether it blocks frontiers now.
        visits: of ``failures``, the legs that reached their goal and left its frontier unresolved.
        goals: every goal that failed there ((k, 2), m): frontiers whose goal lies within the
            blacklist's radius of one are blocked.
        frontier: the cells of the frontiers those goals were for ((n, 2), m; empty when unknown).
        viewed: the goals it failed at that the robot reached and scanned from ((j, 2), m, one
            row a time): views had.
    """

    x: float
    y: float
    failures: int
    known: int
    active: bool = True
    visits: int = 0
    goals: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 2)))
    frontier: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 2)))
    viewed: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 2)))

    def __post_init__(self) -> None:
        if len(self.goals) == 0:
            self.goals = np.array([[self.x, self.y]], np.float64)

    def near_goals(self, points: NDArray[np.float64], radius: float) -> NDArray[np.bool_]:
        """Which of ``points`` ((n, 2), m) lie within ``radius`` (m) of one of its goals."""
        gaps = np.hypot(points[:, None, 0] - self.goals[None, :, 0], points[:, None, 1] - self.goals[None, :, 1])
        return np.asarray(gaps.min(axis=1) <= radius)

    def touches(self, cells: NDArray[np.float64], reach: float) -> bool:
        """Whether a frontier's ``cells`` ((n, 2), m) lie within ``reach`` (m) of its frontiers' cells."""
        if len(cells) == 0 or len(self.frontier) == 0:
            return False
        gaps = np.hypot(cells[:, None, 0] - self.frontier[None, :, 0], cells[:, None, 1] - self.frontier[None, :, 1])
        return bool(gaps.min() <= reach)


class Blacklist:
    """The failed goals of one robot.

    Args:
        radius: frontiers whose goal lies within this distance (m) of a failed goal are blocked.
        max_failures: a goal that failed this often is never retried.
        window: half-size (m) of the square around a goal whose known cells are watched.
        resolution, origin: the map's cell size (m) and origin (m): goals are turned into cells.
        change_cells: the map around a goal has changed when this many more cells are known.
    """

    def __init__(
        self,
        radius: float,
        max_failures: int,
        resolution: float,
        origin: tuple[float, float],
        window: float = 1.0,
        change_cells: int = 10,
    ) -> None:
        self.radius = radius
        self.max_failures = max_failures
        self._resolution = resolution
        self._origin = origin
        self._half = max(1, int(math.ceil(window / resolution)))
        self._change_cells = change_cells
        self.entries: list[BlacklistEntry] = []

    def reframe(self, resolution: float, origin: tuple[float, float]) -> None:
        """The map was re-laid (a SLAM map grows, its origin moves): read it with these cell size
        and origin (m) from now on; the goals stay where they are."""
        self._resolution, self._origin = resolution, origin

    def __len__(self) -> int:
        return sum(entry.active for entry in self.entries)

    def _known(self, state: NDArray[np.int8], x: float, y: float) -> int:
        """Known cells in the window around (x, y) (m) of ``state`` (the full-world map)."""
        col = int(math.floor((x - self._origin[0]) / self._resolution))
        row = int(math.floor((y - self._origin[1]) / self._resolution))
        h = self._half
        window = state[max(row - h, 0) : row + h + 1, max(col - h, 0) : col + h + 1]
        return int(window.size - np.count_nonzero(window == UNKNOWN_I8))

    def _touch_reach(self) -> float:
        """How near (m) a frontier's cell must lie to an entry's to be the same frontier: a cell and a half."""
        return 1.5 * self._resolution

    def _entry_of(self, x: float, y: float, frontier: NDArray[np.float64]) -> BlacklistEntry | None:
        """The entry a failure at goal (x, y) (m) of a frontier with cells ``frontier`` belongs to."""
        goal = np.array([[x, y]])
        for entry in self.entries:
            if math.hypot(entry.x - x, entry.y - y) <= self.radius:
                return entry
        for entry in self.entries:
            if entry.near_goals(goal, self.radius)[0] or entry.touches(frontier, self._touch_reach()):
                return entry
        return None

    def fail(
        self,
        x: float,
        y: float,
        state: NDArray[np.int8],
        *,
        reached: bool = False,
        frontier: NDArray[np.float64] | None = None,
        viewed: bool | None = None,
    ) -> None:
        """Record that the goal (x, y) (m) failed, with the map ``state`` as it is now; ``reached``:
        a visit (the robot got there and the frontier stayed); ``frontier``: the cells of the
        frontier it was for ((n, 2), m), whose history it joins where it touches an entry's;
        ``viewed``: whether the robot stood at the goal and scanned from it (default ``reached``;
        a look counts as a visit whatever its leg did)."""
        cells = np.zeros((0, 2)) if frontier is None else np.asarray(frontier, np.float64).reshape(-1, 2)
        had_view = reached if viewed is None else viewed
        views = np.array([[x, y]] if had_view else [], np.float64).reshape(-1, 2)
        entry = self._entry_of(x, y, cells)
        if entry is None:
            known = self._known(state, x, y)
            self.entries.append(BlacklistEntry(x, y, 1, known, visits=int(reached), frontier=cells, viewed=views))
            return
        entry.viewed = np.vstack((entry.viewed, views))
        entry.failures += 1
        entry.visits += reached
        entry.known = self._known(state, entry.x, entry.y)  # the window refresh watches
        entry.active = True
        if not entry.near_goals(np.array([[x, y]]), self.radius)[0]:
            entry.goals = np.vstack((entry.goals, [[x, y]]))
        if len(cells):
            entry.frontier = np.unique(np.vstack((entry.frontier, cells)), axis=0)

    def unrevealable(self, entry: BlacklistEntry) -> bool:
        """Whether ``entry`` was visited ``max_failures`` times and its frontier stayed."""
        return entry.visits >= self.max_failures

    def refresh(self, state: NDArray[np.int8]) -> None:
        """Lift the entries that may still be retried around which the map ``state`` has changed
        since they failed."""
        for entry in self.entries:
            if not entry.active or entry.failures >= self.max_failures:
                continue
            if self._known(state, entry.x, entry.y) - entry.known >= self._change_cells:
                entry.active = False

    def blocked(self, goals: NDArray[np.float64], *, retrying: bool = False) -> NDArray[np.bool_]:
        """Which of the goals ((n, 2), m) an active entry blocks; with ``retrying``, only the
        entries that have used up their failures block."""
        least = self.max_failures if retrying else 0
        return self._near_goals_of(goals, [e for e in self.entries if e.active and e.failures >= least])

    def _near_goals_of(self, points: NDArray[np.float64], entries: list[BlacklistEntry]) -> NDArray[np.bool_]:
        """Which of ``points`` ((n, 2), m) lie within ``radius`` of a goal of one of ``entries``."""
        near = np.zeros(len(points), np.bool_)
        for entry in entries:
            near |= entry.near_goals(points, self.radius)
        return near

    def retry(self, budget: int | None = None) -> None:
        """Lift every entry that may still be retried: failed fewer than ``budget`` times
        (``max_failures`` by default; the audit's is ``AUDIT_BUDGET * max_failures``) and not
        :meth:`unrevealable`."""
        limit = self.max_failures if budget is None else budget
        for entry in self.entries:
            if entry.failures < limit and not self.unrevealable(entry):
                entry.active = False

    def gave_up(self) -> bool:
        """Whether a goal has used up the audit's budget (``AUDIT_BUDGET`` times ``max_failures``)
        without being :meth:`unrevealable`: a frontier given up for want of a way there, not of a view."""
        budget = AUDIT_BUDGET * self.max_failures
        return any(entry.failures >= budget and not self.unrevealable(entry) for entry in self.entries)

    def views_had(self, points: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Which of ``points`` ((n, 2), m) lie within ``radius`` of a goal the robot reached and
        scanned from (:attr:`BlacklistEntry.viewed`): the blacklist's radius makes a goal there the
        same goal, so a look from there is a view already had."""
        views = np.vstack([np.zeros((0, 2))] + [entry.viewed for entry in self.entries])
        if len(views) == 0 or len(points) == 0:
            return np.zeros(len(points), np.bool_)
        return np.asarray(cKDTree(views).query_ball_point(points, self.radius, return_length=True) > 0)

    def tried_near(self, points: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Which of ``points`` ((n, 2), m) lie within ``radius`` of a goal tried (any entry's)."""
        return self._near_goals_of(points, self.entries)

    def spent_near(self, points: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Which of ``points`` ((n, 2), m) lie within ``radius`` of a view had (:meth:`views_had`)
        or of a goal of an entry that has used up the audit's budget: goals not to try again."""
        budget = AUDIT_BUDGET * self.max_failures
        return self.views_had(points) | self._near_goals_of(points, [e for e in self.entries if e.failures >= budget])

    def failures_near(self, x: float, y: float) -> int:
        """How often a goal within ``radius`` of (x, y) (m) failed."""
        return self.history_of(np.array([[x, y]]))[0]

    def history_of(self, cells: NDArray[np.float64]) -> tuple[int, bool]:
        """A frontier's history, from the entries with a goal within ``radius`` of one of its
        ``cells`` ((n, 2), m) or whose frontiers touch them: the most failures of one, and whether
        one is unrevealable."""
        failures, unrevealable = 0, False
        for entry in self.entries:
            if len(cells) and (entry.near_goals(cells, self.radius).any() or entry.touches(cells, self._touch_reach())):
                failures = max(failures, entry.failures)
                unrevealable |= self.unrevealable(entry)
        return failures, unrevealable
