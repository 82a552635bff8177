"""TrainConfig's cell size for map files (checked, saved with the run, and handed to every env) and
its algorithm (a member of one enum, from Python's text, a file's or the command line's)."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from frontier_rl.cli import app
from frontier_rl.errors import ConfigError
from frontier_rl.registration import Algorithm
from frontier_rl.rl.config import TrainConfig


def test_the_resolution_reaches_every_env_and_is_saved_with_the_run(tmp_path: Path) -> None:
    from frontier_rl.rl.train import _env_kwargs

    config = TrainConfig(worlds="houseexpo", resolution=0.08)
    assert _env_kwargs(config)["resolution"] == 0.08
    assert "resolution" not in _env_kwargs(TrainConfig())  # a run without it makes its envs as before
    config.dump(tmp_path / "config.yaml")
    assert TrainConfig.load(tmp_path / "config.yaml") == config
    assert "--resolution 0.08" in config.command()


@pytest.mark.parametrize("value", [0.0, -0.05, 0.5, float("nan")])
def test_a_resolution_no_world_can_use_is_refused_naming_it(value: float) -> None:
    with pytest.raises(ConfigError, match="resolution"):
        TrainConfig(resolution=value)


def test_the_command_takes_it_and_refuses_a_bad_one_in_one_line(tmp_path: Path) -> None:
    result = CliRunner().invoke(app, ["train", "--out", str(tmp_path / "run"), "--resolution", "2"])
    assert result.exit_code == 2
    assert result.stderr.count("\n") == 1 and "--resolution" in result.stderr, result.stderr
    assert not (tmp_path / "run").exists()


def test_the_algorithm_is_a_member_from_text_saved_and_read_back_as_one(tmp_path: Path) -> None:
    config = TrainConfig(model=5, algo="dagger")  # type: ignore[arg-type]  # Python callers may give the text
    assert config.algo is Algorithm.DAGGER
    config.dump(tmp_path / "config.yaml")
    assert "algo: dagger\n" in (tmp_path / "config.yaml").read_text()
    loaded = TrainConfig.load(tmp_path / "config.yaml")
    assert loaded == config and loaded.algo is Algorithm.DAGGER
    assert "--algo dagger" in config.command()
    with pytest.raises(ConfigError, match="algo must be one of a2c, ppo, dagger, got 'sac'"):
        TrainConfig(algo="sac")  # type: ignore[arg-type]
    (tmp_path / "bad.yaml").write_text("algo: 3\n")
    with pytest.raises(ConfigError, match="algo must be one of a2c, ppo, dagger, got 3"):
        TrainConfig.load(tmp_path / "bad.yaml")
