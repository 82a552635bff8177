"""The kinds of folder the commands write their runs into (``--out``), told apart by the files each
writes first, so that a command refuses a folder another kind of run holds rather than mixing its
files with that run's (a training run's ``config.yaml`` and checkpoints among an evaluation's rows).
"""

from __future__ import annotations

from enum import StrEnum
from pathlib import Path

from frontier_rl.errors import ConfigError, short_path


class RunKind(StrEnum):
    """What a run folder holds, as a message names it."""

    EVALUATION = "an evaluation's results"
    TRAINING = "a training run"
    DEMO = "the demo's output"


_EVALUATION_FILES = ("experiment.json", "episodes.csv")
"""An evaluation writes ``experiment.json`` before its first row, and ``episodes.csv`` with it."""

_TRAINING_CONFIG = "config.yaml"
_TRAINING_FILES = ("checkpoints", "tb", "training_time.txt")
"""A training run writes ``config.yaml`` first, then one of these (a ``config.yaml`` alone may be
anyone's)."""

_TRAINED_FILES = ("model.zip", "checkpoints")
"""What a training run leaves that another run must not overwrite, even without its ``config.yaml``
(a model file downloaded into a folder)."""

_DEMO_FILES = ("config.yaml", "experiment")
"""The demo's settings and its evaluation's folder, which it rewrites."""


def run_kind(folder: Path) -> RunKind | None:
    """The kind of run ``folder`` holds, or None (no folder, an empty one, or other files)."""
    if _holds_evaluation(folder):
        return RunKind.EVALUATION
    trained = any((folder / name).exists() for name in _TRAINED_FILES)
    if trained or ((folder / _TRAINING_CONFIG).is_file() and any((folder / n).exists() for n in _TRAINING_FILES)):
        return RunKind.TRAINING
    if _holds_evaluation(folder / "experiment"):  # its config.yaml is written last
        return RunKind.DEMO
    return None


def _holds_evaluation(folder: Path) -> bool:
    return any((folder / name).exists() for name in _EVALUATION_FILES)


def refuse_other_runs(folder: Path, kind: RunKind, option: str = "--out") -> None:
    """Nothing, unless ``folder`` holds a run of a kind other than ``kind``.

    Raises:
        ConfigError: naming the folder and what it holds.
    """
    held = run_kind(folder)
    if held is not None and held is not kind:
        raise ConfigError(f"{option} {short_path(folder)} holds {held}; choose another folder for {kind}")
    if kind is RunKind.DEMO and held is None and any((folder / name).exists() for name in _DEMO_FILES):
        names = " and ".join(name for name in _DEMO_FILES if (folder / name).exists())
        raise ConfigError(
            f"{option} {short_path(folder)} holds {names}, not written by the demo (which rewrites them); "
            "choose another folder for the demo"
        )
