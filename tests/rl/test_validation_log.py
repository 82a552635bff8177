"""A training run's validation log: what is appended reads back, and a damaged log is named with
its bad line, not a traceback, when a run resumes or draws its curve."""

from __future__ import annotations

from pathlib import Path

import pytest

from frontier_rl.errors import ConfigError
from frontier_rl.rl.curves import plot_learning_curve
from frontier_rl.rl.validation_log import VALIDATION_FILE, Validation, append_validation, read_validations


def test_validations_appended_read_back_as_written(tmp_path: Path) -> None:
    path = tmp_path / VALIDATION_FILE
    assert read_validations(path) == []
    append_validation(path, Validation(32, 301.23456, (300.04, 302.43)))
    append_validation(path, Validation(64, 250.0, ()))
    assert path.read_text().splitlines() == ["timesteps,mean_time_s,times", "32,301.235,300.0 302.4", "64,250.000,"]
    assert read_validations(path) == [Validation(32, 301.235, (300.0, 302.4)), Validation(64, 250.0, ())]


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("timesteps,mean_time_s,times\n32,fast,300.0\n", "line 2 is not a validation"),
        ("timesteps,mean_time_s,times\n32,300.0,300.0\n64\n", "line 3 is not a validation"),
        ("steps,mean\n1,2\n", "line 2 is not a validation"),
        (b"\xff\xfe\x00".decode("latin-1"), "is not a validation log"),
    ],
)
def test_a_damaged_log_is_named_with_its_line(tmp_path: Path, text: str, needle: str) -> None:
    path = tmp_path / VALIDATION_FILE
    path.write_text(text, encoding="latin-1")
    with pytest.raises(ConfigError, match=needle):
        read_validations(path)
    with pytest.raises(ConfigError, match=needle):
        plot_learning_curve(tmp_path)
