"""Tests of frontier_rl.run_folders: a command refuses a folder another kind of run holds."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from frontier_rl.cli import app
from frontier_rl.errors import ConfigError
from frontier_rl.evaluation.results.identity import ExperimentIdentity
from frontier_rl.evaluation.results.store import ResultStore
from frontier_rl.run_folders import RunKind, refuse_other_runs, run_kind


def _training_run(folder: Path) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "config.yaml").write_text("model: 7\n")
    (folder / "checkpoints").mkdir()
    return folder


def _evaluation(folder: Path) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "experiment.json").write_text("{}\n")
    return folder


def test_a_folder_is_told_by_the_files_its_run_writes_first(tmp_path: Path) -> None:
    assert run_kind(tmp_path / "missing") is None
    assert run_kind(tmp_path) is None
    (tmp_path / "config.yaml").write_text("x: 1\n")  # a config.yaml alone may be anyone's
    assert run_kind(tmp_path) is None
    assert run_kind(_training_run(tmp_path / "train")) is RunKind.TRAINING
    assert run_kind(_evaluation(tmp_path / "eval")) is RunKind.EVALUATION
    (tmp_path / "downloaded").mkdir()
    (tmp_path / "downloaded" / "model.zip").write_bytes(b"PK")  # a model file alone is a run's to keep
    assert run_kind(tmp_path / "downloaded") is RunKind.TRAINING
    demo = _evaluation(tmp_path / "demo" / "experiment").parent
    assert run_kind(demo) is RunKind.DEMO  # interrupted before its config.yaml, written last
    (demo / "config.yaml").write_text("robot: {}\n")
    assert run_kind(demo) is RunKind.DEMO


def test_a_demo_refused_for_its_options_keeps_the_last_demos_results(tmp_path: Path) -> None:
    """It deleted OUT/experiment, then refused --workers 0, and then its own folder ("config.yaml,
    not written by the demo")."""
    demo = _evaluation(tmp_path / "demo" / "experiment").parent
    (demo / "config.yaml").write_text("robot: {}\n")
    result = CliRunner().invoke(app, ["demo", "--out", str(demo), "--workers", "0", "--no-progress"])
    assert result.exit_code == 2 and "--workers" in result.output
    assert (demo / "experiment" / "experiment.json").exists() and run_kind(demo) is RunKind.DEMO


def test_the_demo_rewrites_only_its_own_folder(tmp_path: Path) -> None:
    """It deleted OUT/experiment whatever it held and wrote its config.yaml over a training run's."""
    refuse_other_runs(tmp_path / "new", RunKind.DEMO)
    with pytest.raises(ConfigError, match="holds a training run; choose another folder for the demo"):
        refuse_other_runs(_training_run(tmp_path / "train"), RunKind.DEMO)
    notes = tmp_path / "notes"
    (notes / "experiment").mkdir(parents=True)
    (notes / "experiment" / "precious.txt").write_text("mine")
    with pytest.raises(ConfigError, match="holds experiment, not written by the demo"):
        refuse_other_runs(notes, RunKind.DEMO)
    (notes / "config.yaml").write_text("x: 1\n")
    with pytest.raises(ConfigError, match=r"holds config\.yaml and experiment, not written by the demo"):
        refuse_other_runs(notes, RunKind.DEMO)


def test_another_kind_of_run_is_refused_naming_the_folder(tmp_path: Path) -> None:
    evaluation = _evaluation(tmp_path / "eval")
    with pytest.raises(ConfigError, match="eval' holds an evaluation's results; choose another folder for a training"):
        refuse_other_runs(evaluation, RunKind.TRAINING)
    refuse_other_runs(evaluation, RunKind.EVALUATION)  # its own kind: the command checks the rest
    refuse_other_runs(tmp_path / "new", RunKind.TRAINING)


def test_an_evaluation_is_not_written_into_a_training_run(tmp_path: Path) -> None:
    """Its rows and report went in among the run's config.yaml and checkpoints."""
    run = _training_run(tmp_path / "run")
    before = sorted(p.name for p in run.iterdir())
    identity = ExperimentIdentity.from_json(
        {"seed": 0, "worlds": ["office"], "resolution": None, "sim": {}, "methods": {"nearest": "nearest"}}
    )
    with pytest.raises(ConfigError, match="holds a training run"):
        ResultStore(run, identity)
    assert sorted(p.name for p in run.iterdir()) == before
