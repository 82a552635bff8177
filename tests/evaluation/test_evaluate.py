"""``evaluate``: paired rows, identical across backends, resume after SIGKILL, refusal to mix
configurations, the report files, and bad input."""

from __future__ import annotations

import csv
import json
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from typer.testing import CliRunner

from frontier_rl.cli import app
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.errors import ConfigError, UnknownNameError
from frontier_rl.evaluation.report.table import short_labels
from frontier_rl.evaluation.results.store import ResultStore
from frontier_rl.evaluation.running import backends
from frontier_rl.evaluation.running.backends import EpisodeFailedError
from frontier_rl.evaluation.running.evaluate import evaluate, parse_thresholds
from frontier_rl.evaluation.running.experiment import (
    MAX_JOBS,
    EpisodeJob,
    EpisodeSettings,
    ExperimentConfig,
    expand_worlds,
)
from frontier_rl.evaluation.running.fingerprints import identity
from tests.processes import children, gone, left_in_group, loads_numpy, sigint_as_in_a_terminal, workers_started

pytestmark = pytest.mark.slow  # whole experiments, in worker processes and as subprocesses

SHORT = SimConfig(max_sim_time=80.0)  # episodes cut at 80 s of sim time: a fraction of a second each
runner = CliRunner()


def _config(methods: tuple[str, ...] = ("fixed:0.75", "nearest"), episodes: int = 2, **kw: object) -> ExperimentConfig:
    return ExperimentConfig(methods=methods, worlds=("office",), episodes=episodes, sim=SHORT, **kw)  # type: ignore[arg-type]


def _rows(out: Path, drop_wall: bool = True) -> list[dict[str, str]]:
    with (out / "episodes.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    for row in rows:
        if drop_wall:
            row.pop("wall_time_s")
    return rows


@pytest.fixture(scope="module")
def serial_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("serial") / "exp"
    evaluate(_config(), out, backend="serial", progress=False, command="test")
    return out


def test_rows_are_paired_and_complete(serial_run: Path) -> None:
    rows = _rows(serial_run)
    assert [(r["method"], r["episode"]) for r in rows] == [
        ("fixed:0.75", "0"), ("nearest", "0"), ("fixed:0.75", "1"), ("nearest", "1"),
    ]  # fmt: skip
    for episode in ("0", "1"):
        pair = [r for r in rows if r["episode"] == episode]
        # the same world, start and seed for both methods in an episode
        assert len({(r["world"], r["seed"], r["start_x_m"], r["start_y_m"], r["start_theta_rad"]) for r in pair}) == 1
    assert {r["seed"] for r in rows} == {"0", "1"}
    assert all(float(r["sim_time_s"]) <= 80.0 + 1e-6 for r in rows)
    for row in rows:  # how each episode ended; cut at 80 s, none explores the office
        assert row["end_reason"] == "time_cap" and row["truncated"] == "True" and row["done"] == "False"
        assert 0.0 < float(row["free_coverage"]) <= float(row["coverage"]) + 1e-9
        assert float(row["unknown_left_m2"]) >= 0.0
    traces = [json.loads(line) for line in (serial_run / "traces.jsonl").read_text().splitlines()]
    assert [(t["method"], t["episode"]) for t in traces] == [(r["method"], int(r["episode"])) for r in rows]


@pytest.mark.parametrize("backend", ["process", "ray"])
def test_backends_give_identical_rows(serial_run: Path, tmp_path: Path, backend: str) -> None:
    if backend == "ray":
        pytest.importorskip("ray")
    out = tmp_path / backend
    evaluate(_config(), out, backend=backend, workers=2, progress=False, command="test")
    assert _rows(out) == _rows(serial_run)
    assert (out / "traces.jsonl").read_bytes() == (serial_run / "traces.jsonl").read_bytes()


def test_summary_json_has_the_documented_fields(serial_run: Path) -> None:
    summary = json.loads((serial_run / "summary.json").read_text())
    assert summary["baseline"] == "fixed:0.75"
    nearest = summary["methods"]["nearest"]
    for key in ("n", "mean_time_s", "var_time_s", "mean_diff_s", "ci95_s", "p_one_tailed", "p_two_tailed",
                "p_wilcoxon", "reduction_pct"):  # fmt: skip
        assert key in nearest
    times = {(r["method"], r["episode"]): float(r["sim_time_s"]) for r in _rows(serial_run)}
    diffs = [times[("fixed:0.75", e)] - times[("nearest", e)] for e in ("0", "1")]
    assert nearest["n"] == 2 and nearest["mean_diff_s"] == pytest.approx(sum(diffs) / 2)
    assert set(summary["outliers"]) == {"1000", "2000"}
    for method, entry in summary["methods"].items():
        own = [r for r in _rows(serial_run) if r["method"] == method]
        assert entry["end_reasons"] == {"explored": 0, "unreachable": 0, "time_cap": 2}
        assert entry["mean_coverage"] == pytest.approx(sum(float(r["coverage"]) for r in own) / 2)
        assert entry["min_coverage"] == min(float(r["coverage"]) for r in own)
        assert entry["mean_free_coverage"] == pytest.approx(sum(float(r["free_coverage"]) for r in own) / 2)
        assert entry["mean_unknown_left_m2"] == pytest.approx(sum(float(r["unknown_left_m2"]) for r in own) / 2)


def test_report_files_hold_the_table(serial_run: Path) -> None:
    for name in ("report.md", "report.html", "boxplot.png", "scatter.png", "coverage.png", "summary.json"):
        assert (serial_run / name).stat().st_size > 0, name
    markdown = (serial_run / "report.md").read_text()
    assert "| method | n | mean time (s) | variance (s²) | sd (s) | mean saving (s)" in markdown
    assert "| fixed:0.75 (baseline) | 2 |" in markdown and "| nearest | 2 |" in markdown
    assert "![Exploration time per method](boxplot.png)" in markdown
    header = "| method | episodes | explored | unreachable | time cap | mean coverage | min coverage"
    assert f"**Completion**\n\n{header}" in markdown
    assert "| nearest | 2 | 0 | 0 | 2 |" in markdown
    assert "cap): fixed:0.75 2, nearest 2." in markdown  # the episodes cut at the cap, named under Table 4.1
    page = (serial_run / "report.html").read_text()
    assert page.count("<table>") >= 3 and "fixed:0.75 (baseline)" in page
    assert "<caption>Completion</caption>" in page
    assert page.count("data:image/png;base64,") == 3 + 2  # 3 charts (no weight plot without learned methods), 2 runs


def test_rerun_skips_finished_episodes_and_methods_can_be_added(serial_run: Path, tmp_path: Path) -> None:
    out = tmp_path / "grow"
    evaluate(_config(), out, backend="serial", progress=False)
    before = {(r["method"], r["episode"]): r["wall_time_s"] for r in _rows(out, drop_wall=False)}
    evaluate(_config(("fixed:0.75", "nearest", "largest")), out, backend="serial", progress=False)
    after = _rows(out, drop_wall=False)
    assert len(after) == 6
    for row in after:  # the old rows were kept, not rerun (their wall times are unchanged)
        if (row["method"], row["episode"]) in before:
            assert row["wall_time_s"] == before[(row["method"], row["episode"])]


@pytest.mark.parametrize(
    ("change", "needle"),
    [({"seed": 5}, "seed"), ({"sim": SimConfig(max_sim_time=90.0)}, "sim")],
)
def test_a_different_configuration_is_refused_and_nothing_is_lost(
    serial_run: Path, change: dict[str, object], needle: str
) -> None:
    files = {p.name: p.read_bytes() for p in serial_run.iterdir() if p.is_file()}
    kwargs = {"methods": ("fixed:0.75", "nearest"), "worlds": ("office",), "episodes": 2, "sim": SHORT} | change
    with pytest.raises(ConfigError, match=f"different configuration \\({needle}"):
        evaluate(ExperimentConfig(**kwargs), serial_run, backend="serial", progress=False)  # type: ignore[arg-type]
    assert {p.name: p.read_bytes() for p in serial_run.iterdir() if p.is_file()} == files


def test_a_changed_model_file_is_refused(tmp_path: Path) -> None:
    model = Path("models/model4.zip")
    if not model.exists():
        pytest.skip("shipped model missing")
    copy = tmp_path / "m.zip"
    copy.write_bytes(model.read_bytes())
    config = _config(("fixed:0.75", f"learned:{copy}"), episodes=1)
    evaluate(config, tmp_path / "exp", backend="serial", progress=False)
    copy.write_bytes(Path("models/model5.zip").read_bytes())
    with pytest.raises(ConfigError, match="from another version of its model file or policy code"):
        evaluate(config, tmp_path / "exp", backend="serial", progress=False)


def test_map_files_and_folders_are_worlds(real_maps: Path, tmp_path: Path) -> None:
    folder = tmp_path / "maps"
    folder.mkdir()
    for name in ("map.yaml", "map.pgm"):
        (folder / name).write_bytes((real_maps / "turtlebot3_world" / name).read_bytes())
    worlds = expand_worlds(f"{folder},office")
    assert worlds == (str(folder / "map.yaml"), "office")
    config = ExperimentConfig(methods=("fixed:0.75", "nearest"), worlds=worlds, episodes=1, sim=SHORT)
    evaluate(config, tmp_path / "exp", backend="serial", progress=False)
    summary = json.loads((tmp_path / "exp" / "summary.json").read_text())
    assert set(summary["per_world"]) == set(worlds)
    assert "World map" in (tmp_path / "exp" / "report.md").read_text()


def _cli(out: Path, *extra: str) -> list[str]:
    return [sys.executable, "-m", "frontier_rl.cli", "evaluate", "--methods", "nearest,largest", "--episodes", "4",
            "--max-time", "150", "--no-oracle", "--no-progress", "--out", str(out), *extra]  # fmt: skip


@pytest.fixture(scope="module")
def uninterrupted(tmp_path_factory: pytest.TempPathFactory) -> Path:
    whole = tmp_path_factory.mktemp("whole") / "exp"
    subprocess.run(_cli(whole, "--backend", "serial"), check=True, capture_output=True, timeout=300)
    return whole


@pytest.mark.parametrize("backend", ["serial", "process"])
def test_resume_after_sigkill_ends_with_the_uninterrupted_table(
    uninterrupted: Path, tmp_path: Path, backend: str
) -> None:
    killed = tmp_path / "killed"
    process = subprocess.Popen(_cli(killed, "--backend", backend), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    csv_path = killed / "episodes.csv"
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and (not csv_path.exists() or len(csv_path.read_text().splitlines()) < 4):
        time.sleep(0.02)
    workers = children(process.pid)
    os.kill(process.pid, signal.SIGKILL)
    process.wait(timeout=30)
    finished = len(csv_path.read_text().splitlines()) - 1
    assert 3 <= finished < 8, "the kill should land mid-run"
    if backend == "process":  # the pool's workers do not outlive the killed run
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and not all(gone(pid) for pid in workers):
            time.sleep(0.1)
        assert workers and all(gone(pid) for pid in workers)
    with csv_path.open("a") as handle:  # as if killed while writing a row
        handle.write("nearest,office,3,3,1.0")
    with (killed / "traces.jsonl").open("a") as handle:
        handle.write('{"method": "nearest", "wor')
    subprocess.run(_cli(killed, "--backend", backend), check=True, capture_output=True, timeout=300)
    assert _rows(killed) == _rows(uninterrupted)
    assert (killed / "traces.jsonl").read_bytes() == (uninterrupted / "traces.jsonl").read_bytes()


@pytest.mark.serial
@pytest.mark.parametrize("moment", ["loading", "workers starting", "episodes running"])
def test_ctrl_c_ends_the_run_with_one_line_and_every_worker(uninterrupted: Path, tmp_path: Path, moment: str) -> None:
    """Ctrl-C (SIGINT to the whole process group, as a terminal sends it), twice, at three moments:
    while the command line loads, while the pool's workers start, while episodes run. The run ends
    at once with one line and exit code 130, no worker outlives it, and a rerun completes the table."""
    out = tmp_path / "interrupted"
    command = [sys.executable, "-c", "import sys; from frontier_rl.launch import main; sys.exit(main())",
               *_cli(out, "--backend", "process", "--workers", "2")[3:]]  # fmt: skip
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                               start_new_session=True, preexec_fn=sigint_as_in_a_terminal)  # fmt: skip
    csv_path = out / "episodes.csv"
    deadline = time.monotonic() + 120
    while moment == "loading" and time.monotonic() < deadline and not loads_numpy(process.pid):
        time.sleep(0.002)
    while moment == "workers starting" and time.monotonic() < deadline and not workers_started(process.pid):
        time.sleep(0.002)
    while (
        moment == "episodes running"
        and time.monotonic() < deadline
        and not (csv_path.exists() and len(csv_path.read_text().splitlines()) >= 2)
    ):
        time.sleep(0.02)
    os.killpg(process.pid, signal.SIGINT)
    time.sleep(0.02)
    os.killpg(process.pid, signal.SIGINT)  # impatient: a second one, while the run ends
    _, stderr = process.communicate(timeout=60)
    assert process.returncode == 130, stderr
    assert len(stderr.splitlines()) == 1 and stderr.startswith("interrupted"), stderr
    assert not left_in_group(process.pid)
    if moment == "episodes running":
        assert "rerun the same command to resume" in stderr
        subprocess.run(_cli(out, "--backend", "process"), check=True, capture_output=True, timeout=300)
        assert _rows(out) == _rows(uninterrupted)


def test_a_failing_episode_keeps_every_other_one(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    real = backends.run_job

    def flaky(job: EpisodeJob, settings: EpisodeSettings) -> dict[str, object]:
        if job.method == "nearest" and job.episode == 0:
            raise RuntimeError("simulated crash")
        return real(job, settings)

    monkeypatch.setattr(backends, "run_job", flaky)
    out = tmp_path / "exp"
    with pytest.raises(EpisodeFailedError, match="1 of 4 episodes failed, the first nearest on office episode 0"):
        evaluate(_config(), out, backend="serial", progress=False)
    assert len(_rows(out)) == 3  # the other three were recorded
    monkeypatch.setattr(backends, "run_job", real)
    evaluate(_config(), out, backend="serial", progress=False)  # the rerun retries only the failed one
    assert len(_rows(out)) == 4


def test_a_policy_file_that_failed_every_episode_may_be_fixed_and_run_again(tmp_path: Path) -> None:
    """Its file's hash was kept with no row of it, and the rerun after the fix was refused as
    results of another version of its code."""
    policy = tmp_path / "mine.py"
    broken = (
        "import numpy as np\n"
        "from frontier_rl import Ranking\n"
        "class Mine:\n"
        "    name = 'mine'\n"
        "    def rank(self, context, rng):\n"
        "        raise RuntimeError('boom inside rank')\n"
    )
    policy.write_text(broken)
    config, out = _config(("fixed:0.75", f"{policy}:Mine"), episodes=1), tmp_path / "exp"
    with pytest.raises(EpisodeFailedError, match="boom inside rank"):
        evaluate(config, out, backend="serial", progress=False)
    policy.write_text(
        broken.replace("raise RuntimeError('boom inside rank')", "return Ranking(np.arange(len(context.frontiers)))")
    )
    evaluate(config, out, backend="serial", progress=False)
    assert sorted(row["method"] for row in _rows(out)) == sorted(["fixed:0.75", f"{policy}:Mine"])
    policy.write_text(policy.read_text() + "# changed again\n")  # now it has a row: refused
    with pytest.raises(ConfigError, match="from another version of its model file or policy code"):
        evaluate(config, out, backend="serial", progress=False)


@pytest.mark.parametrize("backend", ["serial", "process"])
def test_a_policy_that_calls_sys_exit_fails_its_episodes(tmp_path: Path, backend: str) -> None:
    """sys.exit(0) in rank() ended a serial run with exit code 0 and no results, and a worker with
    "worker process ended (exit code 0)"."""
    policy = tmp_path / "quits.py"
    policy.write_text(
        "import sys\nclass Quits:\n    name = 'q'\n    def rank(self, context, rng):\n        sys.exit(0)\n"
    )
    config = _config(("fixed:0.75", f"{policy}:Quits"), episodes=1)
    with pytest.raises(
        EpisodeFailedError, match=r"1 of 2 episodes failed.*RuntimeError: the policy called sys\.exit\(0"
    ):
        evaluate(config, tmp_path / "exp", backend=backend, workers=1, progress=False)
    assert [row["method"] for row in _rows(tmp_path / "exp")] == ["fixed:0.75"]  # the other episode's row kept


def test_a_map_or_a_method_of_the_folder_written_another_way(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """./maps/a.yaml was refused as "a different configuration", an absolute path too (the same map,
    its hash the same), and a policy file named by another path ran its episodes again as a new method."""
    (tmp_path / "maps").mkdir()
    image = np.zeros((60, 110), np.uint8)
    image[3:-3, 3:-3] = 255
    image[3:-3, 55] = 0
    image[24:36, 55] = 255
    Image.fromarray(image).save(tmp_path / "maps" / "rooms.png")
    (tmp_path / "mine.py").write_text(
        "import numpy as np\nfrom frontier_rl import Ranking\nclass Mine:\n    name = 'mine'\n"
        "    def rank(self, context, rng):\n        return Ranking(np.argsort(context.frontiers.distances))\n"
    )
    monkeypatch.chdir(tmp_path)
    out = tmp_path / "exp"

    def run(world: str, method: str) -> None:
        config = ExperimentConfig(methods=("nearest", method), worlds=(world,), episodes=1, baseline="nearest",
                                  resolution=0.05, sim=SHORT)  # fmt: skip
        evaluate(config, out, backend="serial", progress=False)

    run("maps/rooms.png", "mine.py:Mine")
    with pytest.raises(ConfigError, match=r"rows of the map '\./maps//rooms\.png' under the name 'maps/rooms\.png'"):
        run("./maps//rooms.png", "mine.py:Mine")
    assert len(_rows(out)) == 2
    with pytest.raises(ConfigError, match=r"rows of the map '/.*/maps/rooms\.png' under the name 'maps/rooms\.png'"):
        run(str(tmp_path / "maps" / "rooms.png"), "mine.py:Mine")
    with pytest.raises(ConfigError, match=r"results of 'mine\.py:Mine', which '\./mine\.py:Mine' writes another way"):
        run("maps/rooms.png", "./mine.py:Mine")
    assert len(_rows(out)) == 2


def test_a_folder_of_other_files_is_refused(tmp_path: Path) -> None:
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("keep me")
    with pytest.raises(ConfigError, match="holds other files"):
        evaluate(_config(), out, backend="serial", progress=False)
    assert [p.name for p in out.iterdir() if p.name != ".lock"] == ["notes.txt"]


def test_short_labels_stay_unique() -> None:
    labels = short_labels(["fixed:0.75", "learned:runs/a/model.zip", "learned:runs/b/model.zip", "learned:m5.zip"])
    assert labels == {
        "fixed:0.75": "fixed:0.75", "learned:runs/a/model.zip": "learned:runs/a/model.zip",
        "learned:runs/b/model.zip": "learned:runs/b/model.zip", "learned:m5.zip": "learned:m5",
    }  # fmt: skip
    assert short_labels(["office", "maps/house.yaml"]) == {"office": "office", "maps/house.yaml": "house"}
    assert short_labels(["/a/long/folder/mine.py:Greedy@2"]) == {
        "/a/long/folder/mine.py:Greedy@2": "mine.py:Greedy ×2 uncoordinated"
    }


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["--methods", "nearest,bogus"], "unknown policy 'bogus'"),
        (["--methods", "learned:missing.zip"], "missing.zip"),
        (["--methods", "nearest", "--worlds", "atlantis"], "unknown world 'atlantis'"),
        (["--methods", "nearest", "--episodes", "0"], "episodes must be a positive integer"),
        (["--methods", "nearest", "--backend", "mpi"], "--backend must be one of serial, process, ray, got 'mpi'"),
        (["--methods", "nearest", "--workers", "0"], "--workers must be a positive integer"),
        (["--methods", "nearest", "--workers", "1000"], "--workers must be at most 256"),
        (["--methods", "nearest", "--outliers", "1000,abc"], "outlier thresholds"),
        (["--methods", "nearest", "--backend", "ray", "--ray-address", "127.0.0.1:1"], "does not answer"),
    ],
)
def test_bad_input_is_one_line_and_writes_nothing(tmp_path: Path, args: list[str], needle: str) -> None:
    if "ray" in args:
        pytest.importorskip("ray")
    out = tmp_path / "out"
    result = runner.invoke(app, ["evaluate", "--out", str(out), "--no-progress", *args])
    assert result.exit_code == 2, result.output
    assert needle in result.output and len(result.output.strip().splitlines()) == 1, result.output
    assert not out.exists()


def test_a_ray_node_that_does_not_start_is_one_line(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Ray raises a bare Exception when its local node does not start within 30 s (a loaded machine):
    it was a traceback."""
    ray = pytest.importorskip("ray")

    def slow_node(*args: object, **kwargs: object) -> None:
        raise Exception("The current node timed out during startup. This could happen because ...")

    monkeypatch.setattr(ray, "init", slow_node)
    args = ["--methods", "nearest", "--backend", "ray", "--episodes", "1", "--workers", "1", "--no-oracle"]
    result = runner.invoke(app, ["evaluate", "--out", str(tmp_path / "out"), "--no-progress", *args])
    assert result.exit_code == 2, result.output
    assert result.output.strip() == (
        "error: Ray could not start or reach a local instance: The current node timed out during startup. "
        "This could happen because ..."
    )


def test_outlier_thresholds_parse() -> None:
    assert parse_thresholds("1000, 2000") == (1000.0, 2000.0)
    assert parse_thresholds("") == ()
    with pytest.raises(ConfigError):
        parse_thresholds("-5")


def test_unknown_baseline_duplicates_and_negative_seeds_are_refused() -> None:
    with pytest.raises(ConfigError, match=r"written two ways\): nearest@2, nearest@2:uncoordinated$"):
        ExperimentConfig(methods=("fixed:0.75", "nearest@2", "nearest@2:uncoordinated"), worlds=("office",), episodes=1)
    with pytest.raises(ConfigError, match="worlds are listed twice"):
        ExperimentConfig(methods=("fixed:0.75",), worlds=("office", "office"), episodes=1)
    with pytest.raises(ConfigError, match="seed must be a non-negative integer"):
        ExperimentConfig(methods=("fixed:0.75",), worlds=("office",), episodes=1, seed=-1)
    with pytest.raises(ConfigError, match="baseline"):
        ExperimentConfig(methods=("nearest",), worlds=("office",), episodes=1)
    with pytest.raises(ConfigError, match="twice"):
        ExperimentConfig(methods=("fixed:0.75", "fixed:0.75"), worlds=("office",), episodes=1)
    for one, other in (("fixed:1", "fixed:1.0"), ("tour", "tour:10"), ("mine.py:X", "./mine.py:X")):
        with pytest.raises(ConfigError, match=f"written two ways\\): {re.escape(one)}, {re.escape(other)}$"):
            ExperimentConfig(methods=(one, other), worlds=("office",), episodes=1, baseline=one)
    config = ExperimentConfig(
        methods=("nearest",), worlds=("office",), episodes=np.int64(2), seed=np.int64(3), baseline="nearest"
    )
    assert (config.episodes, config.seed) == (2, 3) and type(config.episodes) is int and type(config.seed) is int
    with pytest.raises(UnknownNameError):
        expand_worlds("office,nowhere/")


def test_an_experiment_too_large_to_list_is_refused_before_any_work() -> None:
    """Its job list is built whole: 10¹² episodes took the machine's memory before this check."""
    with pytest.raises(ConfigError, match="1,000,000,000,000 episodes on 1 world"):
        ExperimentConfig(methods=("fixed:0.75",), worlds=("office",), episodes=10**12)
    ExperimentConfig(methods=("fixed:0.75", "nearest"), worlds=("office",), episodes=MAX_JOBS // 2)


def test_a_folder_in_use_by_another_run_is_refused(tmp_path: Path) -> None:
    config = _config()
    first = ResultStore(tmp_path / "exp", identity(config))
    with pytest.raises(ConfigError, match="another run is writing"):
        evaluate(config, tmp_path / "exp", backend="serial", progress=False)
    first.close()
    evaluate(config, tmp_path / "exp", backend="serial", progress=False)  # free again
    assert len(_rows(tmp_path / "exp")) == 4


def test_a_corrupt_results_file_is_a_clear_error(serial_run: Path, tmp_path: Path) -> None:
    out = tmp_path / "corrupt"
    out.mkdir()
    for name in ("experiment.json", "episodes.csv", "traces.jsonl"):
        (out / name).write_bytes((serial_run / name).read_bytes())
    lines = (out / "episodes.csv").read_text().splitlines()
    lines[2] = lines[2].replace(",True,", ",yes,", 1)
    (out / "episodes.csv").write_text("\n".join(lines) + "\n")
    with pytest.raises(ConfigError, match="truncated 'yes' is not valid"):
        evaluate(_config(), out, backend="serial", progress=False)
