"""The weight-sweep script behind the README's analysis of model 4."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

SCRIPT = Path(__file__).resolve().parents[1] / "experiments" / "weight_sweep.py"


def test_sweep_analysis_matches_the_rows(tmp_path: Path) -> None:
    out = tmp_path / "sweep"
    args = [sys.executable, str(SCRIPT), "--methods", "nearest", "--episodes", "2", "--seed", "5", "--max-time", "60",
            "--workers", "2", "--out", str(out)]  # fmt: skip
    subprocess.run(args, capture_output=True, text=True, check=True, timeout=300)
    summary = json.loads((out / "summary.json").read_text())
    assert len(summary["methods"]) == 23  # fixed:0.75 first, nearest, the other 20 weights, the oracle
    sweep = summary["sweep"]
    best = f"{sweep['best_weight']:.2f}"
    assert sweep["best_mean_time_s"] == summary["methods"][f"fixed:{best}"]["mean_time_s"]
    assert sum(sweep["per_world_best_weight_counts"].values()) == 2
    assert sweep["per_world_oracle_mean_time_s"] <= sweep["best_mean_time_s"]
    assert (out / "report.html").exists()
