"""The command line: JSON output, pictures, and one-line errors with exit code 2 for bad input."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from frontier_rl.cli import app
from frontier_rl.cli.output import print_line, print_table
from frontier_rl.errors import ConfigError
from frontier_rl.evaluation.running.experiment import ExperimentConfig
from frontier_rl.run_folders import RunKind, run_kind
from tests.evaluation.maps import write_slit_map

runner = CliRunner()


def test_explore_json_has_the_documented_fields(tmp_path: Path) -> None:
    result = runner.invoke(app, ["explore", "--world", "lse_arena", "--policy", "nearest", "--json"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout.strip().splitlines()[-1])
    for key in ("sim_time_s", "path_length_m", "coverage", "t90_s", "t99_s", "decisions", "aborts", "done",
                "wall_time_s", "end_reason", "free_coverage", "unknown_left_m2", "frontiers_left"):  # fmt: skip
        assert key in data
    assert data["done"] is True
    assert data["end_reason"] == "explored" and isinstance(data["frontiers_left"], list)
    assert sum(f["unknown_m2"] for f in data["frontiers_left"]) == pytest.approx(data["unknown_left_m2"], abs=1e-3)
    assert data["coverage"] >= 0.99
    assert 0 < data["t90_s"] <= data["t99_s"] <= data["sim_time_s"]


def test_explore_writes_png_and_gif(tmp_path: Path, real_maps: Path) -> None:
    png, gif = tmp_path / "run.png", tmp_path / "run.gif"
    world = real_maps / "lse_arena" / "lse_arena.yaml"
    result = runner.invoke(app, ["explore", "--world", str(world), "--png", str(png), "--gif", str(gif)])
    assert result.exit_code == 0, result.output
    from PIL import Image

    with Image.open(png) as image:
        assert image.width > 2 * 80 and image.height > 60  # two panels of the 80 x 60 map
    with Image.open(gif) as image:
        assert image.n_frames >= 2


def test_a_team_explore_writes_its_picture_and_refuses_an_animation(tmp_path: Path) -> None:
    png = tmp_path / "team.png"
    result = runner.invoke(app, ["explore", "--world", "lse_arena", "--robots", "2", "--png", str(png)])
    assert result.exit_code == 0, result.output
    from PIL import Image

    with Image.open(png) as image:
        assert image.format == "PNG" and image.width > 1.5 * image.height  # true map | merged map
    refused = runner.invoke(app, ["explore", "--world", "lse_arena", "--robots", "2", "--gif", str(tmp_path / "a.gif")])
    assert refused.exit_code == 2 and "--gif" in refused.output and not (tmp_path / "a.gif").exists()


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["--world", "atlantis"], "atlantis"),
        (["--policy", "fixed:1.5"], "1.5"),
        (["--policy", "fixed:-0.1"], "-0.1"),
        (["--policy", "bogus"], "bogus"),
        (["--start", "1,abc"], "1,abc"),
        (["--max-time", "-3"], "-3"),
        (["--max-time", "inf"], "--max-time must be a positive number of seconds, got inf"),
        (["--png", "/dev/null/such/folder/x.png"], "'/dev/null' is a file, not a folder"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(args: list[str], needle: str) -> None:
    result = runner.invoke(app, ["explore", *args])
    assert result.exit_code == 2
    assert "Traceback" not in result.output
    lines = [line for line in result.output.splitlines() if line.strip()]
    assert len(lines) == 1 and needle in lines[0], result.output


@pytest.mark.parametrize(
    ("yaml_text", "needle"),
    [
        ("resolution: 0\nimage: map.pgm\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.2\n", "0"),
        ("image: map.pgm\n", "resolution"),
        ("- not a mapping\n", "mapping"),
    ],
)
def test_bad_map_file_is_one_line_and_exit_2(tmp_path: Path, yaml_text: str, needle: str) -> None:
    path = tmp_path / "map.yaml"
    path.write_text(yaml_text)
    result = runner.invoke(app, ["explore", "--world", str(path)])
    assert result.exit_code == 2
    lines = [line for line in result.output.splitlines() if line.strip()]
    assert len(lines) == 1 and needle in lines[0], result.output


def test_start_inside_a_wall_is_rejected(real_maps: Path) -> None:
    world = real_maps / "lse_arena" / "lse_arena.yaml"
    result = runner.invoke(app, ["explore", "--world", str(world), "--start", "0,0"])
    assert result.exit_code == 2
    assert "(0.00, 0.00)" in result.output


def test_bad_config_key_is_rejected(tmp_path: Path) -> None:
    config = tmp_path / "sim.yaml"
    config.write_text("lidar:\n  num_beams: 0\n")
    result = runner.invoke(app, ["explore", "--config", str(config)])
    assert result.exit_code == 2
    assert "num_beams" in result.output


def test_max_time_truncates(real_maps: Path) -> None:
    world = real_maps / "lse_arena" / "lse_arena.yaml"
    result = runner.invoke(app, ["explore", "--world", str(world), "--max-time", "4", "--json"])
    data = json.loads(result.stdout.strip().splitlines()[-1])
    assert data["truncated"] is True and data["done"] is False and data["end_reason"] == "time_cap"
    assert data["sim_time_s"] == pytest.approx(4.0)


def test_explore_lists_the_frontiers_left(tmp_path: Path) -> None:
    world = str(write_slit_map(tmp_path))  # a slit too narrow for the robot: the room behind it stays unexplored
    result = runner.invoke(app, ["explore", "--world", world, "--start", "1,1", "--policy", "nearest", "--json"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout.strip().splitlines()[-1])
    assert data["end_reason"] == "unreachable" and data["truncated"] is False and data["done"] is False
    left = data["frontiers_left"]
    keys = {"x", "y", "cells", "unknown_cells", "unseen_free_cells", "unknown_m2", "failures", "unseen_behind_m2",
            "has_path", "path_on_map", "unrevealable", "leaves_space",
            "explorable_behind_m2"}  # fmt: skip
    assert left and all(set(f) == keys for f in left)
    assert data["frontiers_with_path_left"] == sum(f["has_path"] and not f["unrevealable"] for f in left)
    assert data["frontiers_unrevealable_left"] == sum(f["unrevealable"] for f in left)
    to_space = sum(f["has_path"] and f["leaves_space"] and not f["unrevealable"] for f in left)
    assert data["frontiers_with_path_to_space_left"] == to_space <= data["frontiers_with_path_left"]
    assert 0.0 <= data["explorable_given_up_m2"] <= data["explorable_left_m2"] + 1e-3
    on_map = sum(f["path_on_map"] and not f["unrevealable"] for f in left)
    assert data["frontiers_with_path_on_map_left"] == on_map <= data["frontiers_with_path_left"]
    assert all(f["has_path"] for f in left if f["path_on_map"])
    assert max(f["unseen_behind_m2"] for f in left) > 0.5  # what it could not see of the room behind the slit
    assert all(f["x"] > 2.0 and f["cells"] > 0 for f in left)  # beyond the wall at x = 2 m
    shares = [f["unknown_m2"] for f in left]  # segments beside the slit share unseen cells, counted once in the sum
    assert max(shares) - 1e-3 <= data["unknown_left_m2"] <= sum(shares) + 1e-3
    assert 0 < data["free_coverage"] < data["coverage"]
    table = runner.invoke(app, ["explore", "--world", world, "--start", "1,1", "--policy", "nearest"])
    assert table.exit_code == 0, table.output
    rows = _table_rows(table.stdout)
    assert rows["end_reason"] == data["end_reason"] and rows["frontiers_left"] == str(len(left))
    causes = ", ".join(f"{cause} {n}" for cause, n in data["aborts_by_cause"].items() if n) or "none"
    assert rows["aborts_by_cause"] == causes  # each cause given up for, not a dict's repr


def _table_rows(stdout: str) -> dict[str, str]:
    """``explore``'s table: each metric's value, as shown."""
    return {line.split()[1]: " ".join(line.split()[3:-1]) for line in stdout.splitlines() if line.count("│") == 3}


def test_train_then_explore_with_the_learned_policy(tmp_path: Path) -> None:
    run = tmp_path / "run"
    args = ["train", "--out", str(run), "--model", "4", "--timesteps", "16", "--n-envs", "1", "--n-steps", "8",
            "--eval-every", "0", "--checkpoint-every", "8", "--no-progress"]  # fmt: skip
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    assert (run / "model.zip").exists() and (run / "learning_curve.png").exists()
    again = runner.invoke(app, args)
    assert again.exit_code == 2 and "--resume" in again.output
    model = str(run / "model.zip")
    result = runner.invoke(app, ["explore", "--policy", f"learned:{model}", "--max-time", "60", "--json"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout.strip().splitlines()[-1])
    assert data["policy"] == f"learned:{model}"
    assert len(data["weights"]) == data["decisions"] and all(0 <= w < 1 for w in data["weights"])


@pytest.mark.parametrize(
    ("args", "needle"),
    [(["--model", "9"], "unknown model 9"), (["--algo", "sac"], "sac"), (["--worlds", "moon"], "moon"),
     (["--observation-size", "100"], "100"), (["--timesteps", "0"], "timesteps"), (["--resume"], "nothing to resume"),
     (["--config", "no-such-sim.yaml"], "no-such-sim.yaml")],
)  # fmt: skip
def test_bad_training_input_is_one_line_and_exit_2(tmp_path: Path, args: list[str], needle: str) -> None:
    result = runner.invoke(app, ["train", "--out", str(tmp_path / "run"), "--no-progress", *args])
    assert result.exit_code == 2
    assert needle in result.output and "Traceback" not in result.output
    assert len(result.output.strip().splitlines()) == 1


@pytest.mark.parametrize(
    ("spec", "needle"),
    [("learned:missing.zip", "not found"), ("learned:README.md", "not a frontier_rl model"), ("learned:", "needs")],
)
def test_bad_learned_policy_is_one_line_and_exit_2(spec: str, needle: str) -> None:
    result = runner.invoke(app, ["explore", "--policy", spec])
    assert result.exit_code == 2
    assert needle in result.output and "Traceback" not in result.output


def test_demo_runs_the_compact_experiment_and_draws_every_method(tmp_path: Path) -> None:
    out = tmp_path / "demo"
    result = runner.invoke(app, ["demo", "--out", str(out), "--episodes", "1", "--max-time", "60", "--no-progress"])
    assert result.exit_code == 0, result.output
    summary = json.loads((out / "experiment" / "summary.json").read_text())
    methods = set(summary["methods"])
    assert {"fixed:0.75", "nearest", "oracle", "learned:models/model7.zip"} <= methods
    assert "not found" not in result.stderr  # run in the checkout: every shipped model is there
    assert summary["worlds"] == ["office", "rooms", "cluttered"] and summary["episodes"] == 1
    assert "| fixed:0.75 (baseline) | 3 |" in (out / "experiment" / "report.md").read_text()
    assert "**Completion**" in (out / "experiment" / "report.md").read_text()
    capped = summary["methods"]["nearest"]["end_reasons"]["time_cap"]
    assert capped >= 1  # 60 s is too short for these worlds
    assert f"nearest {capped} time_cap" in " ".join(result.output.split())  # the terminal summary names them
    assert (out / "experiment" / "boxplot.png").stat().st_size > 0
    pictures = out / "experiment" / "pictures"
    assert len(list(pictures.glob("*.png"))) == 3 * len(methods)
    assert (pictures / "office_fixed_0.75.gif").exists()
    page = (out / "experiment" / "report.html").read_text()
    charts = len(list((out / "experiment").glob("*.png")))  # box plot, scatter, coverage (and weights)
    assert charts >= 3 and page.count("data:image/png;base64,") == charts + 3 * len(methods)
    assert page.count("data:image/gif;base64,") == 1
    assert run_kind(out) is RunKind.DEMO  # what a second demo into the folder takes as its own to rewrite


def test_demo_outside_the_checkout_says_which_models_it_leaves_out(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import frontier_rl.evaluation.running.evaluate as evaluation

    ran: list[tuple[str, ...]] = []

    def stop(experiment: ExperimentConfig, *args: object, **kwargs: object) -> Path:
        ran.append(experiment.methods)
        raise ConfigError("stopped before the episodes")

    monkeypatch.setattr(evaluation, "evaluate", stop)
    monkeypatch.chdir(tmp_path)
    result = runner.invoke(app, ["demo", "--out", "demo", "--episodes", "1", "--no-progress"])
    assert result.exit_code == 2
    note, error = result.stderr.splitlines()
    assert note.startswith("note: models/model4.zip, models/model5.zip, models/model7.zip not found in ")
    assert "the demo runs without them" in note and error == "error: stopped before the episodes"
    assert ran == [("fixed:0.75", "nearest", "tour", "oracle")]


def test_explore_with_a_team_reports_every_robot(tmp_path: Path) -> None:
    png = tmp_path / "team.png"
    args = ["explore", "--seed", "1", "--robots", "3", "--strategy", "coordinated", "--fail", "2@60", "--json"]
    result = runner.invoke(app, [*args, "--png", str(png)])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout.strip().splitlines()[-1])
    assert data["robots"] == 3 and data["strategy"] == "coordinated" and 0 <= data["overlap"] <= 1
    assert len(data["robot_path_lengths_m"]) == 3 and data["failed_at_s"][2] >= 60 and data["done"]
    assert png.stat().st_size > 0
    table = runner.invoke(app, args[:-1])
    assert table.exit_code == 0, table.output
    rows = _table_rows(table.stdout)
    assert rows["failed_at_s"] == f"-, -, {data['failed_at_s'][2]}"  # a value per robot, not a tuple's repr
    assert rows["robot_path_lengths_m"] == ", ".join(str(length) for length in data["robot_path_lengths_m"])


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["--robots", "9"], "9"),
        (["--robots", "2", "--fail", "2@10"], "robot 2"),
        (["--robots", "2", "--fail", "1@-4"], "-4"),
        (["--robots", "2", "--fail", "soon"], "soon"),
        (["--robots", "2", "--comm-range", "-1"], "-1"),
        (["--strategy", "swarming"], "swarming"),
        (["--robots", "2", "--gif", "x.gif"], "--gif"),
        (["--robots", "2.5"], "'2.5'"),  # typer's own message: the value named, by typer or by us
        (["--robots=abc"], "'abc'"),
    ],
)
def test_bad_team_input_is_one_line_and_exit_2(args: list[str], needle: str) -> None:
    result = runner.invoke(app, ["explore", *args])
    assert result.exit_code == 2
    lines = [line for line in result.output.splitlines() if line.strip()]
    assert len(lines) == 1 and needle in lines[0], result.output


def test_team_options_given_to_one_robot_are_named_in_a_warning() -> None:
    base = ["explore", "--world", "lse_arena", "--max-time", "3", "--json"]
    for extra, line in (
        (["--comm-range", "3"], "warning: --comm-range acts between robots: with one robot it is ignored"),
        (["--strategy", "coordinated", "--comm-range", "3"], "warning: --strategy and --comm-range act between"),
    ):
        result = runner.invoke(app, [*base, *extra])
        assert result.exit_code == 0, result.output
        (warning,) = result.stderr.splitlines()
        assert warning.startswith(line) and warning.endswith("(--robots N)")
        alone = json.loads(result.stdout)
        assert alone["world"] == "lse_arena" and "strategy" not in alone  # a single robot's episode
    quiet = runner.invoke(app, [*base, "--robots", "2", "--comm-range", "3"])
    assert quiet.exit_code == 0 and quiet.stderr == ""


def test_the_terminal_summary_gives_the_time_against_the_baseline_and_holms_p_of_the_methods_tested(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    from frontier_rl.cli.experiments import _print_summary
    from frontier_rl.evaluation.results.summary import ExperimentSummary

    monkeypatch.setenv("COLUMNS", "200")

    def entry(mean: float, reduction: float, p: float, holm: float | None) -> dict[str, object]:
        return {"n": 4, "mean_time_s": mean, "reduction_pct": reduction, "p_one_tailed": p, "p_holm": holm,
                "episodes_done": 4, "end_reasons": {"explored": 4}}  # fmt: skip

    methods = {
        "fixed:0.75": entry(400.0, 0.0, 0.5, None),
        "tour": entry(301.2, 24.7, 0.0021, 0.0042),
        "oracle": entry(250.0, 37.5, 0.0001, None),
    }
    head = {"baseline": "fixed:0.75", "reference": "oracle", "worlds": ["office"], "episodes": 4, "seed": 0}
    summary = ExperimentSummary.from_json(head | {"outliers": {}, "methods": methods})
    _print_summary(summary, "run", "fixed:0.75")
    lines = capsys.readouterr().out.splitlines()
    assert any("time vs baseline" in line and "p Holm" in line for line in lines)
    rows = {cells[0]: cells[1:] for line in lines if len(cells := line.replace("│", " ").split()) > 3}
    assert rows["tour"][:4] == ["301.2", "-24.7", "%", "0.0042"]  # 24.7 % less time than the baseline
    assert rows["oracle"][:3] == ["250.0", "-37.5", "%"] and "0.0001" not in rows["oracle"]  # the reference: no p
    assert rows["fixed:0.75"][:2] == ["400.0", "baseline"]


def test_the_program_says_its_version_and_takes_h_for_help() -> None:
    from frontier_rl import __version__

    runner = CliRunner()
    version = runner.invoke(app, ["--version"])
    assert version.exit_code == 0 and version.output == f"frontier-rl {__version__}\n"
    for args in (["-h"], ["explore", "-h"], ["benchmark", "ariadne", "-h"]):
        shown = runner.invoke(app, args)
        assert shown.exit_code == 0 and shown.output.startswith("Usage: "), (args, shown.output)


def test_a_result_line_is_one_line_in_a_pipe(capsys: pytest.CaptureFixture[str]) -> None:
    """A ROS 2 run's summary and a report's path were wrapped at 80 columns, a space left at the break."""
    line = "explored after 385.6 s, 142 goals (1 given up), 100.0 % of the explorable space (the simulator's)"
    print_line(line)
    assert capsys.readouterr().out == line + "\n"


def test_a_table_is_whole_in_a_pipe(capsys: pytest.CaptureFixture[str]) -> None:
    """A long method name was cut to fit 80 columns ("sub/folder/my_poli…") where no terminal gave a width."""
    from rich.table import Table

    method = "policies/of/a/study/my_policy_with_a_long_name.py:NearestCellWithALongName@3:coordinated"
    table = Table(title="methods")
    for column in ("method", "mean time (s)", "time vs baseline", "p Holm", "time / oracle", "done"):
        table.add_column(column, no_wrap=column == "method")
    table.add_row(method, "1,234.5", "+12.3 %", "0.0012", "1.23", "30/30")
    print_table(table)
    out = capsys.readouterr().out
    assert method in out and "30/30" in out and "…" not in out


def test_the_summary_table_has_no_oracle_column_without_the_oracle(tmp_path: Path) -> None:
    """With --no-oracle the column was printed empty."""
    args = ["evaluate", "--methods", "nearest", "--worlds", "office", "--episodes", "1", "--no-oracle",
            "--backend", "serial", "--pictures", "0", "--no-progress", "--out", str(tmp_path / "run")]  # fmt: skip
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, result.output
    assert "p Holm" in result.stdout and "time / oracle" not in result.stdout
