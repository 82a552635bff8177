"""Hostile and careless command lines (issue 14): every bad value is one ``error:`` line on standard
error, exit code 2, before any episode runs; user text is never read as Rich markup; results are
printed before pictures are written; warnings are one line each."""

from __future__ import annotations

import json
import math
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from PIL import Image
from typer.testing import CliRunner

import frontier_rl.api as api
import frontier_rl.swarm.episode as team_episode
from frontier_rl.cli import MAX_SEED, app
from frontier_rl.cli.output import one_line, print_error
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import MAX_HEADING_RAD, Pose, checked_pose, parse_pose
from frontier_rl.core.world.scale import check_resolution, resolution_bounds
from frontier_rl.core.world.worlds import make_world
from frontier_rl.errors import ConfigError, MapError

runner = CliRunner()


def write_box(folder: Path, name: str = "box.png", length_m: float = 2.0) -> Path:
    """A plain bitmap: a room 2 m high and ``length_m`` wide (0.05 m cells) with a one-cell wall."""
    image = np.full((40, round(length_m / 0.05)), 255, dtype=np.uint8)
    image[0, :] = image[-1, :] = image[:, 0] = image[:, -1] = 0
    path = folder / name
    Image.fromarray(image).save(path)
    return path


@pytest.fixture
def box(tmp_path: Path) -> Path:
    return write_box(tmp_path)


@pytest.fixture
def no_episode(monkeypatch: pytest.MonkeyPatch) -> None:
    """Fail the test if an episode starts: bad input must be refused before."""

    def refuse(*args: Any, **kwargs: Any) -> Any:
        raise AssertionError("an episode ran before the bad input was refused")

    monkeypatch.setattr(api, "run_episode", refuse)  # the command runs its episode through the API
    monkeypatch.setattr(team_episode, "run_team_episode", refuse)  # which imports a team's when it runs one


def error_line(result: Any, needle: str) -> str:
    """The one line a refused command printed, checked: exit 2, nothing on stdout, no traceback."""
    assert result.exit_code == 2, (result.exit_code, result.output, result.exception)
    assert "Traceback" not in result.output
    assert result.stdout == ""
    lines = result.stderr.splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("error: ") and needle in lines[0], lines[0]
    return str(lines[0])


# ----------------------------------------------------------------------------------------- seeds
@pytest.mark.parametrize("seed", ["-1", "-7", str(-(2**70)), str(MAX_SEED + 1), str(10**30)])
@pytest.mark.parametrize("command", ["explore", "evaluate", "demo", "train"])
def test_out_of_range_seeds(tmp_path: Path, no_episode: None, command: str, seed: str) -> None:
    args = {"explore": [], "evaluate": ["--methods", "nearest", "--out", str(tmp_path / "r")],
            "demo": ["--out", str(tmp_path / "d")], "train": ["--out", str(tmp_path / "t")]}[command]  # fmt: skip
    error_line(runner.invoke(app, [command, *args, "--seed", seed]), seed)
    assert not (tmp_path / "r").exists() and not (tmp_path / "d").exists() and not (tmp_path / "t").exists()


@pytest.mark.parametrize("seed", ["abc", "1.5", "[/x]", "1e3"])
def test_seeds_that_are_not_numbers(no_episode: None, seed: str) -> None:
    error_line(runner.invoke(app, ["explore", "--seed", seed]), "--seed")


# ----------------------------------------------------------------------------------- resolutions
@pytest.mark.parametrize(
    "value", ["1e-300", "5e-324", "1e-5", "0.001", "1e300", "5", "0.2", "0.11", "0", "-0.05", "-1e300"]
)
@pytest.mark.parametrize("world", ["box", "office"])
def test_resolutions_no_robot_can_use(box: Path, no_episode: None, world: str, value: str) -> None:
    spec = str(box) if world == "box" else world
    line = error_line(runner.invoke(app, ["explore", "--world", spec, "--resolution", value]), "--resolution")
    assert f"{float(value):g}" in line


@pytest.mark.parametrize("value", ["nan", "inf", "-inf", "NaN"])
def test_non_finite_resolutions(box: Path, no_episode: None, value: str) -> None:
    error_line(runner.invoke(app, ["explore", "--world", str(box), "--resolution", value]), "finite")


def test_evaluate_checks_the_resolution_first(tmp_path: Path, box: Path) -> None:
    args = ["evaluate", "--methods", "nearest", "--worlds", str(box), "--out", str(tmp_path / "r")]
    error_line(runner.invoke(app, [*args, "--resolution", "1e-300"]), "1e-300")
    assert not (tmp_path / "r").exists()


@pytest.mark.parametrize("methods", ["", " , "])
def test_evaluate_with_no_method_is_one_line(tmp_path: Path, methods: str) -> None:
    """An empty --methods (an empty shell variable) ran the baseline alone and exited 0."""
    error_line(runner.invoke(app, ["evaluate", "--methods", methods, "--out", str(tmp_path / "r")]), "no policy")
    assert not (tmp_path / "r").exists()


@pytest.mark.parametrize("resolution", [0.0042, 0.012, 0.05, 0.105])
def test_resolutions_in_the_documented_range_are_accepted(resolution: float) -> None:
    assert check_resolution(resolution) == resolution
    lo, hi = resolution_bounds()
    assert lo == pytest.approx(0.0042) and hi == pytest.approx(0.105)


@pytest.mark.parametrize(("resolution", "match"), [(5.0, "5 m"), (1e300, "1e\\+300"), (1e-5, "1e-05"), (0.2, "0.2")])
def test_make_world_refuses_cells_that_do_not_suit_the_robot(resolution: float, match: str) -> None:
    data = np.full((12, 12), CellState.FREE, dtype=np.int8)
    data[0, :] = data[-1, :] = data[:, 0] = data[:, -1] = CellState.OCCUPIED
    grid = OccupancyGrid(data, resolution)
    with pytest.raises(MapError, match=f"world 'hall': cell size {match}.*use 0.0042 to 0.105 m"):
        make_world(grid, "hall", rng=np.random.default_rng(0))


@pytest.mark.parametrize(("radius", "sensor"), [(0.3, 3.0), (0.105, 30.0), (1.0, 10.0)])
def test_resolution_bounds_follow_the_robot(radius: float, sensor: float) -> None:
    lo, hi = resolution_bounds(radius, sensor)
    assert lo == pytest.approx(max(radius / 25, sensor / 2000)) and hi == pytest.approx(min(radius, sensor / 10))
    assert check_resolution(hi, "r", radius, sensor) == hi
    with pytest.raises(MapError):
        check_resolution(hi * 1.01, "r", radius, sensor)


# -------------------------------------------------------------------------------------- headings
@pytest.mark.parametrize("start", ["1,1,1e17", "1,1,-1e17", "1,1,1e300", "1,1,1000001", "1,1,-2e6"])
def test_absurd_headings(box: Path, no_episode: None, start: str) -> None:
    error_line(runner.invoke(app, ["explore", "--world", str(box), "--start", start]), "heading")


@pytest.mark.parametrize("start", ["1,1,nan", "1,1,inf", "nan,1", "1,-inf", "1,1,1,1", "1", "", "[/x]", "1,1,[red]"])
def test_malformed_starts(box: Path, no_episode: None, start: str) -> None:
    error_line(runner.invoke(app, ["explore", "--world", str(box), "--start", start]), "start pose")


def test_a_long_start_is_quoted_cut() -> None:
    with pytest.raises(ConfigError) as info:
        parse_pose("1," * 5000)
    assert len(str(info.value)) < 200 and "…" in str(info.value)


@pytest.mark.parametrize("theta", [7.0, -7.0, 100.0, -1000.5, 1e6, math.pi])
def test_headings_are_wrapped(theta: float) -> None:
    pose = parse_pose(f"1,1,{theta!r}")
    assert -math.pi <= pose.theta <= math.pi
    assert math.cos(pose.theta) == pytest.approx(math.cos(theta), abs=1e-9)
    assert math.sin(pose.theta) == pytest.approx(math.sin(theta), abs=1e-9)


@pytest.mark.parametrize("theta", [0.0, 0.3, -math.pi, 3.1415])
def test_headings_in_range_are_kept_bit_for_bit(theta: float) -> None:
    assert checked_pose(Pose(1.0, 2.0, theta)).theta == theta


def test_make_world_wraps_and_refuses_headings(box: Path) -> None:
    data = np.full((40, 40), CellState.FREE, dtype=np.int8)
    data[0, :] = data[-1, :] = data[:, 0] = data[:, -1] = CellState.OCCUPIED
    grid = OccupancyGrid(data, 0.05)
    world = make_world(grid, "box", start=Pose(1.0, 1.0, 7.0))
    assert world.start.theta == pytest.approx(7.0 - 2 * math.pi)
    for theta in (1e17, -MAX_HEADING_RAD * 2):
        with pytest.raises(MapError, match="heading"):
            make_world(grid, "box", start=Pose(1.0, 1.0, theta))


def test_a_wrapped_heading_lets_the_robot_move(tmp_path: Path) -> None:
    corridor = str(write_box(tmp_path, "corridor.png", length_m=10.0))  # the far end is out of sight
    result = runner.invoke(app, ["explore", "--world", corridor, "--start", "1,1,1000", "--max-time", "20", "--json"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["path_length_m"] > 1.0


# ------------------------------------------------------------------------- nothing to explore
def test_a_world_with_nothing_to_explore_is_an_error(box: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import frontier_rl.core.world.worlds as worlds

    monkeypatch.setattr(worlds, "visible_from", lambda inside, viewers, reach: np.zeros_like(inside))
    line = error_line(runner.invoke(app, ["explore", "--world", str(box)]), "nothing to explore")
    assert "'box'" in line


# -------------------------------------------------------------------------------- Rich markup
MARKUP = ["[/x]", "[red]", "[bold]x[/bold]", "a[/]b", "[link=x]", ":smile:", "[/x"]


@pytest.mark.parametrize("text", MARKUP)
@pytest.mark.parametrize(
    "option", ["--world", "--policy", "--strategy", "--fail", "--config", "--start", "--png", "--gif"]
)
def test_markup_in_arguments_is_printed_as_it_is(no_episode: None, option: str, text: str) -> None:
    value = {"--config": f"{text}.yaml", "--png": f"/dev/null/{text}/x.png", "--gif": f"{text}.txt"}.get(option, text)
    extra = ["--robots", "2"] if option == "--fail" else []
    error_line(runner.invoke(app, ["explore", *extra, option, value]), text)


@pytest.mark.parametrize("name", ["[red]box", "[bold]", "[link=x]y", "[x]", ":smile:box"])  # no "/" in a file name
def test_markup_in_a_world_name_is_printed_as_it_is(tmp_path: Path, name: str) -> None:
    world = write_box(tmp_path, f"{name}.png")
    result = runner.invoke(app, ["explore", "--world", str(world), "--max-time", "2"])
    assert result.exit_code == 0, result.output
    assert name in result.stdout and result.stderr == ""


def test_markup_in_messages_survives(capsys: pytest.CaptureFixture[str]) -> None:
    message = "field 'origin' must be [x, y], got [1]; list of finite [x, y] pairs [/x] [red]"
    print_error(message)
    assert capsys.readouterr().err == f"error: {message}\n"


@pytest.mark.parametrize(
    ("text", "expected"),
    [("a\nb", "a b"), ("a\r\n  b\n", "a b"), ("tab\there", "tab here"), ("esc\x1b[31m", "esc\\x1b[31m"),
     ("bell\x07", "bell\\x07"), ("x" * 700, "x" * 599 + "…")],
)  # fmt: skip
def test_one_line(text: str, expected: str) -> None:
    assert one_line(text) == expected


# ------------------------------------------------------------------------------- output paths
@pytest.mark.parametrize(
    ("option", "name", "needle"),
    [
        ("--png", ".", "is a folder"),
        ("--gif", ".", "is a folder"),
        ("--png", "folder.png", "is a folder"),
        ("--gif", "folder.gif", "is a folder"),
        ("--png", "x.jpg", ".jpg"),
        ("--png", "x", "suffix ''"),
        ("--png", "x.gif", ".gif"),
        ("--gif", "x.png", ".png"),
        ("--gif", "x.mp4", ".mp4"),
        ("--png", "file.txt/x.png", "is a file, not a folder"),
    ],
)
def test_bad_output_paths_are_refused_before_the_episode(
    tmp_path: Path, box: Path, no_episode: None, option: str, name: str, needle: str
) -> None:
    (tmp_path / "folder.png").mkdir()
    (tmp_path / "folder.gif").mkdir()
    (tmp_path / "file.txt").write_text("x")
    target = tmp_path if name == "." else tmp_path / name
    error_line(runner.invoke(app, ["explore", "--world", str(box), option, str(target)]), needle)


def test_a_picture_in_a_folder_not_made_yet_makes_it(tmp_path: Path, box: Path) -> None:
    """As evaluate --out makes its folder (it was refused: "does not exist")."""
    result = runner.invoke(app, ["explore", "--world", str(box), "--png", str(tmp_path / "missing/deeper/x.png")])
    assert result.exit_code == 0, result.output
    assert (tmp_path / "missing/deeper/x.png").stat().st_size > 0
    refused = runner.invoke(app, ["explore", "--world", "atlantis", "--png", str(tmp_path / "made/a/x.png")])
    assert refused.exit_code == 2 and not (tmp_path / "made").exists()  # made only once there is a picture


@pytest.mark.parametrize("command", ["evaluate", "demo", "train"])
@pytest.mark.parametrize("kind", ["file", "under a file"])
def test_results_folders_that_are_files(tmp_path: Path, command: str, kind: str) -> None:
    (tmp_path / "file.txt").write_text("keep me")
    out = tmp_path / "file.txt" if kind == "file" else tmp_path / "file.txt" / "run"
    extra = ["--methods", "nearest"] if command == "evaluate" else []
    error_line(runner.invoke(app, [command, *extra, "--out", str(out)]), "is a file, not a folder")
    assert (tmp_path / "file.txt").read_text() == "keep me"


@pytest.mark.parametrize("how", ["OSError", "OutputWriteError"])
def test_results_are_printed_before_a_picture_fails(
    box: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, how: str
) -> None:
    import frontier_rl.recording as recording
    import frontier_rl.render as render
    from frontier_rl.atomic_write import OutputWriteError

    def raw_full_disk(image: Any, path: Any, **params: Any) -> Path:  # in place of recording.save_image
        raise OSError(28, "No space left on device", str(path))

    def full_disk(path: Any, data: bytes) -> None:  # in place of the atomic writer
        raise OutputWriteError(path, "No space left on device")

    if how == "OSError":
        monkeypatch.setattr(recording, "save_image", raw_full_disk)
    else:
        monkeypatch.setattr(render, "write_bytes_atomic", full_disk)
    png = tmp_path / "run.png"
    png.write_bytes(b"previous")
    result = runner.invoke(app, ["explore", "--world", str(box), "--max-time", "2", "--json", "--png", str(png)])
    assert result.exit_code == 2
    assert json.loads(result.stdout)["world"] == "box"  # the metrics were printed
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and "No space left on device" in lines[0] and str(png) in lines[0], result.stderr
    assert png.read_bytes() == b"previous"


def test_a_failed_picture_leaves_the_previous_one(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from frontier_rl.render import save_image

    png = tmp_path / "a.png"
    save_image(Image.new("RGB", (4, 4)), png)
    before = png.read_bytes()

    def broken_encoder(self: Image.Image, fp: Any, *args: Any, **kwargs: Any) -> None:
        fp.write(b"half a picture")
        raise OSError("encoder error")

    monkeypatch.setattr(Image.Image, "save", broken_encoder)
    with pytest.raises(OSError, match="encoder error"):
        save_image(Image.new("RGB", (8, 8)), png)
    assert png.read_bytes() == before and [p.name for p in tmp_path.iterdir()] == ["a.png"]


@pytest.mark.parametrize("length_m", [2.0, 6.0])  # 2 m: explored before any decision, yet the GIF has a frame
def test_pictures_are_written_whole(tmp_path: Path, length_m: float) -> None:
    room = write_box(tmp_path, "room.png", length_m)
    png, gif = tmp_path / "run.PNG", tmp_path / "run.gif"
    args = ["explore", "--world", str(room), "--start", "1,1", "--max-time", "5", "--png", str(png), "--gif", str(gif)]
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    with Image.open(png) as image:
        assert image.format == "PNG"
    with Image.open(gif) as image:
        assert image.format == "GIF" and image.n_frames >= 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["room.png", "run.PNG", "run.gif"]  # no temporary left


# ------------------------------------------------------------------------------------- warnings
def test_warnings_are_one_line_each_after_the_results(box: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    def noisy() -> None:
        for _ in range(3):
            warnings.warn("careful:\n[/x] twice", UserWarning, stacklevel=1)
        warnings.warn("second", RuntimeWarning, stacklevel=1)

    monkeypatch.setattr(api, "_warm_up", noisy)
    with warnings.catch_warnings():
        warnings.simplefilter("always")
        result = runner.invoke(app, ["explore", "--world", str(box), "--max-time", "2", "--json"])
    assert result.exit_code == 0, result.output
    assert result.stderr.splitlines() == [
        "warning: UserWarning: careful: [/x] twice",
        "warning: RuntimeWarning: second",
    ]


def test_a_map_whose_grey_unknown_the_yaml_reads_as_free_is_read_as_unknown_with_one_warning(tmp_path: Path) -> None:
    pixels = np.full((60, 60), 205, dtype=np.uint8)  # a 2 m room amid unknown, saved with Nav2's free_thresh
    pixels[10:52, 10:52] = 0
    pixels[11:51, 11:51] = 254
    Image.fromarray(pixels).save(tmp_path / "slam.pgm")
    yaml_path = tmp_path / "slam.yaml"
    yaml_path.write_text(
        "image: slam.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.25\n"
    )
    with warnings.catch_warnings():
        warnings.simplefilter("default")  # as a user's Python: the suite's turns warnings into errors
        result = runner.invoke(app, ["explore", "--world", str(yaml_path), "--max-time", "2", "--json"])
    assert result.exit_code == 0, result.output
    (line,) = result.stderr.splitlines()
    assert line.startswith(f"warning: MapWarning: {yaml_path}: 1,836 pixels of grey 205 (map_saver's unknown")
    assert line.endswith("set free_thresh: 0.196 in the YAML to say so")
    assert json.loads(result.stdout)["end_reason"] == "explored"


def test_an_error_is_the_only_line_even_after_warnings(box: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    def noisy() -> None:
        warnings.warn("noise", UserWarning, stacklevel=1)
        raise MapError("broken [/x]")

    monkeypatch.setattr(api, "_warm_up", noisy)
    with warnings.catch_warnings():
        warnings.simplefilter("always")
        result = runner.invoke(app, ["explore", "--world", str(box)])
    error_line(result, "broken [/x]")


# ------------------------------------------------------------------------------ usage errors
@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["explore", "--bogus"], "--bogus"),
        (["explore", "--resolution", "abc"], "--resolution"),
        (["explore", "--max-time", "[/x]"], "--max-time"),
        (["explore", "--robots", "two"], "--robots"),
        (["bogus"], "bogus"),
        (["explore", "--png"], "--png"),
    ],
)
def test_usage_errors_are_one_line(args: list[str], needle: str) -> None:
    error_line(runner.invoke(app, args), needle)
