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
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.world.grid import CellState

_UNKNOWN = np.int8(CellState.UNKNOWN)
AUDIT_BUDGET = 2
"""A goal is given up for good after this many times ``max_failures`` failed legs."""


@dataclass
class BlacklistEntry:
    """A goal that failed.

    Attributes:
        x, y: the goal (m), in the map's frame.
        failures: how often a leg to it failed.
        known: known cells in the window around it when it last failed (the map's state there).
        active: whether it blocks frontiers now.
    """

    x: float
    y: float
    failures: int
    known: int
    active: bool = True


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
        return int(window.size - np.count_nonzero(window == _UNKNOWN))

    def fail(self, x: float, y: float, state: NDArray[np.int8]) -> None:
        """Record that the goal (x, y) (m) failed, with the map ``state`` as it is now."""
        known = self._known(state, x, y)
        for entry in self.entries:
            if math.hypot(entry.x - x, entry.y - y) <= self.radius:
                entry.failures += 1
                entry.known = known
                entry.active = True
                return
        self.entries.append(BlacklistEntry(x, y, 1, known))

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
        blocked = np.zeros(len(goals), np.bool_)
        for entry in self.entries:
            if entry.active and (not retrying or entry.failures >= self.max_failures):
                blocked |= np.hypot(goals[:, 0] - entry.x, goals[:, 1] - entry.y) <= self.radius
        return blocked

    def retry(self, budget: int | None = None) -> None:
        """Lift every entry that may still be retried: failed fewer than ``budget`` times
        (``max_failures`` by default; the audit's is ``AUDIT_BUDGET * max_failures``)."""
        limit = self.max_failures if budget is None else budget
        for entry in self.entries:
            if entry.failures < limit:
                entry.active = False

    def failures_near(self, x: float, y: float) -> int:
        """How often a goal within ``radius`` of (x, y) (m) failed."""
        near = [e.failures for e in self.entries if math.hypot(e.x - x, e.y - y) <= self.radius]
        return max(near, default=0)
