"""How often a repeated warning is logged: a bad message on a topic can come many times a second."""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass
class ThrottledLog:
    """Says whether a warning is due: each key (robot and kind of problem) at most once per
    ``period_s``."""

    period_s: float = 10.0
    _last: dict[tuple[str, str], float] = field(default_factory=dict)

    def due(self, robot: str, kind: str, now_s: float) -> bool:
        """Whether to log (and, if so, start the key's quiet period now)."""
        last = self._last.get((robot, kind))
        if last is not None and now_s - last < self.period_s:
            return False
        self._last[(robot, kind)] = now_s
        return True
