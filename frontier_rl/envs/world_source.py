"""Where an environment's worlds come from: a weighted mix of procedural generators, map files and
folders of map files, drawn per reset."""

from __future__ import annotations

import difflib
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.world.catalog import WORLD_GENERATORS
from frontier_rl.core.world.scale import checked_resolution
from frontier_rl.core.world.worlds import World
from frontier_rl.errors import ConfigError
from frontier_rl.io import load_map
from frontier_rl.map_fingerprint import MapFingerprint
from frontier_rl.world_spec import (
    WorldFamily,
    map_digest,
    map_file,
    parse_world_list,
    read_map,
    resolve_world,
    world_family,
)

__all__ = [
    "EAGER_LOAD_LIMIT",
    "RESET_OPTIONS",
    "TRAIN_SEED_LOW",
    "VALIDATION_SEED_LOW",
    "WorldSource",
    "check_world_files",
    "parse_world_list",
    "reset_world_seed",
]

TRAIN_SEED_LOW = 1_000_000
"""Generator seeds drawn for training lie in [TRAIN_SEED_LOW, 2³¹); seeds below it (``explore
--seed``, evaluations) are never trained on."""

VALIDATION_SEED_LOW = 900_000
"""Training's periodic evaluations use generator seeds from here up: neither trained on nor
among the small seeds used for evaluation."""

_SEED_HIGH = 2**31 - 1

RESET_OPTIONS = {"world_seed": "the generator seed of the world (a non-negative integer below 2**63) or None"}
"""The keys ``reset(options=...)`` takes, with what each must be."""

_WORLD_SEED_LIMIT = 2**63
"""World seeds lie in [0, 2**63)."""


def reset_world_seed(options: Any, *, ignore_unknown: bool = False) -> int | None:
    """The world seed of an env's ``reset(options=...)`` (None: draw one), after checking the
    options: None or a dict whose keys are among :data:`RESET_OPTIONS`.

    Args:
        options: what ``reset`` was given.
        ignore_unknown: let keys pass that are not reset options and look like none of them
            (PettingZoo's API test resets with ``{"options": 1}``); a near miss such as
            ``world_sed`` or ``WorldSeed`` is refused all the same.

    Raises:
        ConfigError: ``options`` is not a dict, has a key that is not a reset option (a typo such
            as ``world_sed`` would otherwise go unnoticed), or a value of the wrong kind.
    """
    if options is None:
        return None
    if not isinstance(options, Mapping):
        raise ConfigError(f"reset options must be a dict or None, got {type(options).__name__}")
    for key in options:
        if key in RESET_OPTIONS:
            continue
        close = _close_option(key)
        if close is None and ignore_unknown:
            continue
        hint = f" (did you mean {close!r}?)" if close else ""
        shown = repr(key) if len(repr(key)) <= 40 else repr(key)[:39] + "…"
        raise ConfigError(f"unknown reset option {shown}{hint}; known: {', '.join(RESET_OPTIONS)}")
    seed = options.get("world_seed")
    if seed is None:
        return None
    if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, (int, np.integer)):
        raise ConfigError(f"reset option world_seed must be {RESET_OPTIONS['world_seed']}, got a {type(seed).__name__}")
    if not 0 <= seed < _WORLD_SEED_LIMIT:
        shown = str(seed) if abs(int(seed)) < 10**30 else "a number of more than 30 digits"
        raise ConfigError(f"reset option world_seed must be {RESET_OPTIONS['world_seed']}, got {shown}")
    return int(seed)


def _close_option(key: Any) -> str | None:
    """The reset option ``key`` is a near miss of (case, "_" and "-" aside, or a close spelling)."""
    if not isinstance(key, str) or len(key) > 100:
        return None
    folded = {name.replace("_", "").lower(): name for name in RESET_OPTIONS}
    plain = key.replace("_", "").replace("-", "").lower()
    if plain in folded:
        return folded[plain]
    close = difflib.get_close_matches(key.lower(), list(RESET_OPTIONS), n=1)
    return close[0] if close else None


EAGER_LOAD_LIMIT = 64
"""A source of at most this many map files reads (and so checks) them all when it is made; a larger
mix reads each when it is drawn, keeping the last 128 read (:func:`~frontier_rl.world_spec.read_map`;
``train`` checks them all once before it starts)."""


@dataclass
class WorldSource:
    """Draws a world per episode from a mix of generators, map files and folders of map files
    (:func:`~frontier_rl.world_spec.parse_world_mix`).

    Args:
        worlds: the entries, "NAME" or "NAME=WEIGHT": generator names ("office", "rooms",
            "cluttered", "building", "cave"), map files and folders.
        resolution: cell size (m) for map files that carry none.
        split: "train" draws a folder's training files; "validation" its held-out files
            (:meth:`~frontier_rl.world_spec.WorldFamily.split`), the family chosen round robin
            by the world seed, so that every family is validated on.
    """

    worlds: tuple[str, ...]
    resolution: float | None = None
    split: str = "train"
    families: tuple[WorldFamily, ...] = field(init=False)
    _members: tuple[tuple[str, ...], ...] = field(init=False, repr=False)
    _p: NDArray[np.float64] | None = field(default=None, init=False, repr=False)  # None: all weights equal

    def __post_init__(self) -> None:
        if not self.worlds:
            raise ConfigError("an environment needs at least one world")
        checked_resolution(self.resolution, "resolution")  # now, not at the first reset
        self.families = tuple(world_family(entry) for entry in self.worlds)
        self._members = tuple(family.split(self.split) for family in self.families)
        weights = np.array([family.weight for family in self.families])
        self._p = None if np.all(weights == weights[0]) else weights / weights.sum()
        files = [m for members in self._members for m in members if m not in WORLD_GENERATORS]
        if len(files) <= EAGER_LOAD_LIMIT:
            for spec in files:  # read (and so check) every map file now, not at some later reset
                read_map(spec, self.resolution)

    def sample(self, rng: np.random.Generator, world_seed: int | None = None) -> World:
        """A world drawn with ``rng``: a family by weight (round robin by ``world_seed`` in the
        validation split), one of its files uniformly, then a generator seed in the training
        range (or ``world_seed`` if given), which also draws the start on a map file."""
        n = len(self.families)
        if self.split == "validation" and world_seed is not None:
            index = world_seed % n
        elif self._p is None:
            index = int(rng.integers(n))
        else:
            index = int(rng.choice(n, p=self._p))
        members = self._members[index]
        spec = members[int(rng.integers(len(members)))] if len(members) > 1 else members[0]
        seed = int(rng.integers(TRAIN_SEED_LOW, _SEED_HIGH)) if world_seed is None else int(world_seed)
        # a start stored in a map file is ignored: every episode starts at a random free cell
        return resolve_world(spec, seed, resolution=self.resolution, stored_start=False)


def check_world_files(worlds: tuple[str, ...], resolution: float | None = None) -> tuple[str, ...]:
    """Read every map file of ``worlds`` once (a bad one raises
    :class:`~frontier_rl.errors.MapError` naming it); returns each as ``spec#sha256:HASH``
    (:func:`~frontier_rl.world_spec.map_digest` of the map as loaded, without the start it may store:
    training draws its own), in the list's order."""
    files = [m for entry in worlds for m in world_family(entry).members if m not in WORLD_GENERATORS]
    loaded = (replace(load_map(map_file(spec), resolution=resolution), start=None) for spec in files)
    return tuple(str(MapFingerprint(spec, map_digest(grid))) for spec, grid in zip(files, loaded, strict=True))
