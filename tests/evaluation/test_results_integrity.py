"""Results folders that were edited, damaged or written on a full disk: edited rows and rows of
another experiment are refused naming the file and line, bytes that are not UTF-8 are a one-line
error, a failed write leaves the previous file and says which path it was, and a refused
configuration shows each differing setting so that both sides read differently."""

from __future__ import annotations

import errno
import json
import math
import os
import re
import shutil
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import pytest
from typer.testing import CliRunner

from frontier_rl import atomic_write
from frontier_rl.atomic_write import OutputWriteError, write_text_atomic
from frontier_rl.cli import app
from frontier_rl.config_diff import contrast, describe_differences, differences_between
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.errors import ConfigError
from frontier_rl.evaluation.results.episode_record import ROW_COLUMNS
from frontier_rl.evaluation.results.identity import ExperimentIdentity
from frontier_rl.evaluation.results.store import ResultStore, adopt_rows
from frontier_rl.evaluation.running.evaluate import evaluate
from frontier_rl.evaluation.running.experiment import ExperimentConfig
from frontier_rl.evaluation.running.fingerprints import identity

pytestmark = pytest.mark.slow  # experiments resumed from damaged results folders

SHORT = SimConfig(max_sim_time=40.0)  # a fraction of a second per episode
METHODS = ("fixed:0.75", "nearest")
FILES = ("experiment.json", "episodes.csv", "traces.jsonl", "checksums.jsonl")
OUTPUTS = ("summary.json", "boxplot.png", "scatter.png", "coverage.png", "report.md", "report.html")
runner = CliRunner()


def _config(seed: int = 0, episodes: int = 2) -> ExperimentConfig:
    return ExperimentConfig(methods=METHODS, worlds=("office",), episodes=episodes, seed=seed, sim=SHORT)


@pytest.fixture(scope="module")
def complete(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A complete experiment: 2 methods x 2 episodes; episodes.csv lines 2-5 are fixed:0.75 and
    nearest of episode 0, then of episode 1 (traces.jsonl and checksums.jsonl lines 1-4)."""
    out = tmp_path_factory.mktemp("complete") / "exp"
    evaluate(_config(), out, backend="serial", progress=False, command="test")
    return out


@pytest.fixture(scope="module")
def other(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Another experiment (seed 5, three episodes) on the same world with the same methods."""
    out = tmp_path_factory.mktemp("other") / "exp"
    evaluate(_config(seed=5, episodes=3), out, backend="serial", progress=False, command="test")
    return out


def _copy(source: Path, target: Path, names: tuple[str, ...] = FILES) -> Path:
    target.mkdir(parents=True)
    for name in names:
        shutil.copyfile(source / name, target / name)
    return target


def _lines(path: Path) -> list[str]:
    return path.read_text().splitlines()


def _write_lines(path: Path, lines: list[str]) -> None:
    path.write_text("".join(line + "\n" for line in lines))


def _snapshot(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.name != ".lock" and p.is_file()}


def _open(out: Path, seed: int = 0) -> None:
    ResultStore(out, identity(_config(seed))).close()


# ----------------------------------------------------------------------------- edited rows
def _field(line: str, column: str, value: str) -> str:
    """``line`` with ``column`` set to ``value`` (no field before it holds a comma)."""
    fields = line.split(",")
    fields[-1 if column == "wall_time_s" else ROW_COLUMNS.index(column)] = value
    return ",".join(fields)


def _edit_csv(edit: Callable[[list[str], Path], list[str]]) -> Callable[[Path, Path], None]:
    def apply(out: Path, other: Path) -> None:
        _write_lines(out / "episodes.csv", edit(_lines(out / "episodes.csv"), other))

    return apply


def _from_other(out: Path, other: Path) -> None:
    """Episode 0 of nearest, with its trace and checksum, from the other experiment."""
    for name, index in (("episodes.csv", 2), ("traces.jsonl", 1), ("checksums.jsonl", 1)):
        mine, theirs = _lines(out / name), _lines(other / name)
        assert theirs[index].split(",")[0] == "nearest" or '"nearest"' in theirs[index]
        mine[index] = theirs[index]
        _write_lines(out / name, mine)


def _edit_trace(out: Path, other: Path) -> None:
    lines = _lines(out / "traces.jsonl")
    trace = json.loads(lines[2])
    trace["coverage"][-1] = 0.99
    lines[2] = json.dumps(trace, separators=(",", ":"))
    _write_lines(out / "traces.jsonl", lines)


def _edit_checksum(out: Path, other: Path) -> None:
    lines = _lines(out / "checksums.jsonl")
    entry = json.loads(lines[3])
    entry["row_sha256"] = "0" * 64
    lines[3] = json.dumps(entry)
    _write_lines(out / "checksums.jsonl", lines)


EDITS: dict[str, tuple[Callable[[Path, Path], None], str]] = {
    "time changed": (_edit_csv(lambda ls, o: [*ls[:2], _field(ls[2], "sim_time_s", "12.5"), *ls[3:]]),
                     r"episodes\.csv line 3 \(nearest on office, episode 0\) does not match its checksum"),
    "time reformatted": (_edit_csv(lambda ls, o: [*ls[:4], ls[4].replace(",40.0", ",40.00", 1), *ls[5:]]),
                         r"episodes\.csv line 5 \(nearest on office, episode 1\) does not match its checksum"),
    "wall time changed": (_edit_csv(lambda ls, o: [*ls[:1], _field(ls[1], "wall_time_s", "0.001"), *ls[2:]]),
                          r"episodes\.csv line 2 \(fixed:0.75 on office, episode 0\) does not match"),
    "method renamed to another": (
        _edit_csv(lambda ls, o: [*ls[:3], _field(ls[3], "method", "nearest"), *ls[4:]]),
        r"episodes\.csv line 5 repeats the episode of line 4 \(nearest on office, episode 1\)",
    ),
    "method renamed to a stranger": (
        _edit_csv(lambda ls, o: [*ls[:1], _field(ls[1], "method", "largest"), *ls[2:]]),
        r"episodes\.csv line 2 \(largest on office, episode 0\): 'largest' is not a method of this experiment",
    ),
    "seed changed": (_edit_csv(lambda ls, o: [*ls[:4], _field(ls[4], "seed", "7"), *ls[5:]]),
                     r"episodes\.csv line 5 \(nearest on office, episode 1\) does not match its checksum"),
    "episode changed": (_edit_csv(lambda ls, o: [*ls[:4], _field(ls[4], "episode", "9"), *ls[5:]]),
                        r"episodes\.csv line 5 \(nearest on office, episode 9\) has no checksum"),
    "start pose changed": (_edit_csv(lambda ls, o: [*ls[:2], _field(ls[2], "start_x_m", "1.0"), *ls[3:]]),
                           r"episodes\.csv line 3 .* does not match its checksum"),
    "duplicated row": (_edit_csv(lambda ls, o: [*ls, ls[1]]),
                       r"episodes\.csv line 6 repeats the episode of line 2 \(fixed:0.75 on office, episode 0\)"),
    "row of another experiment": (
        _edit_csv(lambda ls, o: [*ls[:2], _lines(o / "episodes.csv")[2], *ls[3:]]),
        r"episodes\.csv line 3 \(nearest on office, episode 0\) does not match its checksum",
    ),
    "row, trace and checksum of another experiment": (
        _from_other, r"episodes\.csv line 3 \(nearest on office, episode 0\) does not match its checksum"
    ),
    "extra episode of another experiment": (
        _edit_csv(lambda ls, o: [*ls, _lines(o / "episodes.csv")[5]]),
        r"episodes\.csv line 6 \(fixed:0.75 on office, episode 2\) has no checksum",
    ),
    "trace edited": (_edit_trace, r"traces\.jsonl line 3 \(the trace of fixed:0.75 on office, episode 1\) does "
                                  r"not match its checksum"),
    "checksum edited": (_edit_checksum, r"episodes\.csv line 5 .* does not match its checksum \(checksums\.jsonl "
                                        r"line 4\)"),
    "checksums deleted": (lambda out, other: (out / "checksums.jsonl").unlink(),
                          r"episodes\.csv holds 4 episodes but checksums\.jsonl is missing"),
}  # fmt: skip


@pytest.mark.parametrize("case", list(EDITS))
def test_edited_rows_are_refused_naming_the_file_and_line(complete: Path, other: Path, tmp_path: Path,
                                                          case: str) -> None:  # fmt: skip
    out = _copy(complete, tmp_path / "exp")
    edit, message = EDITS[case]
    edit(out, other)
    before = _snapshot(out)
    with pytest.raises(ConfigError, match=message) as caught:
        _open(out)
    text = str(caught.value)
    assert "\n" not in text and str(out) in text
    assert "delete" in text or "run the experiment again" in text  # says what to do
    assert _snapshot(out) == before  # nothing dropped or rewritten
    with pytest.raises(ConfigError, match=message):  # evaluate refuses before running anything
        evaluate(_config(), out, backend="serial", progress=False)
    assert _snapshot(out) == before


def test_a_refused_folder_keeps_its_experiment_json(complete: Path, tmp_path: Path) -> None:
    out = _copy(complete, tmp_path / "exp")
    lines = _lines(out / "episodes.csv")
    _write_lines(out / "episodes.csv", [*lines[:2], _field(lines[2], "sim_time_s", "1.0"), *lines[3:]])
    before = _snapshot(out)
    bigger = ExperimentConfig(methods=(*METHODS, "largest"), worlds=("office",), episodes=2, sim=SHORT)
    with pytest.raises(ConfigError, match="line 3"):
        evaluate(bigger, out, backend="serial", progress=False)
    assert _snapshot(out) == before  # the added method is not recorded in experiment.json


def test_an_untouched_copy_and_a_deleted_row_are_accepted(complete: Path, tmp_path: Path) -> None:
    out = _copy(complete, tmp_path / "exp")
    _open(out)
    lines = _lines(out / "episodes.csv")
    _write_lines(out / "episodes.csv", [*lines[:2], *lines[3:]])  # deleting a row reruns its episode
    evaluate(_config(), out, backend="serial", progress=False)
    assert len(_lines(out / "episodes.csv")) == 5
    assert [line.split(",")[:3] for line in _lines(out / "episodes.csv")] == [
        line.split(",")[:3] for line in _lines(complete / "episodes.csv")
    ]
    _open(out)


def test_rows_of_a_folder_without_checksums_can_be_adopted(complete: Path, tmp_path: Path) -> None:
    out = _copy(complete, tmp_path / "exp", ("experiment.json", "episodes.csv", "traces.jsonl"))
    with pytest.raises(ConfigError, match=r"checksums\.jsonl is missing.*adopt_rows"):
        _open(out)
    assert adopt_rows(out) == 4
    assert (out / "checksums.jsonl").read_bytes() == (complete / "checksums.jsonl").read_bytes()
    _open(out)
    with pytest.raises(ConfigError, match="checked already"):
        adopt_rows(out)


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("{", r"experiment\.json is not valid JSON"),
        ('{"seed": ' + "[" * 40 + "]" * 40 + "}", r"experiment\.json is not an experiment description \(nested"),
        ("[]", r"experiment\.json is not an experiment description \("),
    ],
)
def test_adopting_reads_experiment_json_as_a_run_does(text: str, needle: str, complete: Path, tmp_path: Path) -> None:
    """adopt_rows read experiment.json with checks of its own, short of a run's (no depth bound)."""
    out = _copy(complete, tmp_path / "exp", ("experiment.json", "episodes.csv", "traces.jsonl"))
    (out / "experiment.json").write_text(text)
    with pytest.raises(ConfigError, match=needle):
        adopt_rows(out)
    assert not (out / "checksums.jsonl").exists()


def test_adopting_still_refuses_rows_that_cannot_belong(complete: Path, tmp_path: Path) -> None:
    out = _copy(complete, tmp_path / "exp", ("experiment.json", "episodes.csv", "traces.jsonl"))
    lines = _lines(out / "episodes.csv")
    _write_lines(out / "episodes.csv", [*lines, lines[2]])
    with pytest.raises(ConfigError, match="line 6 repeats the episode of line 3"):
        adopt_rows(out)
    _write_lines(out / "episodes.csv", [*lines[:1], _field(lines[1], "method", "largest"), *lines[2:]])
    with pytest.raises(ConfigError, match=r"line 2 \(largest on office, episode 0\) is not a method"):
        adopt_rows(out)
    assert not (out / "checksums.jsonl").exists()


def test_the_cli_refuses_an_edited_row_in_one_line(complete: Path, tmp_path: Path) -> None:
    out = _copy(complete, tmp_path / "exp")
    lines = _lines(out / "episodes.csv")
    _write_lines(out / "episodes.csv", [*lines[:2], _field(lines[2], "sim_time_s", "1.0"), *lines[3:]])
    args = ["evaluate", "--methods", "nearest", "--no-oracle", "--episodes", "2", "--max-time", "40", "--out",
            str(out), "--no-progress"]  # fmt: skip
    result = runner.invoke(app, args)
    assert result.exit_code == 2, result.output
    assert len(result.output.strip().splitlines()) == 1 and "line 3" in result.output, result.output


# ----------------------------------------------------------------------------- bytes that are not UTF-8
@pytest.mark.parametrize(
    ("name", "line", "bad"),
    [
        ("episodes.csv", 1, b"\xff"),
        ("episodes.csv", 2, b"\xe9"),
        ("episodes.csv", 3, b"\xc3\x28"),
        ("episodes.csv", 5, b"\x80\x81"),
        ("traces.jsonl", 2, b"\xfe"),
        ("checksums.jsonl", 4, b"\xed\xa0\x80"),  # an encoded surrogate
        ("experiment.json", 3, b"\xff"),
    ],
)
def test_bytes_that_are_not_utf8_are_a_one_line_error(
    complete: Path, tmp_path: Path, name: str, line: int, bad: bytes
) -> None:
    out = _copy(complete, tmp_path / "exp")
    lines = (out / name).read_bytes().split(b"\n")
    lines[line - 1] = lines[line - 1][:5] + bad + lines[line - 1][5:]
    (out / name).write_bytes(b"\n".join(lines))
    before = _snapshot(out)
    with pytest.raises(ConfigError, match=rf"{re.escape(name)} line {line} holds bytes that are not UTF-8"):
        _open(out)
    assert _snapshot(out) == before


def test_the_cli_reports_bytes_that_are_not_utf8_in_one_line(complete: Path, tmp_path: Path) -> None:
    out = _copy(complete, tmp_path / "exp")
    data = (out / "episodes.csv").read_bytes()
    (out / "episodes.csv").write_bytes(data.replace(b"nearest", b"n\xe9arest", 1))
    args = ["evaluate", "--methods", "nearest", "--no-oracle", "--episodes", "2", "--max-time", "40", "--out",
            str(out), "--no-progress"]  # fmt: skip
    result = runner.invoke(app, args)
    assert result.exit_code == 2, result.output
    assert len(result.output.strip().splitlines()) == 1, result.output
    assert "line 3 holds bytes that are not UTF-8" in result.output


@pytest.mark.parametrize("line", [b"nearest,office,0,\x00,1", b'"unterminated,office', b"a,b"])
def test_rows_that_do_not_parse_name_the_line(complete: Path, tmp_path: Path, line: bytes) -> None:
    out = _copy(complete, tmp_path / "exp")
    with (out / "episodes.csv").open("ab") as handle:
        handle.write(line + b"\n")
    with pytest.raises(ConfigError, match=r"episodes\.csv line 6: "):
        _open(out)


@pytest.mark.parametrize(
    ("name", "content", "message"),
    [
        ("experiment.json", b"[" * 100_000 + b"]" * 100_000, r"experiment\.json is not an experiment description"),
        ("experiment.json", b'{"seed": ' + b"[" * 40 + b"]" * 40 + b"}", r"not an experiment description"),
        ("experiment.json", b'{"methods": [1]}', r"not an experiment description"),
        ("experiment.json", b"{", r"experiment\.json is not valid JSON"),
        ("traces.jsonl", b"[" * 100_000 + b"]" * 100_000 + b"\n", r"traces\.jsonl line 1 is not a trace"),
        ("traces.jsonl", b'{"method": "nearest"}\n', r"traces\.jsonl line 1 is not a trace"),
        ("checksums.jsonl", b'{"method": "nearest"}\n', r"checksums\.jsonl line 1 is not a row checksum"),
        ("checksums.jsonl", b"\n\n[1, 2]\n", r"checksums\.jsonl line 3 is not a row checksum"),
        ("traces.jsonl", b'{"episode": ' + b"1" * 5000 + b"}\n", r"traces\.jsonl line 1 is not a trace"),
        ("experiment.json", b'{"seed": ' + b"1" * 5000 + b"}", r"not an experiment description"),
    ],
)
def test_damaged_files_are_a_one_line_error(
    complete: Path, tmp_path: Path, name: str, content: bytes, message: str
) -> None:
    out = _copy(complete, tmp_path / "exp")
    (out / name).write_bytes(content)
    with pytest.raises(ConfigError, match=message) as caught:
        _open(out)
    assert "\n" not in str(caught.value) and len(str(caught.value)) < 400


# ----------------------------------------------------------------------------- a full disk
@contextmanager
def _disk_full(monkeypatch: pytest.MonkeyPatch, name: str, after_calls: int = 0) -> Iterator[list[str]]:
    """Writes to the file ``name`` (or to its temporary file) write half their bytes and then
    fail with ENOSPC, from the ``after_calls``-th such write on; yields the names that failed."""
    real = atomic_write.write_all
    seen = {"calls": 0}
    failed: list[str] = []

    def write_all(fd: int, data: bytes) -> None:
        target = Path(os.readlink(f"/proc/self/fd/{fd}")).name
        if target == name or (target.startswith(f".{name}.") and target.endswith(".tmp")):
            seen["calls"] += 1
            if seen["calls"] > after_calls:
                failed.append(target)
                real(fd, data[: len(data) // 2])
                raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        real(fd, data)

    monkeypatch.setattr(atomic_write, "write_all", write_all)
    yield failed
    monkeypatch.setattr(atomic_write, "write_all", real)


@pytest.mark.skipif(not Path("/proc/self/fd").is_dir(), reason="needs /proc to tell which file is written")
@pytest.mark.parametrize("name", [*OUTPUTS, *FILES])
def test_a_full_disk_while_rewriting_the_report_keeps_every_file(
    complete: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, name: str
) -> None:
    out = _copy(complete, tmp_path / "exp", (*FILES, *OUTPUTS))
    before = _snapshot(out)
    with _disk_full(monkeypatch, name) as failed, pytest.raises(OutputWriteError) as caught:
        evaluate(_config(), out, backend="serial", progress=False, command="test")
    assert failed, "the write should have been tried"
    message = str(caught.value)
    assert str(out / name) in message and "No space left on device" in message and "\n" not in message
    assert "4 finished episodes are kept" in message or "are unchanged" in message
    after = _snapshot(out)
    assert after[name] == before[name]  # the good file is intact, not cut to 0 bytes
    assert set(after) == set(before)  # no temporary file left behind
    assert all(after[n] for n in after)
    _open(out)  # the rows still verify
    evaluate(_config(), out, backend="serial", progress=False, command="test")  # with space again
    assert (out / name).stat().st_size > 0


@pytest.mark.skipif(not Path("/proc/self/fd").is_dir(), reason="needs /proc to tell which file is written")
@pytest.mark.parametrize(("name", "after_calls"), [("episodes.csv", 3), ("traces.jsonl", 2), ("checksums.jsonl", 1)])
def test_a_full_disk_during_a_run_keeps_the_finished_rows(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, name: str, after_calls: int
) -> None:
    out = tmp_path / "exp"
    with _disk_full(monkeypatch, name, after_calls), pytest.raises(OutputWriteError) as caught:
        evaluate(_config(), out, backend="serial", progress=False)
    message = str(caught.value)
    assert str(out / name) in message and "finished episodes are kept" in message
    csv_lines = _lines(out / "episodes.csv")
    assert (out / name).read_bytes().endswith(b"\n")  # the half-written line was cut back
    assert len(csv_lines) - 1 == int(message.split(" finished episodes")[0].rsplit(" ", 1)[-1])
    _open(out)  # what is there verifies
    evaluate(_config(), out, backend="serial", progress=False)  # the rerun completes it
    assert len(_lines(out / "episodes.csv")) == 5
    _open(out)


@pytest.mark.parametrize("payload", [b"", b"x" * 10, b"y" * 300_000])
def test_write_text_atomic_replaces_or_keeps(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, payload: bytes) -> None:
    path = tmp_path / "file.txt"
    path.write_bytes(b"old contents\n")

    def full(fd: int, data: bytes) -> None:
        os.write(fd, data[: len(data) // 2])
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(atomic_write, "write_all", full)
    with pytest.raises(OutputWriteError, match=re.escape(str(path))):
        write_text_atomic(path, payload.decode())
    assert path.read_bytes() == b"old contents\n" and [p.name for p in tmp_path.iterdir()] == ["file.txt"]
    monkeypatch.undo()
    write_text_atomic(path, payload.decode())
    assert path.read_bytes() == payload and [p.name for p in tmp_path.iterdir()] == ["file.txt"]


# ----------------------------------------------------------------------------- configuration differences
def _identity(**changes: Any) -> ExperimentIdentity:
    parts: dict[str, Any] = {
        "seed": 0,
        "worlds": ["office", "/data/maps/" + "very_long_folder_name/" * 4 + "map.yaml#sha256:0123456789abcdef"],
        "resolution": None,
        "sim": {"max_sim_time": 600.0, "lidar": {"num_beams": 360, "noise": [0.01] * 20}, "name": "x" * 80},
        "methods": {"nearest": "nearest"},
    }
    return ExperimentIdentity.from_json(parts | changes)


def _with_sim(**sim: Any) -> ExperimentIdentity:
    return _identity(sim={**_identity().sim, **sim})


DIFFS: dict[str, tuple[ExperimentIdentity, str]] = {
    "map hash at the end of a long path": (
        _identity(worlds=["office", _identity().worlds[1][:-16] + "fedcba9876543210"]), "worlds[1]"),
    "a value deep in the sim settings": (_with_sim(lidar={"num_beams": 180, "noise": [0.01] * 20}),
                                         "sim.lidar.num_beams"),
    "the last item of a long list": (_with_sim(lidar={"num_beams": 360, "noise": [0.01] * 19 + [0.02]}),
                                     "sim.lidar.noise[19]"),
    "a long string that differs at its end": (_with_sim(name="x" * 79 + "y"), "sim.name"),
    "a long string one character longer": (_with_sim(name="x" * 81), "sim.name"),
    "a list of another length": (_with_sim(lidar={"num_beams": 360, "noise": [0.01] * 21}), "sim.lidar.noise"),
    "a setting added": (_identity(team={"comm_range": 2.0, "failures": []}), "team"),
    "seed": (_identity(seed=1), "seed"),
    "an int for a float": (_with_sim(max_sim_time=601), "sim.max_sim_time"),
}  # fmt: skip


def test_a_world_list_of_another_length_names_the_maps_each_side_has_alone() -> None:
    """A folder of maps with one map edited and one added was shown as two lists cut mid-hash."""
    there = ["office", "maps/room_1.png#sha256:aaa", "maps/room_2.png#sha256:bbb"]
    now = ["office", "maps/room_1.png#sha256:ccc", "maps/room_2.png#sha256:bbb", "maps/room_9.png#sha256:ddd"]
    differences = differences_between(there, now, "worlds")
    assert describe_differences(differences) == (
        'worlds: "maps/room_1.png#sha256:aaa" there, (absent) now; '
        'worlds: (absent) there, "maps/room_1.png#sha256:ccc" now; '
        'worlds: (absent) there, "maps/room_9.png#sha256:ddd" now'
    )


def test_a_refused_folder_keeps_a_last_line_without_its_newline(tmp_path: Path) -> None:
    """A run refused for another configuration cut the folder's last row off (its newline dropped by
    an editor), as a torn line is cut once a run takes the folder."""
    ResultStore(tmp_path, _identity()).close()
    csv_path = tmp_path / "episodes.csv"
    csv_path.write_text(",".join(ROW_COLUMNS) + "\n" + "a row an editor left without its newline")
    before = _snapshot(tmp_path)
    with pytest.raises(ConfigError, match="different configuration"):
        ResultStore(tmp_path, _identity(seed=1))
    assert _snapshot(tmp_path) == before
    ResultStore(tmp_path, _identity()).close()  # taken: the torn line is cut, so the next row starts a line
    assert csv_path.read_bytes().endswith(b"\n") and b"editor" not in csv_path.read_bytes()


@pytest.mark.parametrize("case", list(DIFFS))
def test_a_refused_configuration_shows_both_sides_differently(tmp_path: Path, case: str) -> None:
    changed, path = DIFFS[case]
    ResultStore(tmp_path, _identity()).close()
    before = _snapshot(tmp_path)
    with pytest.raises(ConfigError, match="different configuration") as caught:
        ResultStore(tmp_path, changed)
    message = str(caught.value)
    assert _snapshot(tmp_path) == before
    found = re.search(rf"\({re.escape(path)}: (.+?) there, (.+?) now[;)]", message)
    assert found, message
    there, now = found.groups()
    assert there != now, message
    assert len(there) < 80 and len(now) < 80, message  # each value cut


def test_many_differences_are_counted_not_all_listed(tmp_path: Path) -> None:
    ResultStore(tmp_path, _identity()).close()
    changed = _with_sim(max_sim_time=1.0, lidar={"num_beams": 1, "noise": [0.5] * 20}, name="z")
    with pytest.raises(ConfigError, match=r"and 19 more differences\)") as caught:
        ResultStore(tmp_path, changed)
    assert str(caught.value).count(" there, ") == 4


def test_a_changed_model_file_shows_both_fingerprints(tmp_path: Path) -> None:
    method = "learned:" + "models/" * 10 + "m.zip"
    ResultStore(tmp_path, _identity(methods={method: f"{method}#sha256:aaaaaaaaaaaaaaaa"})).close()
    row = [method if column == "method" else "" for column in ROW_COLUMNS]  # a row of it: then a change counts
    (tmp_path / "episodes.csv").write_text(",".join(ROW_COLUMNS) + "\n" + ",".join(row) + "\n")
    with pytest.raises(ConfigError, match="from another version of its model file or policy code") as caught:
        ResultStore(tmp_path, _identity(methods={method: f"{method}#sha256:bbbbbbbbbbbbbbbb"}))
    assert "aaaaaaaa" in str(caught.value) and "bbbbbbbb" in str(caught.value)
    # the hashes alone, whole: the method's name, cut mid-path, hid them
    assert '("sha256:aaaaaaaaaaaaaaaa" there, "sha256:bbbbbbbbbbbbbbbb" now: any edit counts' in str(caught.value)


@pytest.mark.parametrize(
    ("there", "now"),
    [("a" * 200 + "b", "a" * 200 + "c"), ("a" * 100, "a" * 101), ("b" + "a" * 100, "c" + "a" * 100),
     ({"k": "v" * 100}, {"k": "v" * 100, "l": 1}), ([1] * 50, [1] * 49 + [2]), ("short", "x" * 500)],
)  # fmt: skip
def test_contrast_never_shows_two_different_values_alike(there: Any, now: Any) -> None:
    a, b = contrast(there, now)
    assert a != b and len(a) < 80 and len(b) < 80


def test_differences_name_leaves() -> None:
    assert differences_between({"a": {"b": 1, "c": [1, 2]}}, {"a": {"b": 2, "c": [1, 3]}}, "sim") == [
        ("sim.a.b", 1, 2), ("sim.a.c[1]", 2, 3),
    ]  # fmt: skip
    assert differences_between({"a": 1.0}, {"a": 1}, "x") == []  # JSON numbers that compare equal


# ----------------------------------------------------------------------------- special files, signed nonsense
def _fifo(path: Path) -> None:
    path.unlink(missing_ok=True)
    os.mkfifo(path)


def _dev_zero(path: Path) -> None:
    path.unlink()
    path.symlink_to("/dev/zero")


def _sparse(path: Path) -> None:
    os.truncate(path, (1 << 30) + 1)  # 4 kB on disk


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
@pytest.mark.parametrize(
    ("name", "make", "message"),
    [
        (".lock", _fifo, r"\.lock is not a regular file"),  # opening it to write blocked for good
        ("experiment.json", _fifo, r"experiment\.json is not a regular file"),  # so did reading it
        ("episodes.csv", _fifo, r"episodes\.csv is not a regular file"),
        ("traces.jsonl", _dev_zero, r"traces\.jsonl is not a regular file"),  # filled the memory
        ("experiment.json", _sparse, r"experiment\.json holds 1,073,741,825 bytes, more than 16,777,216"),
        ("traces.jsonl", _sparse, r"traces\.jsonl holds 1,073,741,825 bytes, more than 1,073,741,824"),
    ],
)
def test_special_and_huge_files_are_a_one_line_error(
    complete: Path, tmp_path: Path, name: str, make: Callable[[Path], None], message: str
) -> None:
    out = _copy(complete, tmp_path / "exp")
    make(out / name)
    errors: list[BaseException] = []

    def open_it() -> None:
        try:
            _open(out)
        except BaseException as exc:  # handed to the test's thread
            errors.append(exc)

    opening = threading.Thread(target=open_it, daemon=True)  # a regression would block, not fail
    opening.start()
    opening.join(timeout=60)
    assert not opening.is_alive(), f"opening a folder with {name} as {make.__name__} blocked"
    assert len(errors) == 1 and isinstance(errors[0], ConfigError), errors
    assert re.search(message, str(errors[0])) and "\n" not in str(errors[0])


def _set_trace(**fields: object) -> Callable[[Path], None]:
    """Set the first trace's ``fields`` (None deletes one)."""

    def edit(out: Path) -> None:
        lines = _lines(out / "traces.jsonl")
        trace = json.loads(lines[0]) | fields
        lines[0] = json.dumps({k: v for k, v in trace.items() if v is not None})
        _write_lines(out / "traces.jsonl", lines)

    return edit


def _set_row(column: str, value: str) -> Callable[[Path], None]:
    def edit(out: Path) -> None:
        lines = _lines(out / "episodes.csv")
        lines[1] = _field(lines[1], column, value)
        _write_lines(out / "episodes.csv", lines)

    return edit


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (_set_row("sim_time_s", "nan"), r"episodes\.csv line 2: sim_time_s 'nan' is not valid .*finite"),
        (_set_row("sim_time_s", "1e308"), r"sim_time_s '1e308' is not valid"),  # broke the plots' axes
        (_set_row("path_length_m", "-inf"), r"path_length_m '-inf' is not valid"),
        (_set_trace(coverage=None), r"traces\.jsonl line 1 .*coverage_t and coverage must be lists of one length"),
        (_set_trace(coverage=[]), r"coverage must be lists of one length, not empty"),
        (_set_trace(coverage_t="abc"), r"coverage must be lists"),
        (_set_trace(weight=[math.nan]), r"weight_t and weight must be lists of one length"),
        (_set_trace(coverage_t=[1e308, 1e308], coverage=[0.5, 1.0]), r"must hold finite numbers"),
        (_set_trace(robot_coverage={"a": 1}), r"robot_coverage must be a list of finite numbers"),
    ],
)
def test_rows_and_traces_signed_again_after_an_edit_are_checked(
    complete: Path, tmp_path: Path, edit: Callable[[Path], None], message: str
) -> None:
    """Anyone can sign rows again (``adopt_rows``, or the checksums' documented recipe): what the
    report cannot use is refused by file and line, where it was a traceback in the report."""
    out = _copy(complete, tmp_path / "exp")
    edit(out)
    (out / "checksums.jsonl").unlink()
    with pytest.raises(ConfigError, match=message) as caught:
        adopt_rows(out)
    assert "\n" not in str(caught.value)


def test_adopting_names_an_experiment_json_too_large_to_read(complete: Path, tmp_path: Path) -> None:
    """Its reading error was taken for JSON that is no experiment description."""
    out = _copy(complete, tmp_path / "exp")
    (out / "checksums.jsonl").unlink()
    os.truncate(out / "experiment.json", 17 * 1024 * 1024)
    with pytest.raises(ConfigError, match=r"experiment\.json holds 17,825,792 bytes, more than 16,777,216"):
        adopt_rows(out)
