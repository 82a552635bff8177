"""Worlds drawn per reset: generator names, map files and folders."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from frontier_rl.core.world.catalog import generate_world
from frontier_rl.envs.world_source import TRAIN_SEED_LOW, WorldSource, parse_world_list
from frontier_rl.errors import ConfigError, MapError, UnknownNameError


def test_parse_names_files_and_folders(shared_maps: Path) -> None:
    assert parse_world_list("office, rooms") == ("office", "rooms")
    entries = parse_world_list(f"cluttered,{shared_maps / 'turtlebot3_world'}")
    assert entries == ("cluttered", str(shared_maps / "turtlebot3_world" / "map.yaml"))  # not also map.pgm
    houses = parse_world_list(str(shared_maps / "houseexpo"))
    assert len(houses) == 2 and all(h.endswith(".json") for h in houses)


def test_parse_errors_name_the_entry(tmp_path: Path) -> None:
    with pytest.raises(UnknownNameError, match="mars"):
        parse_world_list("office,mars")
    with pytest.raises(ConfigError, match="no worlds"):
        parse_world_list(" , ")
    with pytest.raises(ConfigError, match="no map files"):
        parse_world_list(str(tmp_path))


def test_sample_is_seeded_and_uses_training_seeds() -> None:
    source = WorldSource(("office", "rooms"))
    a = source.sample(np.random.default_rng(1))
    b = source.sample(np.random.default_rng(1))
    assert np.array_equal(a.grid.data, b.grid.data) and a.start == b.start
    names = {source.sample(np.random.default_rng(k)).name for k in range(12)}
    assert names == {"office", "rooms"}
    chosen = WorldSource(("office",)).sample(np.random.default_rng(0), world_seed=7)
    assert np.array_equal(chosen.grid.data, generate_world("office", 7).grid.data)
    assert TRAIN_SEED_LOW >= 1_000_000


def test_map_files_get_random_starts(shared_maps: Path) -> None:
    source = WorldSource(parse_world_list(str(shared_maps / "turtlebot3_world")))
    starts = {source.sample(np.random.default_rng(k)).start for k in range(4)}
    assert len(starts) == 4


def test_bad_map_file_fails_at_construction(tmp_path: Path) -> None:
    bad = tmp_path / "broken.yaml"
    bad.write_text(
        "image: missing.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )
    with pytest.raises(MapError, match=r"missing\.pgm"):
        WorldSource((str(bad),))
