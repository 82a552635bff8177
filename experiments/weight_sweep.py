"""How the best fixed weight of eq. 3.1 varies between worlds (the issue-3 analysis of model 4).

Runs ``frontier-rl evaluate`` with the 21 fixed weights 0.00, 0.05, ..., 1.00 (and any other
methods given) on the same worlds, then adds to ``OUT/summary.json`` a ``sweep`` entry: the best
weight on average, each world's best weight in hindsight and the mean time of that per-world
oracle (optimistic: it also picks each world's luckiest noise).

    .venv/bin/python experiments/weight_sweep.py --methods learned:models/model4.zip,learned:models/model5.zip \
        --worlds office --episodes 100 --out results/office_sweep
"""

from __future__ import annotations

import argparse
import json
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from frontier_rl.atomic_write import write_text_atomic
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.evaluation.results.episode_record import EpisodeKey, EpisodeRow
from frontier_rl.evaluation.results.store import ResultStore
from frontier_rl.evaluation.running.evaluate import evaluate
from frontier_rl.evaluation.running.experiment import ExperimentConfig, expand_worlds
from frontier_rl.evaluation.running.fingerprints import identity
from frontier_rl.evaluation.running.methods import ORACLE

SWEEP = tuple(f"fixed:{0.05 * i:.2f}" for i in range(21))


def sweep_analysis(rows: Mapping[EpisodeKey, EpisodeRow], worlds: tuple[str, ...], episodes: int) -> dict[str, Any]:
    """The best weight of the sweep on average, the per-world best weights and their mean time."""
    keys = [(w, e) for e in range(episodes) for w in worlds]
    times = np.array([[rows[EpisodeKey(m, w, e)].sim_time_s for m in SWEEP] for w, e in keys])
    weights = np.array([float(m.split(":")[1]) for m in SWEEP])
    best = int(times.mean(axis=0).argmin())
    per_world = weights[times.argmin(axis=1)]
    return {
        "best_weight": float(weights[best]),
        "best_mean_time_s": float(times[:, best].mean()),
        "per_world_best_weight_quartiles": [float(q) for q in np.percentile(per_world, [0, 25, 50, 75, 100])],
        "per_world_best_weight_counts": {f"{w:.2f}": int((per_world == w).sum()) for w in weights},
        "per_world_oracle_mean_time_s": float(times.min(axis=1).mean()),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--methods", default="", help="comma-separated policy specs besides the sweep")
    parser.add_argument("--worlds", default="office")
    parser.add_argument("--episodes", type=int, default=100)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--max-time", type=float, default=SimConfig().max_sim_time, help="sim-time cap (s)")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()

    extra = [m.strip() for m in args.methods.split(",") if m.strip()]
    methods = tuple(dict.fromkeys(["fixed:0.75", *extra, *SWEEP, ORACLE]))
    worlds = expand_worlds(args.worlds)
    sim = SimConfig(max_sim_time=args.max_time)
    config = ExperimentConfig(methods=methods, worlds=worlds, episodes=args.episodes, seed=args.seed, sim=sim)
    command = "python experiments/weight_sweep.py " + " ".join(
        f"--{k.replace('_', '-')} {v}" for k, v in vars(args).items() if v not in (None, "")
    )
    report = evaluate(config, args.out, workers=args.workers, command=command)

    store = ResultStore(args.out, identity(config))
    store.close()
    summary_path = args.out / "summary.json"
    summary = json.loads(summary_path.read_text())
    summary["sweep"] = sweep_analysis(store.rows, worlds, args.episodes)
    write_text_atomic(summary_path, json.dumps(summary, indent=1) + "\n")
    print(json.dumps(summary["sweep"], indent=1))
    print(f"report: {report}")


if __name__ == "__main__":
    main()
