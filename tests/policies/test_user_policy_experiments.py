"""A policy file of the user's in ``frontier-rl evaluate``: beside ``nearest`` and as a team, run by the
spawned process-pool workers, named by its spec in the report, and fingerprinted by its content."""

from __future__ import annotations

import json
import shlex
from pathlib import Path

import pytest
from typer.testing import CliRunner

from frontier_rl.cli import app

pytestmark = pytest.mark.slow  # whole experiments in worker processes

runner = CliRunner()

GREEDY = '''
import numpy as np
from frontier_rl import Ranking


class Greedy:
    """The largest frontier per metre to drive."""

    name = "greedy"

    def rank(self, context, rng):
        frontiers = context.frontiers
        return Ranking(np.argsort(-frontiers.sizes / (1.0 + frontiers.distances), kind="stable"))
'''


def test_evaluate_runs_a_relative_policy_file_beside_nearest(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "greedy.py").write_text(GREEDY)
    monkeypatch.chdir(tmp_path)  # the spec is relative: it resolves against the working folder (Path.cwd())
    args = shlex.split(
        "evaluate --methods greedy.py:Greedy,greedy.py:Greedy@2:coordinated --baseline nearest --out results "
        "--episodes 2 --max-time 90 --no-oracle --pictures 0 --backend process --workers 2 --no-progress"
    )
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    summary = json.loads((tmp_path / "results/summary.json").read_text())
    assert list(summary["methods"]) == ["nearest", "greedy.py:Greedy", "greedy.py:Greedy@2:coordinated"]
    assert summary["methods"]["greedy.py:Greedy@2:coordinated"]["robots"] == 2
    report = (tmp_path / "results/report.md").read_text()
    assert "| greedy.py:Greedy | A user policy: The largest frontier per metre to drive. | Greedy from file" in report
    identity = json.loads((tmp_path / "results/experiment.json").read_text())
    assert identity["methods"]["greedy.py:Greedy"].startswith("greedy.py:Greedy#sha256:")

    (tmp_path / "greedy.py").write_text(GREEDY.replace("1.0 +", "2.0 +"))  # another policy under the same spec
    rerun = runner.invoke(app, args)
    assert rerun.exit_code == 2 and "holds results of 'greedy.py:Greedy'" in rerun.output, rerun.output
