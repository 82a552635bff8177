"""Whether the robot's map is new enough to judge a goal on, and whether it has stopped coming.

A goal reached whose frontier is still open on the map is given up: it cannot be seen from there;
a goal aborted is given up unless the map shows its frontier seen.
But a SLAM map comes in its own time (slam_toolbox every 5 s by default, the simulator's every
0.1 s), so the map at hand when Nav2 says "reached" may predate the robot's arrival: judged on it,
the goal's frontier is still open, and a frontier the robot has just seen is given up (twice, and
it is never tried again), and a last look's mapped floor is not yet on it. A :class:`MapWatch` holds
the judgement of such a goal (ended, its frontier open on the map at hand, or a look) back until a
map from after the goal's end has come, for at most two of the map's periods (0.5-15 s); a map that
has stopped coming (SLAM crashed, a topic remapped) is then said so, and the goal is judged on the
last map, as before. A mapper that maps only as the robot moves sends no map while it stands: after
two such stands in a row, no judgement waits.
"""

from __future__ import annotations

import enum
import statistics
from collections import deque
from dataclasses import dataclass, field
from itertools import pairwise

_INTERVALS_KEPT = 5
"""The map's period is the median of this many last intervals between maps."""
_PERIODS_WAITED = 2.0
"""A judgement waits at most this many of the map's periods for a newer map, ..."""
_LEAST_WAIT_S = 0.5
"""... at least this long (wall s): a map's period measured while the robot stood may be short, ..."""
_MOST_WAIT_S = 15.0
"""... and at most this long (wall s): the robot stands while it waits."""
_QUIET_STANDS = 2
"""After this many goals after which no map came while the robot stood, though it had come as the
robot drove (a mapper that maps as the robot moves: gmapping's, rtabmap's), no judgement waits."""


class MapWait(enum.Enum):
    """What a judgement held back for a newer map does now."""

    READY = "ready"
    """Judge now: a map from after the goal's end has come (or no judgement waits)."""
    WAIT = "wait"
    """Wait: no newer map yet, within :meth:`MapWatch.wait_bound_s`."""
    STOPPED = "stopped"
    """Judge on the last map, which had stopped coming before the goal ended."""
    QUIET = "quiet"
    """Judge on the last map: it came as the robot drove, but not while it stood after the goal."""


@dataclass
class MapWatch:
    """When the robot's maps came, and a judgement that waits for one newer than a goal's end.

    Times are the node's: ``wall_s`` a steady clock (s), ``clock_s`` the ROS clock the maps are
    stamped with (s; simulated with ``use_sim_time``). A map's stamp counts only when it is not
    ahead of the node's clock as it comes: a robot's clock ahead of the explorer's would make the
    map at hand look newer than the goal's end.
    """

    _arrivals: deque[float] = field(default_factory=lambda: deque(maxlen=_INTERVALS_KEPT + 1))
    _last_stamp_s: float = 0.0  # 0: none to go by
    _pending: tuple[float, float] | None = None  # the goal's end: (wall s, clock s)
    _quiet_stands: int = 0
    waits: bool = True
    """Whether judgements still wait (no longer after :data:`_QUIET_STANDS` quiet stands)."""

    def map_came(self, wall_s: float, stamp_s: float, clock_s: float) -> None:
        """A map came at ``wall_s`` (``clock_s`` on the node's clock), stamped ``stamp_s`` (0 for a
        map stamped with no time)."""
        self._arrivals.append(wall_s)
        self._last_stamp_s = stamp_s if 0.0 < stamp_s <= clock_s else 0.0

    @property
    def period_s(self) -> float | None:
        """How often the map comes (s, the median of its last intervals); None before the second map."""
        times = self._arrivals
        if len(times) < 2:
            return None
        return statistics.median(later - earlier for earlier, later in pairwise(times))

    def wait_bound_s(self) -> float:
        """How long a judgement waits at most (wall s): two of the map's periods, within bounds."""
        return min(max(_PERIODS_WAITED * (self.period_s or 0.0), _LEAST_WAIT_S), _MOST_WAIT_S)

    def age_s(self, wall_s: float) -> float:
        """How long ago the last map came (s); infinite before the first."""
        return wall_s - self._arrivals[-1] if self._arrivals else float("inf")

    def goal_ended(self, wall_s: float, clock_s: float) -> bool:
        """A goal ended at ``wall_s`` (``clock_s`` on the ROS clock): whether its judgement
        waits for a newer map (not for a map that has come once, a fixed map, nor once waits stopped)."""
        self._pending = (wall_s, clock_s) if self.waits and self.period_s is not None else None
        return self._pending is not None

    def judgement(self, wall_s: float) -> MapWait:
        """Whether the judgement held back can be made now (:class:`MapWait`); all but WAIT end the wait."""
        if self._pending is None:
            return MapWait.READY
        ended_wall, ended_clock = self._pending
        waited = wall_s - ended_wall
        if self.age_s(wall_s) < waited or 0.0 < ended_clock <= self._last_stamp_s:
            self._pending, self._quiet_stands = None, 0
            return MapWait.READY
        if waited < self.wait_bound_s():
            return MapWait.WAIT
        self._pending = None
        if self.age_s(wall_s) - waited >= self.wait_bound_s():  # silent before the goal ended too
            return MapWait.STOPPED
        self._quiet_stands += 1
        self.waits = self._quiet_stands < _QUIET_STANDS
        return MapWait.QUIET

    def forget_goal(self) -> None:
        """No judgement waits any more (the run is over)."""
        self._pending = None
