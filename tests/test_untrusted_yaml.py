"""Untrusted YAML (issue 14): alias bombs against every YAML the tool reads, under a memory and time
bound; anchors refused even when harmless; YAML-1.2 numbers in every file; size, encoding, node and
depth limits; values quoted in messages cut to a bounded length."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from typer.testing import CliRunner

from frontier_rl.cli import app
from frontier_rl.config_files import load_sim_config
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.world.grid import OccupancyGrid
from frontier_rl.errors import ConfigError, FrontierRLError, MapError, short_path, short_repr, short_text
from frontier_rl.io import load_map, save_ros_map
from frontier_rl.rl.config import MAX_LEARNING_RATE, TrainConfig
from frontier_rl.safe_yaml import (
    MAX_YAML_BYTES,
    MAX_YAML_DEPTH,
    MAX_YAML_NODES,
    dump_yaml,
    parse_yaml,
)

_REPO_ROOT = Path(__file__).resolve().parents[1]
#: Longest message a refusal may print (characters): the path plus a bounded explanation.
_MESSAGE_LIMIT = 600
runner = CliRunner()


def laughs(depth: int = 9, width: int = 10) -> str:
    """A flow-style "billion laughs" value: ``width ** depth`` copies of "lol" in under 1 KB of YAML."""
    items = ["&l0 lol"] + [f"&l{i} [{', '.join([f'*l{i - 1}'] * width)}]" for i in range(1, depth + 1)]
    return "[" + ", ".join(items) + "]"


MAP_FIELDS = {
    "image": "map.pgm",
    "resolution": "0.05",
    "origin": "[0.0, 0.0, 0.0]",
    "negate": "0",
    "occupied_thresh": "0.65",
    "free_thresh": "0.196",
}


def map_yaml(folder: Path, overrides: dict[str, str] | None = None, extra: str = "", name: str = "map.yaml") -> Path:
    """A map_server YAML beside a small free PGM; ``overrides`` replace fields' YAML text."""
    (folder / "map.pgm").write_bytes(b"P5\n4 3\n255\n" + bytes([254]) * 12)
    fields = {**MAP_FIELDS, **(overrides or {})}
    path = folder / name
    path.write_text("".join(f"{key}: {value}\n" for key, value in fields.items()) + extra)
    return path


# --------------------------------------------------------------------------- alias bombs, bounded
# Every YAML the tool reads: a map YAML (load_map, the sibling YAML of an image, --world of the CLI),
# the SimConfig of --config (load_sim_config, explore and evaluate), and a training run's config.yaml.
BOMB_CASES: dict[str, tuple[str, str, str]] = {
    # case: (reader, file name, YAML text)
    "map-resolution": ("load_map", "map.yaml", f"{'image: map.pgm'}\nresolution: {laughs()}\n"),
    "map-origin": ("load_map", "map.yaml", f"image: map.pgm\nresolution: 0.05\norigin: {laughs()}\n"),
    "map-image": ("load_map", "map.yaml", f"image: {laughs()}\nresolution: 0.05\n"),
    "map-mode": ("load_map", "map.yaml", "".join(f"{k}: {v}\n" for k, v in MAP_FIELDS.items()) + f"mode: {laughs()}\n"),
    "map-negate": (
        "load_map",
        "map.yaml",
        f"image: map.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: {laughs()}\n",
    ),
    "map-unused-field": (
        "load_map",
        "map.yaml",
        "".join(f"{k}: {v}\n" for k, v in MAP_FIELDS.items()) + f"x: {laughs()}\n",
    ),
    "map-sibling-of-image": ("load_map_image", "map.yaml", f"image: {laughs()}\n"),
    "cli-world": ("cli_world", "map.yaml", f"image: map.pgm\nresolution: {laughs()}\n"),
    "config-max-sim-time": ("load_sim_config", "sim.yaml", f"max_sim_time: {laughs()}\n"),
    "config-nested": ("load_sim_config", "sim.yaml", f"lidar:\n  num_beams: {laughs()}\n"),
    "config-section": ("load_sim_config", "sim.yaml", f"robot: {laughs()}\n"),
    "config-unknown-key": ("load_sim_config", "sim.yaml", f"bogus: {laughs()}\n"),
    "config-as-key": ("load_sim_config", "sim.yaml", f"? {laughs()}\n: 1\n"),
    "cli-explore-config": ("cli_explore", "sim.yaml", f"sensor_noise: {laughs()}\n"),
    "cli-evaluate-config": ("cli_evaluate", "sim.yaml", f"max_sim_time: {laughs()}\n"),
    "train-timesteps": ("train_config", "config.yaml", f"timesteps: {laughs()}\n"),
    "train-worlds": ("train_config", "config.yaml", f"worlds: {laughs()}\n"),
    "train-model": ("train_config", "config.yaml", f"model: {laughs()}\n"),
    "train-whole-file": ("train_config", "config.yaml", f"{laughs()}\n"),
}

# Runs in a child process whose address space is limited to what it has after importing the tool
# plus _HEADROOM, and that is killed after _CHILD_SECONDS: an alias that is expanded (into a message,
# a list, ...) ends it with MemoryError or a timeout instead of taking the machine.
_HEADROOM = 768 << 20
_CHILD_SECONDS = 120
_CHILD = r"""
import json, resource, sys, time
from pathlib import Path
from typer.testing import CliRunner
from frontier_rl.cli import app
from frontier_rl.config_files import load_sim_config
from frontier_rl.io import load_map
from frontier_rl.rl.config import TrainConfig

pages = int(open("/proc/self/statm").read().split()[0])
limit = pages * resource.getpagesize() + int(sys.argv[1])
resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
runner = CliRunner()

def run(reader, path):
    if reader == "load_map":
        load_map(path)
    elif reader == "load_map_image":
        load_map(path.with_suffix(".pgm"))
    elif reader == "load_sim_config":
        load_sim_config(path)
    elif reader == "train_config":
        TrainConfig.load(path)
    else:
        args = {
            "cli_world": ["explore", "--world", str(path)],
            "cli_explore": ["explore", "--config", str(path)],
            "cli_evaluate": ["evaluate", "--methods", "nearest", "--out", str(path.parent / "out"),
                             "--config", str(path), "--episodes", "1", "--backend", "serial"],
        }[reader]
        result = runner.invoke(app, args)
        return {"type": f"exit {result.exit_code}", "message": result.output.strip()}
    return {"type": "no error", "message": ""}

for line in sys.stdin:
    case = json.loads(line)
    start = time.perf_counter()
    try:
        outcome = run(case["reader"], Path(case["path"]))
    except BaseException as exc:
        outcome = {"type": type(exc).__name__, "message": str(exc)[:2000]}
    outcome.update(case=case["case"], seconds=time.perf_counter() - start)
    print(json.dumps(outcome), flush=True)
"""


@pytest.fixture(scope="module")
def bomb_outcomes(tmp_path_factory: pytest.TempPathFactory) -> dict[str, dict[str, Any]]:
    """Every bomb case, read in one memory- and time-limited child process."""
    if not Path("/proc/self/statm").exists():
        pytest.skip("needs Linux /proc to bound the child's memory")
    root = tmp_path_factory.mktemp("bombs")
    lines = []
    for case, (reader, name, text) in BOMB_CASES.items():
        folder = root / case
        folder.mkdir()
        (folder / "map.pgm").write_bytes(b"P5\n4 3\n255\n" + bytes([254]) * 12)
        path = folder / name
        path.write_text(text)
        assert len(text.encode()) < 1024  # a 1 KB file
        lines.append(json.dumps({"case": case, "reader": reader, "path": str(path)}))
    env = {**os.environ, "PYTHONPATH": str(_REPO_ROOT), "NUMBA_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}
    proc = subprocess.run(
        [sys.executable, "-W", "error", "-c", _CHILD, str(_HEADROOM)],
        input="\n".join(lines) + "\n",
        capture_output=True,
        text=True,
        timeout=_CHILD_SECONDS,
        env=env,
        cwd=root,
    )
    outcomes = {}
    for line in proc.stdout.splitlines():
        outcome = json.loads(line)
        outcomes[outcome["case"]] = outcome
    assert proc.returncode == 0, proc.stderr[-3000:]
    return outcomes


@pytest.mark.parametrize("case", list(BOMB_CASES))
def test_alias_bomb_is_refused_within_memory_and_time(bomb_outcomes: dict[str, dict[str, Any]], case: str) -> None:
    outcome = bomb_outcomes[case]
    reader = BOMB_CASES[case][0]
    expected = "exit 2" if reader.startswith("cli_") else ("MapError" if "map" in reader else "ConfigError")
    assert outcome["type"] == expected, outcome
    message = outcome["message"]
    assert "aliases" in message and "not allowed" in message, message
    assert "\n" not in message and len(message) < _MESSAGE_LIMIT, message
    assert BOMB_CASES[case][1] in message  # names the file
    assert outcome["seconds"] < 10, outcome


# --------------------------------------------------------------------------- every YAML reader
def _read_map(path: Path) -> object:
    return load_map(path)


def _read_config(path: Path) -> object:
    return load_sim_config(path)


def _read_training(path: Path) -> object:
    return TrainConfig.load(path)


READERS: dict[str, tuple[Callable[[Path], object], type[FrontierRLError]]] = {
    "map": (_read_map, MapError),
    "config": (_read_config, ConfigError),
    "training": (_read_training, ConfigError),
}
#: A valid document of each reader, to which a case adds lines.
VALID_TEXT = {
    "map": "".join(f"{key}: {value}\n" for key, value in MAP_FIELDS.items()),
    "config": "sensor_noise: false\n",
    "training": "model: 4\n",
}


def _refusal(tmp_path: Path, reader: str, data: bytes, error: type[Exception] | None = None) -> str:
    """The one-line message of ``reader`` refusing a file holding ``data`` (with ``error``, or the
    reader's own error type)."""
    map_yaml(tmp_path)  # the image a map YAML names
    path = tmp_path / "doc.yaml"
    path.write_bytes(data)
    read, own_error = READERS[reader]
    error = error or own_error
    start = time.perf_counter()
    with pytest.raises(error) as info:
        read(path)
    assert time.perf_counter() - start < 10
    message = str(info.value)
    assert "\n" not in message and len(message) < _MESSAGE_LIMIT, message
    assert "doc.yaml" in message
    return message


@pytest.mark.parametrize("reader", list(READERS))
@pytest.mark.parametrize(
    "extra",
    [
        "harmless: &same 1\nagain: *same\n",  # one anchor and one alias of a number
        "spare: &unused 0.5\n",  # an anchor nothing refers to
        "base: &base {a: 1}\nmerged:\n  <<: *base\n",  # a merge key
        "list: &l [1, 2]\n",
    ],
)
def test_even_a_harmless_anchor_or_alias_is_refused(tmp_path: Path, reader: str, extra: str) -> None:
    message = _refusal(tmp_path, reader, (VALID_TEXT[reader] + extra).encode())
    assert "aliases" in message and "not even a harmless one" in message
    assert "line " in message  # says where


@pytest.mark.parametrize("reader", list(READERS))
def test_a_key_given_twice_is_refused_naming_it_and_its_line(tmp_path: Path, reader: str) -> None:
    first = VALID_TEXT[reader].splitlines()[0]
    message = _refusal(tmp_path, reader, (VALID_TEXT[reader] + first + "\n").encode())
    key = first.split(":")[0]
    assert f"the key {key!r} is given twice in one mapping" in message
    assert f"line {len(VALID_TEXT[reader].splitlines()) + 1}" in message
    nested = _refusal(tmp_path, reader, (VALID_TEXT[reader] + "extra:\n  a: 1\n  a: 2\n").encode())
    assert "the key 'a' is given twice" in nested


def test_a_merge_key_without_an_alias_still_merges_its_mapping() -> None:
    assert parse_yaml("a: 1\n<<: {b: 2}\n") == {"a": 1, "b": 2}
    assert parse_yaml("a: 1\n<<: {a: 2}\n") == {"a": 1}  # a key of its own wins over a merged one


@pytest.mark.parametrize("reader", list(READERS))
@pytest.mark.parametrize(
    ("data", "needle"),
    [
        (b"resolution: \xff\xfe\n", "not UTF-8"),
        (b"\xff\xfer\x00e\x00s\x00", "not UTF-8"),  # UTF-16 with a byte-order mark
        (b"a: caf\xe9\n", "byte 0xe9 at offset 6"),  # Latin-1
        (b"\xef\xbb\xbfa: caf\xe9\n", "byte 0xe9 at offset 9"),  # after a UTF-8 byte-order mark
        (b"a: \x00\n", "not allowed in YAML"),  # a control character
        (b"a: [1, 2\n", "cannot parse"),
        (b"a: 1\n---\nb: 2\n", "cannot parse"),
        (b"a: !!python/object:os.system x\n", "cannot parse"),
        (b"a: " + b"1" * 5000 + b"\n", "more than 100 digits"),
        (b"a: " + b"[" * (MAX_YAML_DEPTH + 1) + b"]" * (MAX_YAML_DEPTH + 1) + b"\n", "nested more than"),
        (b"a: [" + b"1, " * MAX_YAML_NODES + b"1]\n", f"more than {MAX_YAML_NODES} YAML nodes"),
        (b"# " + b"x" * MAX_YAML_BYTES + b"\n", f"more than the {MAX_YAML_BYTES}"),
    ],
    ids=[
        "ff-fe",
        "utf-16",
        "latin-1",
        "bom-latin-1",
        "nul",
        "unclosed",
        "two-docs",
        "python-tag",
        "long-int",
        "deep",
        "nodes",
        "size",
    ],
)
def test_bad_files_are_one_line_errors_naming_the_file(tmp_path: Path, reader: str, data: bytes, needle: str) -> None:
    assert needle in _refusal(tmp_path, reader, data)


@pytest.mark.parametrize("reader", list(READERS))
def test_a_huge_file_is_refused_by_its_size_before_reading(tmp_path: Path, reader: str) -> None:
    path = tmp_path / "doc.yaml"
    with path.open("wb") as stream:
        stream.truncate(8 << 30)  # 8 GiB, sparse: reading it whole would take the machine
    read, error = READERS[reader]
    start = time.perf_counter()
    with pytest.raises(error, match=rf"doc\.yaml is {8 << 30} bytes, more than the {MAX_YAML_BYTES} allowed"):
        read(path)
    assert time.perf_counter() - start < 1


@pytest.mark.parametrize("reader", list(READERS))
def test_a_folder_or_missing_file_is_a_one_line_error(tmp_path: Path, reader: str) -> None:
    read, error = READERS[reader]
    folder = tmp_path / "folder.yaml"
    folder.mkdir()
    for path in (folder, tmp_path / "missing.yaml"):
        with pytest.raises(error, match=path.name) as info:
            read(path)
        assert "\n" not in str(info.value)


def test_a_file_just_under_the_size_limit_is_read(tmp_path: Path) -> None:
    path = tmp_path / "sim.yaml"
    body = b"sensor_noise: false\n"
    path.write_bytes(body + b"#" * (MAX_YAML_BYTES - len(body) - 1) + b"\n")
    assert path.stat().st_size == MAX_YAML_BYTES
    assert load_sim_config(path).sensor_noise is False


# --------------------------------------------------------------------------- YAML 1.2 numbers
@pytest.mark.parametrize(
    ("literal", "value"),
    [("6e2", 600.0), ("1e-3", 0.001), ("1E3", 1000.0), ("2.5e+1", 25.0), (".5", 0.5), ("1.", 1.0), ("0.05", 0.05),
     ("+7e-4", 0.0007), ("1_000.5", 1000.5)],
)  # fmt: skip
def test_exponent_numbers_are_floats_in_map_config_and_training_yaml(
    tmp_path: Path, literal: str, value: float
) -> None:
    grid = load_map(map_yaml(tmp_path, {"resolution": literal})).grid
    assert grid.resolution == value
    config = tmp_path / "sim.yaml"
    config.write_text(f"max_sim_time: {literal}\nnavigation: {{}}\ntime_per_area: {literal}\n")
    sim = load_sim_config(config)
    assert sim.max_sim_time == value and sim.time_per_area == value
    training = tmp_path / "config.yaml"
    training.write_text(f"learning_rate: {literal}\n")
    if value <= MAX_LEARNING_RATE:
        assert TrainConfig.load(training).learning_rate == value
    else:  # out of range, and named as the float it was read as
        with pytest.raises(ConfigError, match=re.escape(f"got {value!r}")):
            TrainConfig.load(training)


@pytest.mark.parametrize(
    ("literal", "value"),
    [("6e2", 600.0), ("-1E3", -1000.0), ("1e-3", 0.001), (".5", 0.5), ("-.5", -0.5), ("1.", 1.0), ("1.5e3", 1500.0),
     ("1e999", float("inf")), (".inf", float("inf")), ("-.Inf", float("-inf")), ("10", 10), ("-0", 0), ("010", 10),
     ("0o17", 15), ("0x1F", 31), ("100_000", 100_000), ("+5", 5),
     ("1e", "1e"), ("e3", "e3"), ("1.2.3", "1.2.3"), ("1:30", "1:30"), ("2024-01-02", "2024-01-02"), ("0b101", "0b101"),
     ("'6e2'", "6e2"), ("yes", True), ("null", None)],
)  # fmt: skip
def test_scalars_resolve_as_yaml_1_2(literal: str, value: object) -> None:
    parsed = parse_yaml(f"a: {literal}\n")["a"]
    assert parsed == value and type(parsed) is type(value)


def test_a_string_where_a_number_belongs_is_named_not_a_traceback(tmp_path: Path) -> None:
    training = tmp_path / "config.yaml"
    for text, needle in [("timesteps: abc\n", "timesteps must be an integer"), ("gamma: x\n", "gamma must be a number"),
                         ("worlds: 5\n", "worlds must be a string"), ("seed: -1\n", "seed must be >= 0"),
                         ("model: 4.0\n", "model must be an integer"), ("reward: [1]\n", "reward")]:  # fmt: skip
        training.write_text(text)
        with pytest.raises(ConfigError, match=needle):
            TrainConfig.load(training)


def test_a_config_saved_and_read_back_is_the_same(tmp_path: Path) -> None:
    config = TrainConfig(learning_rate=1e-5, ent_coef=0.0, timesteps=100_000)
    config.dump(tmp_path / "config.yaml")
    assert TrainConfig.load(tmp_path / "config.yaml") == config


def test_a_saved_map_reads_back_through_the_same_loader(tmp_path: Path) -> None:
    grid = OccupancyGrid(np.array([[0, 100, -1]], dtype=np.int8), 1e-3, (6e2, -1e-3))
    loaded = load_map(save_ros_map(grid, tmp_path / "1e3.yaml")).grid
    np.testing.assert_array_equal(loaded.data, grid.data)
    assert (loaded.resolution, loaded.origin) == (grid.resolution, grid.origin)


# --------------------------------------------------------------------------- bounded quotes
LONG = "x" * 200_000


@pytest.mark.parametrize(
    ("reader", "text"),
    [
        ("map", VALID_TEXT["map"] + f"mode: {LONG}\n"),
        ("map", VALID_TEXT["map"].replace("0.05", LONG)),
        ("map", VALID_TEXT["map"].replace("map.pgm", "[" + ", ".join(["1"] * 5000) + "]")),
        ("config", f"max_sim_time: {LONG}\n"),
        ("config", f"{LONG[:1000]}: 1\n"),  # a longer plain key is a syntax error
        ("config", f"lidar: [{', '.join([LONG[:1000]] * 50)}]\n"),
        ("training", f"algo: {LONG}\n"),
        ("training", f"worlds: {LONG}\n"),
        ("training", f"reward: {LONG}\n"),
        ("training", f"{LONG[:1000]}: 1\n"),
    ],
    ids=["map-mode", "map-resolution", "map-image-list", "config-value", "config-key", "config-list",
         "train-algo", "train-worlds", "train-reward", "train-key"],
)  # fmt: skip
def test_long_values_are_quoted_cut_short(tmp_path: Path, reader: str, text: str) -> None:
    message = _refusal(tmp_path, reader, text.encode(), FrontierRLError)  # an unknown world is UnknownNameError
    assert "xxxxxxxx" in message or "1, 1" in message or "must be" in message


def test_short_repr_is_bounded_without_expanding_the_value() -> None:
    shared: list[Any] = ["lol"]
    for _ in range(30):  # 10**30 leaves, built from 30 small lists
        shared = [shared] * 10
    start = time.perf_counter()
    for value in (shared, LONG, list(range(10**6)), {str(i): i for i in range(10**5)}, 10**20000, b"\xff" * 10**6):
        text = short_repr(value)
        assert len(text) <= 80 and "\n" not in text
    assert time.perf_counter() - start < 1
    assert short_repr("abc") == "'abc'" and short_repr(0.5) == "0.5"
    assert short_text("a\nb  c" + "d" * 500, 20) == "a b c" + "d" * 14 + "…"


@pytest.mark.parametrize(
    "folder", ["/tmp/pytest-of-root/pytest-15/test_a_member_declaring_16_gib0", "x" * 5000, "a\nb" * 40]
)
def test_a_long_path_is_cut_in_the_middle_so_its_file_name_stays(folder: str) -> None:
    text = short_path(Path(folder) / "bomb_policy.pth.zip")
    assert len(text) <= 80 and "\n" not in text and "…" in text
    assert text.endswith("/bomb_policy.pth.zip'") and text.startswith(repr(folder[:10])[:-1])
    assert short_path(Path("/a/b.zip")) == "'/a/b.zip'" and short_path("c.zip", 3) == "'c…"


def test_the_cli_reports_a_harmless_alias_in_one_line(tmp_path: Path) -> None:
    config = tmp_path / "sim.yaml"
    config.write_text("max_sim_time: &t 600\nmin_time_cap: *t\n")
    result = runner.invoke(app, ["explore", "--config", str(config)])
    assert result.exit_code == 2
    lines = [line for line in result.output.splitlines() if line.strip()]
    assert len(lines) == 1 and "not even a harmless one" in lines[0] and "sim.yaml" in lines[0], result.output


@pytest.mark.parametrize(
    "text", ["1e5", "0o17", "0x1F", "010", ".5", "1.", "6E2", "100_000", "yes", "1:30", "null", "~"]
)
def test_what_the_tool_writes_it_reads_back_the_same(text: str) -> None:
    """A string that YAML 1.2 would read as a number (or a boolean, or null) is quoted when dumped."""
    data = {"worlds": text, "nested": [text, {"k": text}], "number": 6e2}
    assert parse_yaml(dump_yaml(data)) == data


def test_an_empty_training_config_is_refused_but_an_empty_sim_config_is_the_defaults(tmp_path: Path) -> None:
    empty = tmp_path / "config.yaml"
    empty.write_text("# nothing\n")
    with pytest.raises(ConfigError, match="is empty"):
        TrainConfig.load(empty)
    assert load_sim_config(empty) == SimConfig()


def test_config_errors_name_the_field_and_the_file(tmp_path: Path) -> None:
    sim = tmp_path / "sim.yaml"
    sim.write_text("lidar: {max_range: fast}\n")
    with pytest.raises(ConfigError, match=r"sim\.yaml: SimConfig\.lidar\.max_range must be a number"):
        load_sim_config(sim)
    training = tmp_path / "config.yaml"
    training.write_text("timestep: 5\n")
    with pytest.raises(ConfigError, match=r"unknown key 'timestep' in TrainConfig; valid keys: model, worlds"):
        TrainConfig.load(training)
