"""Where an environment's worlds come from: procedural generators and map files, drawn per reset."""

from __future__ import annotations

import difflib
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from frontier_rl.core.world.catalog import WORLD_GENERATORS, generate_world
from frontier_rl.core.world.worlds import World, make_world
from frontier_rl.errors import ConfigError, UnknownNameError, short_repr
from frontier_rl.io import LoadedMap, load_map

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

_MAP_SUFFIXES = (".yaml", ".yml", ".png", ".pgm", ".json", ".bmp")


def parse_world_list(text: str) -> tuple[str, ...]:
    """Split a comma-separated world list ("office,rooms,maps/") into entries, folders expanded
    into the map files they hold."""
    entries: list[str] = []
    for item in (part.strip() for part in text.split(",")):
        if not item:
            continue
        path = Path(item)
        try:
            is_dir, is_file = path.is_dir(), path.is_file()
        except OSError as exc:  # a name too long for the file system, ...
            raise ConfigError(f"world {short_repr(item)}: {exc.strerror or exc}") from None
        if item not in WORLD_GENERATORS and is_dir:
            files = sorted(str(p) for p in path.iterdir() if p.suffix.lower() in _MAP_SUFFIXES)
            yaml_stems = {Path(p).stem for p in files if p.endswith((".yaml", ".yml"))}
            # a ROS map's image is read through its YAML; do not also load it as a bitmap
            files = [p for p in files if p.endswith((".yaml", ".yml")) or Path(p).stem not in yaml_stems]
            if not files:
                raise ConfigError(f"world folder {short_repr(item)} holds no map files ({', '.join(_MAP_SUFFIXES)})")
            entries.extend(files)
        elif item in WORLD_GENERATORS or is_file:
            entries.append(item)
        else:
            raise UnknownNameError(
                f"unknown world {short_repr(item)}: not one of {', '.join(sorted(WORLD_GENERATORS))}, "
                "and no such file or folder"
            )
    if not entries:
        raise ConfigError(f"no worlds given in {short_repr(text)}")
    return tuple(entries)


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


@dataclass
class WorldSource:
    """Draws a world per episode from a list of generator names and map files.

    Args:
        worlds: generator names ("office", "rooms", "cluttered") and map file paths.
        resolution: cell size (m) for map files that carry none.
    """

    worlds: tuple[str, ...]
    resolution: float | None = None
    _maps: dict[str, LoadedMap] = field(default_factory=dict, init=False, repr=False)

    def __post_init__(self) -> None:
        if not self.worlds:
            raise ConfigError("an environment needs at least one world")
        for spec in self.worlds:  # load (and so check) every map file now, not at some later reset
            if spec not in WORLD_GENERATORS:
                self._load(spec)

    def _load(self, spec: str) -> LoadedMap:
        if spec not in self._maps:
            if not Path(spec).is_file():
                raise UnknownNameError(
                    f"unknown world {spec!r}: not one of {', '.join(sorted(WORLD_GENERATORS))}, and no such file"
                )
            self._maps[spec] = load_map(spec, resolution=self.resolution)
        return self._maps[spec]

    def sample(self, rng: np.random.Generator, world_seed: int | None = None) -> World:
        """A world drawn with ``rng``: the generator or map uniformly, then a generator seed in the
        training range (or ``world_seed`` if given), which also draws the start on a map file."""
        spec = self.worlds[int(rng.integers(len(self.worlds)))]
        seed = int(rng.integers(TRAIN_SEED_LOW, _SEED_HIGH)) if world_seed is None else int(world_seed)
        if spec in WORLD_GENERATORS:
            return generate_world(spec, seed)
        # a start stored in the file is ignored: every episode starts at a random free cell
        return make_world(self._load(spec).grid, Path(spec).stem, rng=np.random.default_rng(seed))
