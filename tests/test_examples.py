"""The scripts in examples/, each run as a user runs it (a subprocess, from another folder) with tiny settings."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow  # each trains, evaluates in worker processes or runs several episodes

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def _run(script: str, args: list[str], cwd: Path) -> subprocess.CompletedProcess[str]:
    command = [sys.executable, str(EXAMPLES / script), *args]
    return subprocess.run(command, cwd=cwd, capture_output=True, text=True, timeout=300)


def test_custom_policy_is_compared_with_nearest_and_model_7(tmp_path: Path) -> None:
    args = ["--episodes", "1", "--worlds", "office", "--max-time", "60", "--workers", "2", "--no-oracle"]
    run = _run("custom_policy.py", [*args, "--out", "results"], tmp_path)
    assert run.returncode == 0, run.stderr
    lines = run.stdout.splitlines()
    assert lines[0] == "1 episode(s) on office; baseline nearest"
    assert [line.split(":")[0].strip() for line in lines[1:4]] == ["nearest", "size-per-metre", "model7"]
    assert "(baseline)" in lines[1] and "saves" in lines[2] and "p = " in lines[3]
    summary = json.loads((tmp_path / "results/summary.json").read_text())
    policy_file = next(m for m in summary["methods"] if m.endswith("custom_policy.py:SizePerMetre"))
    assert (tmp_path / policy_file.rpartition(":")[0]).resolve() == EXAMPLES / "custom_policy.py"


def test_train_on_maps_trains_on_the_catalogue_and_evaluates_on_held_out_maps(tmp_path: Path) -> None:
    args = ["--timesteps", "16", "--n-envs", "1", "--test-maps", "dungeon/easy/img_10", "--max-time", "60"]
    run = _run("train_on_maps.py", [*args, "--out", "run"], tmp_path)
    assert run.returncode == 0, run.stderr
    assert "model: run/training/model.zip" in run.stdout
    assert "1 test map(s), 1 paired episodes" in run.stdout and "nearest: 60.0 s; model 7:" in run.stdout
    config = (tmp_path / "run/training/config.yaml").read_text()
    assert "worlds: dungeon/train" in config and "model: 7" in config


def test_team_runs_every_strategy_and_a_failure(tmp_path: Path) -> None:
    run = _run("team.py", ["--robots", "2", "--max-time", "60", "--fail", "1@30"], tmp_path)
    assert run.returncode == 0, run.stderr
    lines = run.stdout.splitlines()
    assert [line.split(":")[0].strip() for line in lines] == ["one robot", "uncoordinated", "coordinated", "rendezvous"]
    assert all("each robot saw" in line and "1 failed" in line for line in lines[1:])


def test_a_bad_argument_is_one_line(tmp_path: Path) -> None:
    run = _run("team.py", ["--robots", "9"], tmp_path)
    assert run.returncode == 1 and run.stderr == "error: robots must be 1 to 8, got 9\n"
