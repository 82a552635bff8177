"""Worlds drawn per reset: generator names, map files and folders, with sampling weights and
train / validation splits."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from frontier_rl import world_spec
from frontier_rl.core.world.catalog import generate_world
from frontier_rl.envs import world_source
from frontier_rl.envs.world_source import TRAIN_SEED_LOW, WorldSource, check_world_files
from frontier_rl.errors import ConfigError, MapError, UnknownNameError
from frontier_rl.io import LoadedMap, load_map
from frontier_rl.world_spec import VALIDATION_SHARE, parse_world_list, parse_world_mix


def test_parse_names_files_and_folders(real_maps: Path) -> None:
    assert parse_world_list("office, rooms") == ("office", "rooms")
    entries = parse_world_list(f"cluttered,{real_maps / 'turtlebot3_world'}")
    assert entries == ("cluttered", str(real_maps / "turtlebot3_world" / "map.yaml"))  # not also map.pgm
    houses = parse_world_list(str(real_maps / "houseexpo"))
    assert len(houses) == 2 and all(h.endswith(".json") for h in houses)


def test_a_folder_lists_a_ros_map_once_whatever_its_image_is_called(tmp_path: Path, real_maps: Path) -> None:
    source = real_maps / "turtlebot3_world"
    image = (source / "map.pgm").read_bytes()
    (tmp_path / "world.pgm").write_bytes(image)  # the image the YAML names, of another stem
    (tmp_path / "map.yaml").write_text((source / "map.yaml").read_text().replace("map.pgm", "world.pgm"))
    (tmp_path / "world.png").write_bytes((real_maps / "dungeon" / "easy" / "img_1.png").read_bytes())
    assert parse_world_list(str(tmp_path)) == (str(tmp_path / "map.yaml"), str(tmp_path / "world.png"))
    (tmp_path / "map.yaml").write_text("image: [")  # broken: named where it is loaded, not here
    assert str(tmp_path / "world.pgm") in parse_world_list(str(tmp_path))


def test_parse_errors_name_the_entry(tmp_path: Path) -> None:
    with pytest.raises(UnknownNameError, match="mars"):
        parse_world_list("office,mars")
    with pytest.raises(ConfigError, match="no worlds"):
        parse_world_list(" , ")
    with pytest.raises(ConfigError, match="no map files"):
        parse_world_list(str(tmp_path))
    (tmp_path / "room.bmp").write_bytes(b"BM")  # no loader reads it: not a map file of the folder
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


def test_map_files_get_random_starts(real_maps: Path) -> None:
    source = WorldSource(parse_world_list(str(real_maps / "turtlebot3_world")))
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


def make_folder(folder: Path, n: int, pattern: str = "room_{:03d}.png") -> Path:
    """``n`` small bitmap maps (an open room each, 2 m square at 0.05 m), named by ``pattern``."""
    from PIL import Image

    folder.mkdir()
    image = np.zeros((40, 40), np.uint8)
    image[3:-3, 3:-3] = 255
    for k in range(n):
        Image.fromarray(image).save(folder / pattern.format(k))
    return folder


def test_weights_are_parsed_and_bad_ones_refused(tmp_path: Path) -> None:
    families = parse_world_mix("office=2, rooms ,cluttered=0.5")
    assert [(f.spec, f.members, f.weight) for f in families] == [
        ("office", ("office",), 2.0), ("rooms", ("rooms",), 1.0), ("cluttered", ("cluttered",), 0.5)
    ]  # fmt: skip
    for bad in ("office=0", "office=-1", "office=nan", "office=inf", "office=two", "office=", "office=1e7"):
        with pytest.raises(ConfigError, match="world weight must be a number"):
            parse_world_mix(bad)
    with pytest.raises(UnknownNameError, match="mars"):
        parse_world_mix("mars=2")
    odd = tmp_path / "a=b"  # an existing folder whose name holds "=" is taken as it is
    make_folder(odd, 1)
    assert parse_world_mix(str(odd))[0].members == (str(odd / "room_000.png"),)


def test_an_evaluation_list_refuses_weights() -> None:
    with pytest.raises(ConfigError, match="'rooms=2' has a weight"):
        parse_world_list("office,rooms=2")


def test_families_are_drawn_by_weight_and_a_folder_shares_its_weight(tmp_path: Path) -> None:
    folder = make_folder(tmp_path / "maps", 12)
    source = WorldSource(("office=3", f"{folder}=1"))
    names = [source.sample(np.random.default_rng(k)).name for k in range(400)]
    office = names.count("office") / len(names)
    assert 0.68 < office < 0.82  # 3 / 4: the folder's 12 files share its weight of 1
    equal = WorldSource(("office", "rooms"))
    assert equal._p is None  # equal weights draw as a plain uniform index (the draws of before)


def test_validation_files_are_held_out_of_training(tmp_path: Path) -> None:
    folder = make_folder(tmp_path / "maps", 40)
    family = parse_world_mix(str(folder))[0]
    train, held_out = family.split("train"), family.split("validation")
    assert set(train) | set(held_out) == set(family.members) and not set(train) & set(held_out)
    assert 0 < len(held_out) < len(family.members) / 4
    trained = {WorldSource((str(folder),)).sample(np.random.default_rng(k)).name for k in range(300)}
    validated = {
        WorldSource((str(folder),), split="validation").sample(np.random.default_rng(k), world_seed=k).name
        for k in range(60)
    }
    assert trained <= {Path(p).stem for p in train} and validated <= {Path(p).stem for p in held_out}
    small = make_folder(tmp_path / "few", VALIDATION_SHARE - 1)
    assert parse_world_mix(str(small))[0].split("validation") == parse_world_mix(str(small))[0].members
    with pytest.raises(ConfigError, match="unknown split"):
        family.split("test")


def test_validation_visits_every_family_in_turn() -> None:
    source = WorldSource(("office", "rooms", "cluttered"), split="validation")
    names = [source.sample(np.random.default_rng(0), world_seed=900_000 + k).name for k in range(6)]
    assert names == ["office", "rooms", "cluttered"] * 2  # the family of seed s is families[s % 3]: 900,000 % 3 == 0


def test_large_mixes_read_files_when_drawn_and_check_them_once(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    folder = make_folder(tmp_path / "maps", 8)
    (folder / "room_003.png").write_bytes(b"not a png")
    monkeypatch.setattr(world_source, "EAGER_LOAD_LIMIT", 4)
    read: list[str] = []

    def spy(path: str, resolution: float | None) -> LoadedMap:
        read.append(path)
        return load_map(path, resolution=resolution)

    monkeypatch.setattr(world_spec, "load_map", spy)
    source = WorldSource((str(folder),))  # 8 files > 4: nothing read yet
    assert read == []
    with pytest.raises(MapError, match="room_003"):
        check_world_files((str(folder),))
    with pytest.raises(MapError, match="room_003"):
        for k in range(100):
            source.sample(np.random.default_rng(k))
    assert read and len(read) == len(set(read))  # each file read once, when first drawn


def test_a_folder_of_ten_or_more_always_keeps_a_validation_file(tmp_path: Path) -> None:
    """map_0 ... map_14: no name hashes to the validation residue, so the least hash is held out."""
    for n in (10, 15, 20):
        folder = make_folder(tmp_path / f"n{n}", n, "map_{}.png")
        family = parse_world_mix(str(folder))[0]
        held_out, train = family.split("validation"), family.split("train")
        assert held_out and train and not set(held_out) & set(train) and len(held_out) + len(train) == n
    assert len(parse_world_mix(str(tmp_path / "n15"))[0].split("validation")) == 1  # the fallback


def test_an_entry_without_a_name_is_refused() -> None:
    with pytest.raises(ConfigError, match="names no world"):
        parse_world_mix("=2")


def test_tuple_entries_are_taken_whole(tmp_path: Path) -> None:
    """A map file whose name holds a comma works as a tuple entry (a string list splits at commas)."""
    folder = make_folder(tmp_path / "a,b", 1)
    source = WorldSource((str(folder / "room_000.png"), "office=2"))
    assert [f.spec for f in source.families] == [str(folder / "room_000.png"), "office"]


def test_a_resolution_no_world_can_use_is_refused_when_the_source_is_made() -> None:
    with pytest.raises(ConfigError, match="resolution"):
        WorldSource(("office",), resolution=0.5)
