"""The benchmark script keeps up with the engine's API (it is not run by the suite otherwise: its
timings belong to ``make bench``). A smoke run of its cheapest parts."""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
import time
from pathlib import Path
from types import ModuleType

import pytest

pytestmark = pytest.mark.slow  # the benchmark scripts, run whole

SCRIPT = Path(__file__).resolve().parents[1] / "benchmarks" / "run.py"
MODELS = SCRIPT.parents[1] / "models"


@pytest.fixture(scope="module")
def bench() -> ModuleType:
    spec = importlib.util.spec_from_file_location("frontier_rl_bench", SCRIPT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look their module up
    spec.loader.exec_module(module)
    return module


def test_the_frontier_benchmark_runs_and_tabulates(bench: ModuleType) -> None:
    rows = bench.bench_frontiers(1)
    assert len(rows) == 4 and all(row.value > 0 for row in rows)
    assert bench.table(rows).count("\n") == len(rows) + 1


def test_the_json_report_keeps_six_significant_digits(bench: ModuleType) -> None:
    payload = {"runtime_s": 107.84208977900562, "results": [{"value": 0.08563399751437828, "target": 10, "ok": True}]}
    assert bench.rounded(payload) == {"runtime_s": 107.842, "results": [{"value": 0.085634, "target": 10, "ok": True}]}


def test_the_large_map_rows_are_skipped_without_the_real_maps(bench: ModuleType, tmp_path: Path) -> None:
    assert bench.bench_large_map(1, tmp_path) == []


def test_the_decision_benchmark_runs_every_policy(bench: ModuleType) -> None:
    from frontier_rl.core.world.catalog import generate_world

    rows = bench.bench_decisions(1, 1, MODELS / "model5.zip", {"office": generate_world("office", 0)})
    names = " ".join(row.metric for row in rows)
    assert all(
        what in names for what in ("`nearest` decision", "Model-5 decision", "Model-7 decision", "`tour` decision")
    )
    assert all(row.value > 0 for row in rows)


def test_the_process_benchmark_times_help_a_small_explore_and_the_floors_under_them(bench: ModuleType) -> None:
    rows = bench.bench_processes(1)
    assert [row.target for row in rows] == [0.3, None, None, 0.8, None, None]
    assert [row.unit for row in rows] == ["s", "s", "×", "s", "s", "×"]
    assert rows[1].metric.startswith("floor:") and "--help" in rows[1].metric
    assert rows[4].metric.startswith("floor:") and "numba" in rows[4].metric
    assert all(0 < row.value < 60 and not row.higher_is_better for row in rows)
    assert rows[2].value == pytest.approx(rows[0].value / rows[1].value)  # one round: the ratio of its two times
    assert rows[5].value == pytest.approx(rows[3].value / rows[4].value)


def test_a_timed_process_is_waited_for_not_polled_and_one_that_fails_or_hangs_is_an_error() -> None:
    from benchmarks.startup import exact_wall_seconds

    environment = dict(os.environ)
    assert exact_wall_seconds([sys.executable, "-c", "import time; time.sleep(0.2)"], environment) >= 0.2
    with pytest.raises(subprocess.CalledProcessError):
        exact_wall_seconds([sys.executable, "-c", "raise SystemExit(3)"], environment)
    started = time.perf_counter()
    with pytest.raises(subprocess.CalledProcessError):  # killed at its limit
        exact_wall_seconds([sys.executable, "-c", "import time; time.sleep(60)"], environment, limit_s=0.5)
    assert time.perf_counter() - started < 30
