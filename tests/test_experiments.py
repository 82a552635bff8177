"""The paired comparison script behind the README's results table."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

SCRIPT = Path(__file__).resolve().parents[1] / "experiments" / "compare_methods.py"


def _run(out: Path) -> str:
    args = [sys.executable, str(SCRIPT), "--methods", "nearest,fixed:0.9", "--episodes", "2", "--first-seed", "5",
            "--workers", "1", "--out", str(out)]  # fmt: skip
    return subprocess.run(args, capture_output=True, text=True, check=True, timeout=300).stdout


def test_paired_statistics_and_resume(tmp_path: Path) -> None:
    out = tmp_path / "cmp"
    first = _run(out)
    assert first.startswith("6 episodes to run")
    summary = json.loads((out / "summary.json").read_text())
    assert summary["baseline"] == "fixed:0.75" and summary["episodes"] == 2
    nearest = summary["methods"]["nearest"]
    for key in ("n", "mean_time_s", "var_time_s", "mean_diff_s", "ci95_s", "p_one_tailed", "p_two_tailed",
                "reduction_pct"):  # fmt: skip
        assert key in nearest
    rows = [json.loads(line) for line in (out / "episodes.jsonl").read_text().splitlines()]
    assert len(rows) == 6 and {r["seed"] for r in rows} == {5, 6}
    base = {r["seed"]: r["sim_time_s"] for r in rows if r["method"] == "fixed:0.75"}
    other = {r["seed"]: r["sim_time_s"] for r in rows if r["method"] == "nearest"}
    diff = sum(base[s] - other[s] for s in (5, 6)) / 2
    assert abs(nearest["mean_diff_s"] - diff) < 1e-9
    again = _run(out)
    assert again.startswith("0 episodes to run (6 already")
    assert len((out / "episodes.jsonl").read_text().splitlines()) == 6
    assert "| nearest |" in (out / "table.md").read_text()
