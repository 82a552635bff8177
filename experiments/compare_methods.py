"""Paired comparison of exploration methods on procedural worlds (the issue-3 experiment).

Every method explores the same worlds: episode i uses generator seed ``first_seed + i`` for the
world, its start pose and the sensor noise. Results are appended to ``OUT/episodes.jsonl`` as
episodes finish (a rerun skips finished ones); ``OUT/summary.json`` and ``OUT/table.md`` hold the
paired statistics of every method against the baseline.

    .venv/bin/python experiments/compare_methods.py --methods fixed:0.75,learned:models/model4.zip \
        --world office --episodes 100 --first-seed 0 --out results/model4_vs_fixed
"""

from __future__ import annotations

import argparse
import json
import os
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

import numpy as np

SWEEP = tuple(f"fixed:{0.05 * i:.2f}" for i in range(21))


def _episode(method: str, world: str, seed: int) -> dict[str, object]:
    from frontier_rl.core.episode import run_episode
    from frontier_rl.policies.registry import make_policy
    from frontier_rl.world_spec import resolve_world

    if method.startswith("learned:"):
        import torch

        torch.set_num_threads(1)  # one episode per core; a tiny network gains nothing from threads
    result = run_episode(resolve_world(world, seed), make_policy(method), seed=seed)
    row: dict[str, object] = {"method": method, "world": world, "seed": seed, **result.summary()}
    weights = [d.weight for d in result.decision_log if d.weight is not None]
    if weights:
        row["mean_weight"] = float(np.mean(weights))
    return row


def _load(path: Path) -> dict[tuple[str, str, int], dict[str, object]]:
    rows: dict[tuple[str, str, int], dict[str, object]] = {}
    if path.exists():
        for line in path.read_text().splitlines():
            if line.strip():
                row = json.loads(line)
                rows[(row["method"], row["world"], row["seed"])] = row
    return rows


def summarise(
    rows: dict[tuple[str, str, int], dict[str, object]], methods: list[str], world: str, seeds: list[int], baseline: str
) -> dict[str, object]:
    """Paired statistics of each method's exploration time against ``baseline``."""
    from frontier_rl.evaluation import compare_methods

    times = {m: [float(rows[(m, world, s)]["sim_time_s"]) for s in seeds] for m in methods}  # type: ignore[arg-type]
    out: dict[str, object] = {"baseline": baseline, "world": world, "episodes": len(seeds), "methods": {}}
    for m, paired in compare_methods(times, baseline).items():  # type: ignore[arg-type]
        entry = paired.to_dict() | {"all_done": bool(all(rows[(m, world, s)]["done"] for s in seeds))}
        weights = [rows[(m, world, s)].get("mean_weight") for s in seeds]
        if all(w is not None for w in weights):
            entry["mean_weight"] = float(np.mean(weights))  # type: ignore[arg-type]
        out["methods"][m] = entry  # type: ignore[index]
    return out


def sweep_analysis(
    rows: dict[tuple[str, str, int], dict[str, object]], world: str, seeds: list[int]
) -> dict[str, object]:
    """How the best fixed weight varies between worlds: the best weight of the sweep on average,
    each world's best weight in hindsight, and the mean time of that per-world oracle (optimistic:
    it also picks each world's luckiest noise)."""
    times = np.array([[float(rows[(m, world, s)]["sim_time_s"]) for m in SWEEP] for s in seeds])
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
    parser.add_argument("--methods", required=True, help="comma-separated policy specs; 'sweep' adds fixed:0.00..1.00")
    parser.add_argument("--baseline", default="fixed:0.75")
    parser.add_argument("--world", default="office")
    parser.add_argument("--episodes", type=int, default=100)
    parser.add_argument("--first-seed", type=int, default=0)
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()

    methods: list[str] = []
    for m in args.methods.split(","):
        for name in SWEEP if m == "sweep" else (m,):
            if name not in methods:
                methods.append(name)
    if args.baseline not in methods:
        methods.insert(0, args.baseline)
    seeds = list(range(args.first_seed, args.first_seed + args.episodes))
    args.out.mkdir(parents=True, exist_ok=True)
    log = args.out / "episodes.jsonl"
    rows = _load(log)
    todo = [(m, args.world, s) for m in methods for s in seeds if (m, args.world, s) not in rows]
    print(f"{len(todo)} episodes to run ({len(rows)} already in {log})", flush=True)
    with ProcessPoolExecutor(args.workers) as pool, log.open("a") as sink:
        futures = [pool.submit(_episode, *job) for job in todo]
        for i, future in enumerate(as_completed(futures), 1):
            row = future.result()
            sink.write(json.dumps(row) + "\n")
            sink.flush()
            rows[(row["method"], row["world"], row["seed"])] = row  # type: ignore[index]
            if i % 50 == 0:
                print(f"  {i}/{len(todo)}", flush=True)
    summary = summarise(rows, methods, args.world, seeds, args.baseline)
    if all((m, args.world, s) in rows for m in SWEEP for s in seeds):
        summary["sweep"] = sweep_analysis(rows, args.world, seeds)
    (args.out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    lines = [
        "| method | mean time (s) | reduction vs baseline | 95 % CI of the difference (s) | p (one-tailed) |",
        "|---|---:|---:|---:|---:|",
    ]
    for m, e in summary["methods"].items():  # type: ignore[union-attr]
        if m == args.baseline:
            lines.append(f"| {m} (baseline) | {e['mean_time_s']:.1f} | | | |")
        else:
            lo, hi = e["ci95_s"]
            lines.append(
                f"| {m} | {e['mean_time_s']:.1f} | {e['reduction_pct']:+.1f} % | {lo:.1f} … {hi:.1f} "
                f"| {e['p_one_tailed']:.2g} |"
            )
    (args.out / "table.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
