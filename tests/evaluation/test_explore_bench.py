"""Explore-Bench's metrics: the exploration rate over the blueprint's known area, T_90, T_total at
0.99, the path until then, and for teams the robots' own rates' std and overlap."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from frontier_rl.cli import app
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.errors import ConfigError
from frontier_rl.evaluation.protocols.explore_bench import (
    blueprint_known_cells,
    explore_bench_maps,
    explore_bench_rows,
    run_explore_bench,
    run_explore_bench_all,
)
from frontier_rl.io import save_ros_map
from frontier_rl.policies import make_policy
from frontier_rl.swarm import TeamConfig, run_team_episode
from frontier_rl.world_spec import read_map, resolve_world


def _blueprint(folder: Path, name: str, hidden: bool) -> Path:
    """A 6 m x 4 m room (0.05 m cells) walled by one cell, as a SLAM map draws it, with a small
    pillar; with ``hidden``, two 7 m x 0.4 m strips of the outside beyond the walls are known free
    in the blueprint, which no robot can ever see (a fifth of its known area)."""
    data = np.full((100, 140), CellState.UNKNOWN, np.int8)
    data[10:90, 10:130] = CellState.OCCUPIED
    data[11:89, 11:129] = CellState.FREE
    data[50:52, 60:62] = CellState.OCCUPIED
    if hidden:
        data[0:8, :] = data[92:100, :] = CellState.FREE
    folder.mkdir(exist_ok=True)
    return save_ros_map(OccupancyGrid(data, 0.05), folder / f"{name}.yaml")


def test_the_known_area_counts_the_pixels_that_are_not_unknown_grey(tmp_path: Path) -> None:
    data = np.array([[CellState.UNKNOWN, CellState.FREE], [CellState.OCCUPIED, CellState.FREE]], np.int8)
    blueprint = save_ros_map(OccupancyGrid(data, 0.05), tmp_path / "four.yaml")
    assert blueprint_known_cells(blueprint, 0.05) == 3
    assert blueprint_known_cells(blueprint, 0.1) == pytest.approx(0.75)  # in the world's coarser cells
    # a YAML whose free_thresh loads a few grey spots as free (nav2_depot's 0.25, 5 % of its free
    # cells): still unknown to Explore-Bench
    spotted = np.full((4, 6), CellState.FREE, np.int8)
    spotted[0, 0], spotted[3, 5] = CellState.UNKNOWN, CellState.OCCUPIED
    blueprint = save_ros_map(OccupancyGrid(spotted, 0.05), tmp_path / "spotted.yaml")
    yaml = blueprint.read_text().replace("free_thresh: 0.196", "free_thresh: 0.25")
    assert "0.25" in yaml
    blueprint.write_text(yaml)
    assert (read_map(str(blueprint)).grid.data != CellState.UNKNOWN).sum() == 24  # 1 grey of 23 free: quiet
    assert blueprint_known_cells(blueprint, 0.05) == 23


@pytest.mark.parametrize("robots", [1, 2])
def test_a_room_ends_at_the_rate_and_the_episode_is_the_plain_one(tmp_path: Path, robots: int) -> None:
    room = _blueprint(tmp_path, "room", hidden=False)
    run = run_explore_bench("nearest", room, 3, robots)
    assert run.t90_s is not None and run.t_total_s is not None and run.t90_s <= run.t_total_s <= run.sim_time_s
    assert run.final_rate >= 0.99 and run.explored and run.map_name == f"{tmp_path.name}/room.yaml"
    plain = run_team_episode(
        resolve_world(str(room), 3), make_policy("nearest"), team=TeamConfig(robots=robots), seed=3
    )
    assert plain.sim_time_s == run.sim_time_s  # recording the rate changes nothing
    assert 0 < run.path_m <= plain.path_length_m + 1e-9
    if robots == 1:
        assert run.coverage_std is None and run.overlap_rate is None
    else:
        assert run.coverage_std is not None and run.overlap_rate is not None
        assert 0 <= run.coverage_std <= 0.6 and -0.02 <= run.overlap_rate <= 1.0


def test_a_blueprint_that_knows_what_no_robot_can_see_has_no_t_total(tmp_path: Path) -> None:
    room = _blueprint(tmp_path, "room", hidden=True)
    run = run_explore_bench("nearest", room, 3, 1)
    assert run.t_total_s is None and run.final_rate < 0.99 and run.explored
    plain = run_team_episode(resolve_world(str(room), 3), make_policy("nearest"), team=TeamConfig(robots=1), seed=3)
    assert run.path_m == plain.path_length_m  # without T_total: the whole episode's path
    rows = explore_bench_rows([run])
    assert rows[0].ended == 0 and np.isnan(rows[0].t_total_s)


def test_only_ros_maps_are_blueprints(tmp_path: Path, real_maps: Path) -> None:
    assert explore_bench_maps(str(real_maps / "turtlebot3_world")) == [real_maps / "turtlebot3_world" / "map.yaml"]
    for bad in ("office", str(real_maps / "dungeon" / "easy" / "img_1.png")):
        with pytest.raises(ConfigError, match="ROS map"):
            explore_bench_maps(bad)


def test_the_command_prints_the_table_and_writes_every_run(tmp_path: Path) -> None:
    room = _blueprint(tmp_path, "room", hidden=False)
    out = tmp_path / "eb.json"
    result = CliRunner().invoke(app, ["benchmark", "explore-bench", "--maps", str(room), "--seeds", "1", "--robots",
                                      "1,2", "--workers", "1", "--json", str(out)])  # fmt: skip
    assert result.exit_code == 0, result.output
    payload = json.loads(out.read_text(), parse_constant=lambda name: pytest.fail(f"{name} is not JSON"))
    assert [r["robots"] for r in payload["runs"]] == [1, 2] and payload["failures"] == []
    assert payload["summary"][0]["coverage_std"] is None  # one robot: no team figures (NaN was written)
    assert [row["ended"] for row in payload["summary"]] == [1, 1]
    twice = ["--robots", "1,1", "--methods", "nearest,nearest"]
    once = CliRunner().invoke(app, ["benchmark", "explore-bench", "--maps", str(room), "--seeds", "1", *twice,
                                    "--workers", "1", "--json", str(out)])  # fmt: skip
    assert once.exit_code == 0 and len(json.loads(out.read_text())["runs"]) == 1, once.output  # each given once
    (tmp_path / "a_file").write_text("x")
    bad_options: list[tuple[list[str], str]] = [
        (["--robots", "0"], "team sizes"),
        (["--seeds", "0"], "--seeds"),
        (["--maps", "office"], "ROS"),
        (["--json", str(tmp_path / "a_file" / "eb.json")], "is a file, not a folder"),  # refused before the runs
    ]
    for args, needle in bad_options:
        bad = CliRunner().invoke(app, ["benchmark", "explore-bench", "--maps", str(room), *args])
        assert bad.exit_code != 0 and needle in bad.output and "Traceback" not in bad.output


def test_the_oracle_runs_alone_but_not_in_a_team(tmp_path: Path) -> None:
    room = _blueprint(tmp_path, "room", hidden=False)
    assert run_explore_bench("oracle", room, 0, 1).t_total_s is not None
    with pytest.raises(ConfigError, match="cannot run in a team"):
        run_explore_bench("oracle", room, 0, 2)
    # the whole protocol refuses it before any run (it ran every run, then counted the teams' failed)
    with pytest.raises(ConfigError, match="cannot run in a team"):
        run_explore_bench_all(["nearest", "oracle"], [room], 1, [1, 2], workers=1)
