"""The map catalogue: every shipped map loads by name, its listed size is the loaded grid's, its
folder carries its licence and source, and world arguments find catalogue names after generators
and paths."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

import frontier_rl.world_spec as world_spec
from frontier_rl.core.world.catalog import WORLD_GENERATORS
from frontier_rl.core.world.grid import CellState
from frontier_rl.envs.world_source import WorldSource, check_world_files
from frontier_rl.errors import ConfigError, MapError, UnknownNameError
from frontier_rl.evaluation.running.experiment import EpisodeSettings, ExperimentConfig, job_parts
from frontier_rl.evaluation.running.fingerprints import world_fingerprint
from frontier_rl.io import load_map
from frontier_rl.io.catalogue import (
    MAPS_DIR,
    Catalogue,
    CatalogueMap,
    MapCollection,
    MapFamily,
    catalogue,
    load_catalogue,
)
from frontier_rl.rl.config import TrainConfig
from frontier_rl.world_spec import map_file, parse_world_list, parse_world_mix, resolve_world, world_path
from tests.io.catalogue_names import STANDALONE

STAGE = ("stage/autolab", "stage/uoa_robotics_lab", "stage/simple_rooms", "stage/cave", "stage/mbicp")
COLLECTIONS = {
    "stage": 5,
    "houseexpo": 2,
    "dungeon/train": 500,
    "dungeon/easy": 100,
    "dungeon/medium": 100,
    "dungeon/complex": 100,
}


def _checked_maps() -> list[str]:
    """Every map but the dungeon collections', which are checked by their first, a middle and last member."""
    maps = catalogue()
    names = [m.name for m in maps.maps if m.family is not MapFamily.DUNGEON]
    for collection in maps.collections:
        if collection.family is MapFamily.DUNGEON:
            names += [collection.members[0], collection.members[len(collection.members) // 2], collection.members[-1]]
    return names


def test_the_catalogue_holds_the_documented_names() -> None:
    maps = catalogue()
    assert [e.name for e in maps.listed()] == [*STANDALONE, *COLLECTIONS]
    assert {c.name: len(c.members) for c in maps.collections} == COLLECTIONS
    assert set(STAGE) <= {m.name for m in maps.maps}
    assert "dungeon/easy/img_10" in maps.get("dungeon/easy").members  # type: ignore[union-attr]
    assert "houseexpo/house_expo_room_0000" in {m.name for m in maps.maps}
    assert len(maps.maps) == len(STANDALONE) + sum(COLLECTIONS.values())
    for entry in maps.maps:
        assert entry.path.is_relative_to(MAPS_DIR) and entry.installed, entry.name
        assert entry.source.startswith("https://github.com/") and entry.licence, entry.name
    assert {m.name for m in maps.maps if not m.in_wheel} == {
        *STAGE,
        "adblab",
        "brsu_c069",
    }  # copyleft: in the repository only


@pytest.mark.parametrize("name", _checked_maps())
def test_every_map_loads_as_a_world_with_the_listed_size(name: str) -> None:
    entry = catalogue().get(name)
    assert isinstance(entry, CatalogueMap)
    world = resolve_world(name, 0)
    assert world.name == name and world.grid.count(CellState.FREE) > 0
    grid = load_map(entry.path).grid
    size = entry.size()
    assert size is not None
    assert (size.height_cells, size.width_cells) == grid.shape and size.resolution_m == grid.resolution
    assert size.width_m == pytest.approx(grid.shape[1] * grid.resolution)


def test_a_uniform_collection_is_uniform() -> None:
    maps = catalogue()
    for collection in maps.collections:
        sizes = {m.size() for m in collection.maps}
        assert (len(sizes) == 1) == collection.uniform_size, collection.name
        assert collection.size() == (sizes.pop() if collection.uniform_size else None), collection.name
        assert collection.installed and collection.installed_count == len(collection.maps) > 0
        assert collection.members == tuple(m.name for m in collection.maps)
        assert all(maps.get(m.name) is m for m in collection.maps)


def test_resolving_a_world_looks_the_catalogue_up_once(monkeypatch: pytest.MonkeyPatch) -> None:
    looked_up: list[str] = []
    find = Catalogue.find

    def counted(self: Catalogue, name: str) -> CatalogueMap | MapCollection | None:
        looked_up.append(name)
        return find(self, name)

    monkeypatch.setattr(Catalogue, "find", counted)
    for name in ("lse_arena", "dungeon/easy/img_10"):
        looked_up.clear()
        assert resolve_world(name, 0).name == name
        assert looked_up == [name]
    looked_up.clear()
    resolve_world("office", 0)
    assert looked_up == []


def test_every_map_folder_has_its_licence_and_source() -> None:
    folders = sorted(p for p in MAPS_DIR.iterdir() if p.is_dir())
    expected = {"dungeon", "houseexpo", "stage", *STANDALONE}
    assert [p.name for p in folders] == sorted(expected)
    for folder in folders:
        licences = [p for p in folder.iterdir() if p.name.startswith(("LICENSE", "COPYING"))]
        assert licences and all(p.stat().st_size > 100 for p in licences), folder.name
        source = (folder / "SOURCE.md").read_text()
        assert "https://github.com/" in source and "Licence" in source, folder.name
    for entry in catalogue().maps:  # every map lies in one of them
        assert entry.path.relative_to(MAPS_DIR).parts[0] in {p.name for p in folders}


def test_world_arguments_take_catalogue_names_after_generators_and_paths(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    assert world_path("office") is None
    assert world_path("nav2_depot") == MAPS_DIR / "nav2_depot" / "depot.yaml"
    assert world_path("dungeon/easy") == MAPS_DIR / "dungeon" / "easy"
    assert map_file("dungeon/easy/img_10") == MAPS_DIR / "dungeon" / "easy" / "img_10.png"
    with pytest.raises(ConfigError, match="collection of maps; `frontier-rl maps dungeon/easy` lists them"):
        resolve_world("dungeon/easy", 0)
    # an existing path wins over the catalogue name it spells: here a folder nav2_depot/ holding lse_arena
    monkeypatch.chdir(tmp_path)
    shutil.copytree(MAPS_DIR / "lse_arena", tmp_path / "nav2_depot")
    assert parse_world_list("nav2_depot") == (str(Path("nav2_depot", "lse_arena.yaml")),)
    with pytest.raises(MapError, match=r"^nav2_depot is a folder, not a map file: name one of the maps in it$"):
        resolve_world("nav2_depot", 0)
    assert resolve_world("nav2_depot/lse_arena.yaml", 0).grid.shape == (60, 80)
    assert resolve_world("nav2_depot", 0, base_dir=MAPS_DIR / "dungeon").grid.shape == (307, 604)  # no such path
    assert resolve_world("lse_arena", 0, base_dir=tmp_path).name == "lse_arena"


@pytest.mark.parametrize("spec", ["atlantis", "dungeon/easy/img_0", "dungeon/hard"])
def test_an_unknown_world_is_one_line_naming_the_generators_and_the_catalogue(spec: str) -> None:
    for call in (lambda: resolve_world(spec, 0), lambda: parse_world_list(spec)):
        with pytest.raises(UnknownNameError) as caught:
            call()
        message = str(caught.value)
        assert "\n" not in message and repr(spec) in message and "`frontier-rl maps` lists them" in message
        assert all(name in message for name in WORLD_GENERATORS)


def test_a_collection_stands_where_a_folder_does() -> None:
    names = parse_world_list("office,dungeon/easy")
    folder = parse_world_list(str(MAPS_DIR / "dungeon" / "easy"))
    assert names[0] == "office" and len(names) == 101
    assert [Path(p).name for p in folder] == [Path(map_file(n)).name for n in names[1:]]  # the folder's order
    family = parse_world_mix("dungeon/train=3")[0]
    assert (family.spec, family.weight, len(family.members)) == ("dungeon/train", 3.0, 500)
    by_folder = parse_world_mix(str(MAPS_DIR / "dungeon" / "train"))[0]
    for part in ("train", "validation"):  # the same files held out as the folder's
        assert [map_file(n).name for n in family.split(part)] == [Path(p).name for p in by_folder.split(part)]


def test_evaluate_and_train_take_a_collection(tmp_path: Path) -> None:
    worlds = parse_world_list("dungeon/easy")
    config = ExperimentConfig(methods=("nearest", "fixed:0.75"), worlds=worlds, episodes=1, baseline="nearest")
    job = config.jobs()[0]
    assert job.world == "dungeon/easy/img_1"  # results name the map as given, wherever the package is
    settings = EpisodeSettings(config.sim, None, False, str(tmp_path))  # a results folder elsewhere
    world, _, _ = job_parts(job, settings)
    assert world.name == "dungeon/easy/img_1" and world.grid.shape == (480, 640)
    assert world_fingerprint(job.world, None).startswith("dungeon/easy/img_1#sha256:")
    assert world_fingerprint(job.world, None) == world_fingerprint(job.world, None)
    assert TrainConfig(worlds="office,dungeon/easy=2").worlds == "office,dungeon/easy=2"
    checked = check_world_files(("houseexpo", "stage/cave"))
    assert [name.split("#")[0] for name in checked] == [*parse_world_list("houseexpo"), "stage/cave"]
    source = WorldSource(("dungeon/easy",))
    assert source.sample(np.random.default_rng(0)).name.startswith("dungeon/easy/img_")


def test_a_map_that_is_not_installed_says_where_to_get_it(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """As a wheel install sees Stage's bitmaps: the YAML is there, the image is not."""
    (tmp_path / "stage").mkdir()
    shutil.copy(MAPS_DIR / "stage" / "cave.yaml", tmp_path / "stage" / "cave.yaml")
    text = (MAPS_DIR / "catalogue.yaml").read_text()
    maps = load_catalogue(MAPS_DIR / "catalogue.yaml", tmp_path)
    cave = maps.get("stage/cave")
    assert isinstance(cave, CatalogueMap) and not cave.installed and cave.size() is None
    assert maps.get("nav2_depot").installed is False
    stage = maps.get("stage")
    assert isinstance(stage, MapCollection) and stage.members == ("stage/cave",)
    assert (stage.installed, stage.installed_count, stage.size(), stage.in_wheel) == (False, 0, None, False)
    assert "'stage' has 0 of its 1 maps installed (its licence keeps its maps out of the wheel" in stage.not_installed()
    easy = maps.get("dungeon/easy")
    assert isinstance(easy, MapCollection) and easy.maps == () and not easy.installed  # no folder: no maps
    assert "dungeon/easy/img_1" not in {m.name for m in maps.maps}  # its folder is missing here
    monkeypatch.setattr(world_spec, "catalogue", lambda: maps)
    with pytest.raises(MapError, match=r"'stage/cave' is not installed .*GPL-2.0.*github.com/rtv/Stage"):
        resolve_world("stage/cave", 0)
    assert text == (MAPS_DIR / "catalogue.yaml").read_text()


@pytest.mark.parametrize(
    ("edit", "needle"),
    [
        (("    family: ros\n", "    family: rosy\n", 1), "unknown family 'rosy'"),
        (("    licence: BSD\n", "", 1), "'lse_arena': field 'licence' must be a non-empty string"),
        (("    wheel: false\n", "    wheel: 'no'\n", 1), "field 'wheel' must be true or false"),
        (("    uniform_size: true\n", "    uniform_size: true\n    colour: red\n", 1), "unknown field(s) colour"),
        (("  lse_arena:\n", "  office:\n", 1), "names 'office' twice (or as a world generator)"),
        (("file: stage/cave.yaml", "file: stage/mbicp.yaml", 1), "'stage/cave' is not its file cave.yaml"),
        (("\ncollections:\n", "\nextra: 1\ncollections:\n", 1), "a mapping of 'maps' and 'collections'"),
    ],
)
def test_a_malformed_catalogue_is_refused_naming_the_problem(
    tmp_path: Path, edit: tuple[str, str, int], needle: str
) -> None:
    old, new, count = edit
    text = (MAPS_DIR / "catalogue.yaml").read_text()
    assert old in text
    path = tmp_path / "catalogue.yaml"
    path.write_text(text.replace(old, new, count))
    with pytest.raises(MapError) as caught:
        load_catalogue(path, MAPS_DIR)
    assert needle in str(caught.value) and "\n" not in str(caught.value)
