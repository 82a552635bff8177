"""What a team knows: the cells a surviving robot has seen, and the team's coverage curve.

The :class:`~frontier_rl.swarm.team.TeamSimulator` adds each shared scan's window as it merges it
and rebuilds the whole from the surviving robots' maps when one fails; the curve gets a point each
time the count of explorable cells known changes.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


class TeamKnowledge:
    """The cells a team knows, and how their count grew.

    Args:
        explorable: the world's explorable cells (the coverage's denominator), its grid's shape.

    Attributes:
        known: the cells a surviving robot knows (the world's shape).
        count: how many of them are explorable.
        times, curve: the sim time (s) of each change of ``count``, never decreasing, and the count then.
    """

    def __init__(self, explorable: NDArray[np.bool_]) -> None:
        self._explorable = explorable
        self.known = np.zeros(explorable.shape, np.bool_)
        self.count = 0
        self.times: list[float] = []
        self.curve: list[int] = []

    def add(self, seen: NDArray[np.bool_], rows: slice, cols: slice, time_s: float) -> None:
        """A robot whose map knows the cells ``seen`` (the world's shape) shared the window
        (``rows``, ``cols``) of it at ``time_s`` (s)."""
        newly = seen[rows, cols] & ~self.known[rows, cols]
        self.known[rows, cols] |= newly
        self.count += int(np.count_nonzero(newly & self._explorable[rows, cols]))
        self._record(time_s)

    def rebuild(self, seen: list[NDArray[np.bool_]], time_s: float) -> None:
        """What the team knows is what the maps ``seen`` (the surviving robots') know, at ``time_s`` (s)."""
        self.known[:] = False
        for cells in seen:
            self.known |= cells
        self.count = int(np.count_nonzero(self.known & self._explorable))
        self._record(time_s)

    def _record(self, time_s: float) -> None:
        if self.curve and self.count == self.curve[-1]:
            return
        self.times.append(max(time_s, self.times[-1]) if self.times else time_s)
        self.curve.append(self.count)
