"""How long a robot has explored, on a clock that may jump back or be paused: the time a node's
time cap and status count."""

from __future__ import annotations


class ExploredTime:
    """The time explored (s) on a clock read now and then: the clock's time as it moves on between
    readings, a jump back (a restarted simulator's ``/clock``) counted as no time, and the time
    between readings while :meth:`held` (a pause) not counted."""

    def __init__(self) -> None:
        self._last_s: float | None = None  # the clock at the last reading (s)
        self.elapsed_s = 0.0
        """The time explored so far (s)."""

    def advanced(self, now_s: float) -> float:
        """The time explored with the clock now at ``now_s`` (s)."""
        if self._last_s is not None and now_s > self._last_s:
            self.elapsed_s += now_s - self._last_s
        self._last_s = now_s
        return self.elapsed_s

    def held(self, now_s: float) -> None:
        """The clock read at ``now_s`` (s) while exploring is paused: the time since the last
        reading is not explored."""
        self._last_s = now_s
