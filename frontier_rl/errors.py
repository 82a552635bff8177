"""Exception types: every error a user can cause names the bad value in one line."""

from __future__ import annotations


class FrontierRLError(Exception):
    """Base class of the errors frontier_rl raises for bad input."""


class MapError(FrontierRLError, ValueError):
    """A map file or grid that cannot be used (malformed, truncated, no free space)."""


class ConfigError(FrontierRLError, ValueError):
    """A configuration value out of range or of the wrong kind (a weight outside [0, 1], ...)."""


class UnknownNameError(FrontierRLError, KeyError):
    """A world, policy or method name that does not exist."""

    def __str__(self) -> str:  # KeyError quotes its argument; keep the message readable
        return str(self.args[0]) if self.args else ""
