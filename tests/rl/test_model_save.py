"""Model files are replaced whole or not at all (issue 14, class 5): a full disk while saving or
re-tagging a model leaves the previous file as it was."""

from __future__ import annotations

import errno
import os
import shutil
from dataclasses import replace
from pathlib import Path

import pytest
from stable_baselines3 import A2C

from frontier_rl import atomic_write
from frontier_rl.atomic_write import OutputWriteError
from frontier_rl.inference.model_file import read_metadata
from frontier_rl.rl.model_file import save_model, write_metadata

MODEL4 = Path(__file__).resolve().parents[2] / "models" / "model4.zip"


def _full_disk(monkeypatch: pytest.MonkeyPatch) -> None:
    def write_all(fd: int, data: bytes) -> None:
        os.write(fd, data[: len(data) // 2])
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(atomic_write, "write_all", write_all)


@pytest.mark.parametrize("action", ["write_metadata", "save_model", "save_model_bare"])
def test_a_full_disk_leaves_the_previous_model_file_whole(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, action: str
) -> None:
    path = tmp_path / "model.zip"
    shutil.copy(MODEL4, path)
    before = path.read_bytes()
    info = read_metadata(path)
    assert info is not None
    model = A2C.load(str(MODEL4), device="cpu")  # the project's own file: trusted
    _full_disk(monkeypatch)
    with pytest.raises(OutputWriteError, match="No space left on device"):
        if action == "write_metadata":
            write_metadata(path, replace(info, timesteps=1))
        else:
            save_model(model, path, info if action == "save_model" else None)
    assert path.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["model.zip"]  # no temporary file left


def test_a_saved_model_reads_back_with_its_metadata(tmp_path: Path) -> None:
    info = read_metadata(MODEL4)
    assert info is not None
    path = tmp_path / "again.zip"
    save_model(A2C.load(str(MODEL4), device="cpu"), path, replace(info, timesteps=7))
    assert read_metadata(path) == replace(info, timesteps=7)
