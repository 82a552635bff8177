"""Whether the robot's map is new enough to judge a goal on, and whether it has stopped coming.

A goal reached whose frontier is still open on the map is given up: it cannot be seen from there.
But a SLAM map comes in its own time (slam_toolbox every 5 s by default, the simulator's every
0.1 s), so the map at hand when Nav2 says "reached" may predate the robot's arrival: judged on it,
the goal's frontier is still open, and a frontier the robot has just seen is given up (twice, and
it is never tried again). A :class:`MapWatch` holds the judgement of such a goal (reached, its
frontier open on the map at hand) back until a map from after the goal's end has come, for at most
two of the map's periods; a map that has stopped coming (SLAM crashed, a topic remapped) is then
said so, and the goal is judged on the last map, as before.
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
"""A judgement waits at most this many of the map's periods for a newer map."""
_LEAST_WAIT_S = 0.5
"""... and at least this long (wall s): a map's period measured while the robot stood may be short."""


class MapWait(enum.Enum):
    """What a judgement held back for a newer map does now."""

    READY = "ready"
    """Judge now: a map from after the goal's end has come (or no judgement waits, or the map has
    come only once: a fixed map, which no wait makes newer)."""
    WAIT = "wait"
    """Wait: no newer map yet, within two of the map's periods."""
    STALE = "stale"
    """Judge on the last map: none has come from after the goal's end within two of its periods."""


@dataclass
class MapWatch:
    """When the robot's maps came, and a judgement that waits for one newer than a goal's end.

    Times are the node's: ``wall_s`` a steady clock (s), ``clock_s`` the ROS clock the maps are
    stamped with (s; simulated with ``use_sim_time``).
    """

    _arrivals: deque[float] = field(default_factory=lambda: deque(maxlen=_INTERVALS_KEPT + 1))
    _last_stamp_s: float = 0.0
    _pending: tuple[float, float] | None = None  # the goal's end: (wall s, clock s)

    def map_came(self, wall_s: float, stamp_s: float) -> None:
        """A map came at ``wall_s``, stamped ``stamp_s`` (0 for a map stamped with no time)."""
        self._arrivals.append(wall_s)
        self._last_stamp_s = stamp_s

    @property
    def period_s(self) -> float | None:
        """How often the map comes (s, the median of its last intervals); None before the third map."""
        times = self._arrivals
        if len(times) < 3:
            return None
        return statistics.median(later - earlier for earlier, later in pairwise(times))

    def age_s(self, wall_s: float) -> float:
        """How long ago the last map came (s); infinite before the first."""
        return wall_s - self._arrivals[-1] if self._arrivals else float("inf")

    def goal_ended(self, wall_s: float, clock_s: float) -> None:
        """A goal was reached at ``wall_s`` (``clock_s`` on the ROS clock): its judgement waits for a newer map."""
        self._pending = (wall_s, clock_s)

    def judgement(self, wall_s: float) -> MapWait:
        """Whether the judgement held back can be made now (:class:`MapWait`); READY and STALE end the wait."""
        if self._pending is None:
            return MapWait.READY
        ended_wall, ended_clock = self._pending
        newer = self.age_s(wall_s) < wall_s - ended_wall or 0.0 < ended_clock <= self._last_stamp_s
        period = self.period_s
        if newer or period is None:
            self._pending = None
            return MapWait.READY
        if wall_s - ended_wall < max(_PERIODS_WAITED * period, _LEAST_WAIT_S):
            return MapWait.WAIT
        self._pending = None
        return MapWait.STALE
