"""Turn a world argument (a generator name or a map file) into a :class:`World`."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from frontier_rl.core.world.catalog import WORLD_GENERATORS, generate_world
from frontier_rl.core.world.robot import Pose, checked_pose
from frontier_rl.core.world.worlds import World, check_resolution, make_world
from frontier_rl.errors import ConfigError, MapError, UnknownNameError, short_repr
from frontier_rl.io import load_map


def checked_resolution(resolution: float | None, what: str = "--resolution") -> float | None:
    """``resolution`` (m) if a world can use it (:func:`~frontier_rl.core.world.worlds.check_resolution`
    for the default robot: 0.0042 to 0.105 m), None for None.

    Raises:
        ConfigError: any other value, named with ``what``.
    """
    if resolution is None:
        return None
    try:
        return check_resolution(resolution, what)
    except MapError as exc:
        raise ConfigError(str(exc)) from None


def resolve_world(spec: str, seed: int, start: Pose | None = None, resolution: float | None = None) -> World:
    """The world named by ``spec``: a procedural generator ("office", "rooms", "cluttered") drawn
    with ``seed``, or a map file (ROS YAML, DungeonMaps PNG, HouseExpo JSON, bitmap).

    Args:
        spec: generator name or path.
        seed: seeds the generator, or the random start on a map file without one.
        start: a start pose that replaces the generated / stored one.
        resolution: cell size (m) for map files that carry none (bitmaps, HouseExpo); checked
            (:func:`checked_resolution`) before the file is read, whatever the world.

    Raises:
        UnknownNameError: neither a generator nor an existing file.
        ConfigError: a resolution or start no world can use.
        MapError: a map file that cannot be used.
    """
    resolution = checked_resolution(resolution, "resolution")
    if start is not None:
        start = checked_pose(start, "start pose")
    if spec in WORLD_GENERATORS:
        world = generate_world(spec, seed)
        return world if start is None else make_world(world.grid, world.name, start=start)
    path = Path(spec)
    if not path.exists():
        raise UnknownNameError(
            f"unknown world {short_repr(spec)}: not one of {', '.join(sorted(WORLD_GENERATORS))}, and no such file"
        )
    loaded = load_map(path, resolution=resolution)
    return make_world(loaded.grid, path.stem, start=start or loaded.start, rng=np.random.default_rng(seed))


def parse_pose(text: str) -> Pose:
    """A pose from "x,y" or "x,y,theta" (m, m, rad): finite, the heading within +-1e6 rad and
    wrapped into [-pi, pi) (:func:`~frontier_rl.core.world.robot.checked_pose`).

    Raises:
        ConfigError: anything else, quoting ``text`` (cut to 80 characters).
    """
    usage = f"start pose must be 'x,y' or 'x,y,theta' in metres/radians, got {short_repr(text)}"
    parts = text.split(",")
    if len(parts) not in (2, 3):
        raise ConfigError(usage)
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise ConfigError(usage) from None
    if not all(np.isfinite(values)):
        raise ConfigError(usage)
    return checked_pose(Pose(*values), f"start pose {short_repr(text)}")
