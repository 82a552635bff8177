"""Shared test fixtures."""

from __future__ import annotations

from pathlib import Path

import pytest

_REPO_ROOT = Path(__file__).resolve().parents[1]
#: Where the development maps live: beside the checkout, or inside it on some machines.
_SHARED_MAPS_CANDIDATES = (_REPO_ROOT.parent / "shared" / "maps", _REPO_ROOT / "shared" / "maps")


@pytest.fixture(scope="session")
def shared_maps() -> Path:
    """The folder of real maps (``../shared/maps``); skips the test where it is missing."""
    for candidate in _SHARED_MAPS_CANDIDATES:
        if candidate.is_dir():
            return candidate
    pytest.skip(f"shared maps not found at {_SHARED_MAPS_CANDIDATES[0]}")
