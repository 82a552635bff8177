"""Warnings raised in a worker process come back to the parent, where the command line prints
them one line each (issue 14, class 6): a worker's stderr is not the command's."""

from __future__ import annotations

import warnings
from typing import Any

import pytest

from frontier_rl.evaluation.running import backends


class PolicyWarning(UserWarning):
    """A category of a module this process has loaded (a user policy's, say)."""


def test_a_workers_warnings_are_raised_again_in_the_parent_in_their_own_category() -> None:
    """A MapWarning came back as a UserWarning, which a filter on MapWarning let through."""
    row = {"method": "nearest"}
    caught = [
        ("builtins", "RuntimeWarning", "overflow in exp"),
        (__name__, "PolicyWarning", "seed reused"),
        ("numba_not_loaded_here", "NumbaPerformanceWarning", "slow loop"),
        ("frontier_rl.errors", "MapWarning", "/abs/m.yaml: field 'extra' ignored"),  # the parent read it already
    ]
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        assert backends._warn_again((row, caught)) is row
    assert [(w.category, str(w.message)) for w in seen] == [
        (RuntimeWarning, "overflow in exp"),
        (PolicyWarning, "seed reused"),
        (UserWarning, "NumbaPerformanceWarning: slow loop"),  # a category not loaded here: named in the text
    ]


@pytest.mark.parametrize("category", [RuntimeWarning, DeprecationWarning, UserWarning])
def test_a_worker_records_what_its_episode_warned(monkeypatch: pytest.MonkeyPatch, category: type[Warning]) -> None:
    def run_job(job: Any, settings: Any) -> dict[str, Any]:
        warnings.warn("careful", category, stacklevel=1)
        return {"episode": job}

    monkeypatch.setattr(backends, "run_job", run_job)
    row, caught = backends.run_job_catching_warnings(3, None)  # type: ignore[arg-type]
    assert row == {"episode": 3} and caught == [("builtins", category.__name__, "careful")]
