"""The scripts in examples/, each run as a user runs it (a subprocess, from another folder) with tiny settings."""

from __future__ import annotations

import importlib.util
import json
import subprocess
import sys
from pathlib import Path
from types import ModuleType

import pytest

from frontier_rl import ConfigError, TeamConfig

pytestmark = pytest.mark.slow  # each trains, evaluates in worker processes or runs several episodes

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def _run(script: str, args: list[str], cwd: Path) -> subprocess.CompletedProcess[str]:
    command = [sys.executable, str(EXAMPLES / script), *args]
    return subprocess.run(command, cwd=cwd, capture_output=True, text=True, timeout=300)


def _example(script: str) -> ModuleType:
    """An example imported as a module (its main() does not run)."""
    spec = importlib.util.spec_from_file_location(f"example_{Path(script).stem}", EXAMPLES / script)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_custom_policy_is_compared_with_nearest_and_model_7(tmp_path: Path) -> None:
    # --workers 1: the episodes one after another in the script's own process, no worker to start
    args = ["--episodes", "1", "--worlds", "office", "--max-time", "60", "--workers", "1", "--no-oracle"]
    run = _run("custom_policy.py", [*args, "--out", "results"], tmp_path)
    assert run.returncode == 0, run.stderr
    lines = run.stdout.splitlines()
    assert lines[0] == "1 episode(s) on office; baseline nearest"
    assert [line.split(":")[0].strip() for line in lines[1:4]] == ["nearest", "size-per-metre", "model7"]
    assert "(baseline)" in lines[1] and "saves" in lines[2] and "p = " in lines[3]
    summary = json.loads((tmp_path / "results/summary.json").read_text())
    # the policy's name holds the script's absolute path: the same from any working folder, so a rerun resumes
    policy = f"{EXAMPLES / 'custom_policy.py'}:SizePerMetre"
    assert list(summary["methods"]) == ["nearest", policy, f"learned:{EXAMPLES.parent / 'models/model7.zip'}"]


def test_custom_policy_leaves_out_model_7_with_a_line_only_where_it_is_missing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    example = _example("custom_policy.py")
    assert example.compared_model(None) == EXAMPLES.parent / "models/model7.zip"
    assert capsys.readouterr().err == ""
    monkeypatch.setattr(example, "MODEL_7", tmp_path / "model7.zip")  # as in a copy of the script alone
    assert example.compared_model(None) is None
    left_out = f"model 7 left out: no {tmp_path / 'model7.zip'} (--model names another model file)\n"
    assert capsys.readouterr().err == left_out


def test_train_on_maps_trains_on_the_catalogue_and_evaluates_on_held_out_maps(tmp_path: Path) -> None:
    args = ["--timesteps", "16", "--n-envs", "1", "--test-maps", "dungeon/easy/img_10", "--max-time", "60"]
    args += ["--workers", "1"]  # the test episodes in the process that trained: torch and the kernels are loaded
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


@pytest.mark.parametrize(
    ("script", "args", "error"),
    [
        ("team.py", ["--robots", "9"], "error: robots must be 1 to 8, got 9"),
        ("custom_policy.py", ["--model", "missing.zip"], "error: --model 'missing.zip' is not a file"),
        ("train_on_maps.py", ["--model", "9"], "error: unknown model 9; choose one of 1, 2, 3, 4, 5, 6, 7"),
    ],
)
def test_bad_input_ends_with_one_error_line_and_exit_code_2(
    script: str, args: list[str], error: str, tmp_path: Path
) -> None:
    run = _run(script, args, tmp_path)
    assert (run.returncode, run.stderr) == (2, error + "\n")


def test_the_team_size_in_the_help_is_the_one_accepted_and_a_bad_argument_is_one_line(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    team = _example("team.py")
    monkeypatch.setattr(sys, "argv", ["team.py", "--help"])
    with pytest.raises(SystemExit):
        team.main()
    assert "team size, 1 to 8" in " ".join(capsys.readouterr().out.split())
    TeamConfig(1)  # the smallest team is accepted
    with pytest.raises(ConfigError, match="robots must be 1 to 8"):
        TeamConfig(9)
    monkeypatch.setattr(sys, "argv", ["team.py", "--robots", "two"])
    with pytest.raises(SystemExit) as exited:
        team.main()
    assert (exited.value.code, capsys.readouterr().err) == (2, "error: argument --robots: invalid int value: 'two'\n")
