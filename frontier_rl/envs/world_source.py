"""Where an environment's worlds come from: procedural generators and map files, drawn per reset."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from frontier_rl.core.worlds import WORLD_GENERATORS, World, generate_world, make_world
from frontier_rl.errors import ConfigError, UnknownNameError
from frontier_rl.io import LoadedMap, load_map

TRAIN_SEED_LOW = 1_000_000
"""Generator seeds drawn for training lie in [TRAIN_SEED_LOW, 2³¹); seeds below it (``explore
--seed``, evaluations) are never trained on."""

VALIDATION_SEED_LOW = 900_000
"""Training's periodic evaluations use generator seeds from here up: neither trained on nor
among the small seeds used for evaluation."""

_SEED_HIGH = 2**31 - 1
_MAP_SUFFIXES = (".yaml", ".yml", ".png", ".pgm", ".json", ".bmp")


def parse_world_list(text: str) -> tuple[str, ...]:
    """Split a comma-separated world list ("office,rooms,maps/") into entries, folders expanded
    into the map files they hold."""
    entries: list[str] = []
    for item in (part.strip() for part in text.split(",")):
        if not item:
            continue
        path = Path(item)
        if item not in WORLD_GENERATORS and path.is_dir():
            files = sorted(str(p) for p in path.iterdir() if p.suffix.lower() in _MAP_SUFFIXES)
            yaml_stems = {Path(p).stem for p in files if p.endswith((".yaml", ".yml"))}
            # a ROS map's image is read through its YAML; do not also load it as a bitmap
            files = [p for p in files if p.endswith((".yaml", ".yml")) or Path(p).stem not in yaml_stems]
            if not files:
                raise ConfigError(f"world folder {item!r} holds no map files ({', '.join(_MAP_SUFFIXES)})")
            entries.extend(files)
        elif item in WORLD_GENERATORS or path.is_file():
            entries.append(item)
        else:
            raise UnknownNameError(
                f"unknown world {item!r}: not one of {', '.join(sorted(WORLD_GENERATORS))}, and no such file or folder"
            )
    if not entries:
        raise ConfigError(f"no worlds given in {text!r}")
    return tuple(entries)


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
