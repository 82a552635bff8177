"""``frontier-rl maps`` and catalogue names on the command line: the listing, a collection's
members, JSON, and worlds given by catalogue name to explore and evaluate."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from frontier_rl.cli import WORLD_HELP, app
from frontier_rl.io.catalogue import MAPS_DIR

runner = CliRunner()


def _invoke(*args: str) -> str:
    result = runner.invoke(app, list(args), env={"COLUMNS": "200"})
    assert result.exit_code == 0, result.output
    return result.stdout


def test_maps_lists_each_map_and_each_collection_once() -> None:
    lines = _invoke("maps").splitlines()
    row = {line.split()[0]: line for line in lines if line.strip() and not line.lstrip().startswith(("name", "─"))}
    for name in ("turtlebot3_world", "aws_small_house", "nav2_depot", "nav2_warehouse", "lse_arena"):
        assert name in row
    assert "604 × 307" in row["nav2_depot"] and "30.2 × 15.3" in row["nav2_depot"]
    assert "0.03" in row["nav2_warehouse"] and "Apache-2.0" in row["nav2_warehouse"]
    assert "ros-navigation/navigation2" in row["nav2_depot"]
    assert (
        "(100 maps)" in row["dungeon/easy"] and "640 × 480" in row["dungeon/easy"] and "0.04375" in row["dungeon/easy"]
    )
    assert "(5 maps)" in row["stage"] and "GPL-2.0-or-later" in row["stage"] and "varies" in row["stage"]
    assert "(500 maps)" in row["dungeon/train"] and "(2 maps)" in row["houseexpo"]
    assert not any(name.startswith(("dungeon/easy/", "stage/")) for name in row)  # collections are one row each
    assert "installed" not in " ".join(lines)  # every map is here, so the column is left out


def test_maps_of_a_collection_lists_its_members() -> None:
    out = _invoke("maps", "dungeon/easy")
    members = [line.split()[0] for line in out.splitlines() if line.strip().startswith("dungeon/easy/")]
    assert len(members) == 100 and "dungeon/easy/img_10" in members
    stage = _invoke("maps", "stage")
    assert "stage/autolab" in stage and "809 × 689" in stage and "0.025" in stage


def test_maps_json_gives_every_field() -> None:
    records = json.loads(_invoke("maps", "--json"))
    by_name = {r["name"]: r for r in records}
    depot = by_name["nav2_depot"]
    expected = {"kind": "map", "family": "ros", "width_cells": 604, "height_cells": 307, "width_m": 30.2}
    expected |= {"height_m": 15.35, "resolution_m": 0.05, "licence": "Apache-2.0", "installed": "yes"}
    assert depot == depot | expected
    assert depot["source"] == "https://github.com/ros-navigation/navigation2/tree/main/nav2_bringup/maps"
    assert by_name["dungeon/complex"]["count"] == 100 and by_name["dungeon/complex"]["kind"] == "collection"
    assert by_name["stage"]["width_cells"] is None  # its members differ in size
    members = json.loads(_invoke("maps", "houseexpo", "--json"))
    assert [m["name"] for m in members] == [
        "houseexpo/0a1b29dba355df2ab02630133187bfab",
        "houseexpo/house_expo_room_0000",
    ]
    assert all(m["resolution_m"] == 0.05 and m["width_cells"] > 100 for m in members)
    assert json.loads(_invoke("maps", "lse_arena", "--json"))[0]["width_cells"] == 80


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
