"""Turn a world argument (a generator name or a map file) into a :class:`World`."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from frontier_rl.core.robot import Pose
from frontier_rl.core.worlds import WORLD_GENERATORS, World, generate_world, make_world
from frontier_rl.errors import ConfigError, UnknownNameError
from frontier_rl.io import load_map


def resolve_world(spec: str, seed: int, start: Pose | None = None, resolution: float | None = None) -> World:
    """The world named by ``spec``: a procedural generator ("office", "rooms", "cluttered") drawn
    with ``seed``, or a map file (ROS YAML, DungeonMaps PNG, HouseExpo JSON, bitmap).

    Args:
        spec: generator name or path.
        seed: seeds the generator, or the random start on a map file without one.
        start: a start pose that replaces the generated / stored one.
        resolution: cell size (m) for map files that carry none (bitmaps, HouseExpo).
    """
    if spec in WORLD_GENERATORS:
        world = generate_world(spec, seed)
        return world if start is None else make_world(world.grid, world.name, start=start)
    path = Path(spec)
    if not path.exists():
        raise UnknownNameError(
            f"unknown world {spec!r}: not one of {', '.join(sorted(WORLD_GENERATORS))}, and no such file"
        )
    loaded = load_map(path, resolution=resolution)
    return make_world(loaded.grid, path.stem, start=start or loaded.start, rng=np.random.default_rng(seed))


def parse_pose(text: str) -> Pose:
    """A pose from "x,y" or "x,y,theta" (m, m, rad)."""
    parts = text.split(",")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise ConfigError(f"start pose must be 'x,y' or 'x,y,theta' in metres/radians, got {text!r}") from None
    if len(values) not in (2, 3) or not all(np.isfinite(values)):
        raise ConfigError(f"start pose must be 'x,y' or 'x,y,theta' in metres/radians, got {text!r}")
    return Pose(*values)
