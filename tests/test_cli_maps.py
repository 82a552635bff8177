"""``frontier-rl maps`` and catalogue names on the command line: the listing at 80 and 200
columns, a collection's members, one map's fields, JSON, maps that are not installed, and worlds
given by catalogue name to explore and evaluate."""

from __future__ import annotations

import csv
import json
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

from frontier_rl.cli import WORLD_HELP, app
from frontier_rl.io.catalogue import MAPS_DIR, load_catalogue
from tests.io.catalogue_names import STANDALONE

runner = CliRunner()
WIDTHS = (80, 200)
"""The terminal widths the listing is read at: the default of a terminal, and a wide one."""


def _invoke(*args: str, width: int = 200) -> str:
    result = runner.invoke(app, list(args), env={"COLUMNS": str(width)})
    assert result.exit_code == 0, result.output
    return result.stdout


def _rows(out: str) -> dict[str, str]:
    """The table's rows by their first word (the name): the lines from under the header row to the
    first blank one."""
    lines = out.splitlines()
    first = next(k for k, line in enumerate(lines) if line.startswith("name ")) + 2
    last = next((k for k in range(first, len(lines)) if not lines[k].strip()), len(lines))
    return {line.split()[0]: line for line in lines[first:last]}


@pytest.mark.parametrize("width", WIDTHS)
def test_maps_lists_each_map_and_each_collection_once_on_one_line(width: int) -> None:
    out = _invoke("maps", width=width)
    assert all(len(line) <= width for line in out.splitlines())
    header = next(line.split() for line in out.splitlines() if line.startswith("name "))
    row = _rows(out)
    assert list(row) == [
        *STANDALONE,
        "stage",
        "houseexpo",
        "dungeon/train",
        "dungeon/easy",
        "dungeon/medium",
        "dungeon/complex",
    ]
    assert header[:3] == ["name", "maps", "family"] and "licence" in header  # a collection's count at 80 too
    cells = ["604", "×", "307"] if width == 200 else []  # the size in cells only where there is room
    assert row["nav2_depot"].split()[1:] == ["ros", *cells, "30.2", "×", "15.3", "0.05", "Apache-2.0"] + (
        ["ros-navigation/navigation2"] if width == 200 else []
    )
    assert row["nav2_warehouse"].split()[-2 if width == 200 else -1] == "Apache-2.0"
    dungeon = row["dungeon/easy"].split()
    assert dungeon[1] == "100" and "0.04375" in dungeon and ("640" in dungeon) == (width == 200)
    assert "stage" in row["stage"].split()[1:] and "GPL-2.0-or-later" in row["stage"] and "varies" in row["stage"]
    assert "installed" not in out  # every map is here, so the column is left out


def test_maps_of_a_collection_lists_its_members_under_what_they_share() -> None:
    for width in WIDTHS:
        out = _invoke("maps", "dungeon/easy", width=width)
        assert all(len(line) <= width for line in out.splitlines())
        members = [name for name in _rows(out) if name.startswith("dungeon/easy/")]
        assert len(members) == 100 and "dungeon/easy/img_10" in members
        heading = out[: out.index("\nname ")]
        assert "dungeon/easy (100 maps)" in heading and "licence    MIT" in heading
        assert "  source     https://github.com/marmotlab/ARiADNE/tree/main/DungeonMaps/easy\n" in heading
        assert "28.00 m × 21.00 m (640 × 480 cells of 0.04375 m)" in heading
    stage = _rows(_invoke("maps", "stage", width=80))
    assert stage["stage/autolab"].split()[1:] == ["809", "×", "689", "20.2", "×", "17.2", "0.025"]
    houseexpo = _invoke("maps", "houseexpo", width=80)  # long names: the columns still fit
    assert _rows(houseexpo)["houseexpo/0a1b29dba355df2ab02630133187bfab"].split()[-1] == "0.05"


def test_maps_of_one_map_gives_every_field_whole_at_80_columns() -> None:
    out = _invoke("maps", "aws_small_house", width=80)
    source = "https://github.com/aws-robotics/aws-robomaker-small-house-world/tree/ros1/maps/turtlebot3_waffle_pi"
    assert len(source) > 80 and f"  source     {source}\n" in out  # one line: it copies as one address
    assert "  family     ros\n" in out and "  licence    MIT-0\n" in out and "  installed  yes\n" in out
    assert f"  file       {MAPS_DIR / 'aws_small_house' / 'map.yaml'}\n" in out
    assert "25.00 m × 25.00 m (500 × 500 cells of 0.05 m)" in out and "furnished house" in out
    assert "licence    BSD\n" in _invoke("maps", "lse_arena", width=80)


def test_maps_json_gives_every_field() -> None:
    records = json.loads(_invoke("maps", "--json", width=80))
    by_name = {r["name"]: r for r in records}
    depot = by_name["nav2_depot"]
    assert depot == {
        "name": "nav2_depot",
        "kind": "map",
        "family": "ros",
        "description": "a depot with shelves (Nav2 sample map)",
        "width_cells": 604,
        "height_cells": 307,
        "width_m": 30.2,
        "height_m": 15.35,
        "resolution_m": 0.05,
        "licence": "Apache-2.0",
        "source": "https://github.com/ros-navigation/navigation2/tree/main/nav2_bringup/maps",
        "in_wheel": True,
        "installed": True,
        "count": None,
        "installed_count": None,
    }
    complex_ = by_name["dungeon/complex"]
    assert (complex_["kind"], complex_["count"], complex_["installed_count"], complex_["installed"]) == (
        "collection",
        100,
        100,
        True,
    )
    assert by_name["stage"]["width_cells"] is None and by_name["stage"]["in_wheel"] is False  # sizes differ
    members = json.loads(_invoke("maps", "houseexpo", "--json"))
    assert [m["name"] for m in members] == [
        "houseexpo/0a1b29dba355df2ab02630133187bfab",
        "houseexpo/house_expo_room_0000",
    ]
    assert all(m["resolution_m"] == 0.05 and m["width_cells"] > 100 for m in members)
    assert json.loads(_invoke("maps", "lse_arena", "--json"))[0]["width_cells"] == 80


def test_maps_not_installed_are_listed_with_where_to_get_them(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """As a wheel install sees Stage's bitmaps (their YAMLs are there, their images are not), with
    one Stage map's image present here."""
    (tmp_path / "stage").mkdir()
    for name in ("cave", "mbicp"):
        shutil.copy(MAPS_DIR / "stage" / f"{name}.yaml", tmp_path / "stage" / f"{name}.yaml")
    shutil.copy(MAPS_DIR / "stage" / "cave.png", tmp_path / "stage" / "cave.png")
    shutil.copytree(MAPS_DIR / "lse_arena", tmp_path / "lse_arena")
    maps = load_catalogue(MAPS_DIR / "catalogue.yaml", tmp_path)
    monkeypatch.setattr("frontier_rl.cli.map_listing.catalogue", lambda: maps)
    for width in WIDTHS:
        out = _invoke("maps", width=width)
        assert all(len(line) <= width for line in out.splitlines())
        row = _rows(out)
        assert row["lse_arena"].split()[-2 if width == 200 else -1] == "yes"
        assert " 1 of 2 " in row["stage"] and row["nav2_depot"].split()[-2 if width == 200 else -1] == "no"
        assert "catalogue collection 'stage' has 1 of its 2 maps installed" in " ".join(out.split())
    records = {r["name"]: r for r in json.loads(_invoke("maps", "--json"))}
    assert (records["stage"]["installed"], records["stage"]["installed_count"], records["stage"]["count"]) == (
        False,
        1,
        2,
    )
    assert records["nav2_depot"]["installed"] is False and records["nav2_depot"]["width_cells"] is None
    one = _invoke("maps", "stage/mbicp", width=80)
    assert "  installed  no\n" in one and "catalogue map 'stage/mbicp' is not installed" in " ".join(one.split())


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["maps", "dungeon/hard"], "no map 'dungeon/hard' in the catalogue; `frontier-rl maps` lists them"),
        (["explore", "--world", "dungeon/easy"], "is a collection of maps; `frontier-rl maps dungeon/easy` lists them"),
        (["explore", "--world", "nav3_depot"], "no catalogue map of that name (`frontier-rl maps` lists them)"),
    ],
)
def test_a_bad_map_name_is_one_line_and_exit_2(args: list[str], needle: str) -> None:
    result = runner.invoke(app, args)
    assert result.exit_code == 2 and "Traceback" not in result.output
    assert [line for line in result.output.splitlines() if line.strip()] == [f"error: {result.output.strip()[7:]}"]
    assert needle in result.output


def test_explore_and_evaluate_take_catalogue_names(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    assert "a catalogue map" in WORLD_HELP
    monkeypatch.chdir(tmp_path)  # away from the checkout: names, not paths
    data = json.loads(_invoke("explore", "--world", "lse_arena", "--policy", "nearest", "--json").splitlines()[-1])
    assert data["world"] == "lse_arena" and data["end_reason"] == "explored"
    out = tmp_path / "results"
    settings = ("--episodes", "1", "--no-oracle", "--workers", "1", "--out", str(out))
    _invoke("evaluate", "--methods", "nearest", "--worlds", "houseexpo,lse_arena", *settings)
    with (out / "episodes.csv").open() as handle:
        worlds = sorted({row["world"] for row in csv.DictReader(handle)})
    assert worlds == ["houseexpo/0a1b29dba355df2ab02630133187bfab", "houseexpo/house_expo_room_0000", "lse_arena"]
    assert not any(str(MAPS_DIR) in line for line in (out / "experiment.json").read_text().splitlines())


def test_the_benchmarks_default_to_catalogue_maps(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from frontier_rl.cli.protocols import DEFAULT_BLUEPRINTS, DEFAULT_DUNGEON_TESTS

    assert (DEFAULT_DUNGEON_TESTS, DEFAULT_BLUEPRINTS) == (
        "dungeon/complex",
        "turtlebot3_world,aws_small_house,nav2_depot",
    )
    monkeypatch.chdir(tmp_path)
    out = tmp_path / "ariadne.json"
    _invoke("benchmark", "ariadne", "--methods", "nearest", "--limit", "1", "--workers", "1", "--json", str(out))
    payload = json.loads(out.read_text())
    assert payload["maps"] == "dungeon/complex" and payload["runs"][0]["map_name"] == "img_99.png"
    settings = ("--seeds", "1", "--robots", "1", "--workers", "1", "--json", str(out))
    _invoke("benchmark", "explore-bench", "--maps", "lse_arena", *settings)
    assert json.loads(out.read_text())["summary"][0]["map"] == "lse_arena/lse_arena.yaml"
