"""Fixtures of the user-policy tests."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.policies.user_code import GREEDY


@pytest.fixture
def policy_dir(tmp_path: Path) -> Path:
    """A folder outside the repository with the user's policy file ``greedy.py``."""
    folder = tmp_path / "user code"  # a blank in the path, as users' folders have
    folder.mkdir()
    (folder / "greedy.py").write_text(GREEDY)
    return folder
