"""Seeds: the range every entry point accepts (a world, an episode, a training run), checked."""

from __future__ import annotations

from frontier_rl.checked_values import python_integer
from frontier_rl.errors import ConfigError, short_repr

MAX_SEED = 2**32 - 1
"""Largest seed of a world and an episode (NumPy's legacy seeding, which SB3 uses, takes no more)."""


def checked_seed(value: object, what: str = "seed") -> int:
    """``value`` if it is a seed: a whole number from 0 to :data:`MAX_SEED` (a NumPy integer too).

    Raises:
        ConfigError: any other value, named with ``what``.
    """
    value = python_integer(value)  # a NumPy integer
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= MAX_SEED:
        raise ConfigError(f"{what} must be a whole number from 0 to {MAX_SEED}, got {short_repr(value)}")
    return value
