"""How much could a weight chosen from the map gain over the best constant one? (issue 15, item 4)

For each office world, the robot explores with the best constant weight ``--constant`` (eq. 3.1);
at every ``--every``-th decision the simulator is copied whole (map, pose, clock, noise stream)
and, for each weight of ``--weights``, the decision is taken with that weight and the episode
finished with the constant. The weight whose episode ends first is that decision's best weight in
hindsight; its saving is the time the constant would have taken minus that episode's. A decision
where no other weight saves time gives the constant nothing to learn; a map-dependent weight
policy can gain at most what these per-decision choices save (one decision at a time, the others
held at the constant). Writes ``OUT`` (JSON): every probed decision's times per weight, and a
summary.

    .venv/bin/python experiments/weight_headroom.py --episodes 20 --out results/weight_headroom.json
"""

from __future__ import annotations

import argparse
import copy
import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from frontier_rl.atomic_write import write_text_atomic
from frontier_rl.core.frontiers.ranking import rank, weighted_cost
from frontier_rl.core.sim.episode import decision_context
from frontier_rl.core.sim.episode_log import EndReason
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.catalog import generate_world


def finish(sim: ExplorationSimulator, weight: float) -> float:
    """Explore on with the constant ``weight``; the time (s) when the map is explored, inf when the
    episode ended otherwise (frontiers given up, the time cap): a weight must not win by giving up."""
    while not sim.truncated and not sim.finished:
        context = decision_context(sim)
        sim.execute(rank(weighted_cost(context.frontiers, weight)), weight)
    return sim.sim_time if sim.end_reason() is EndReason.EXPLORED else math.inf


def probe_episode(seed: int, constant: float, weights: list[float], every: int) -> list[dict[str, Any]]:
    """Every ``every``-th decision of an episode with the ``constant`` weight: the end time with
    each of ``weights`` taken there (the constant everywhere else)."""
    sim = ExplorationSimulator(generate_world("office", seed), rng=np.random.default_rng(seed))
    probes = []
    decision = 0
    while not sim.truncated and not sim.finished:
        if decision % every == 0:
            times = {f"{w:.2f}": finish(_take(copy.deepcopy(sim), w), constant) for w in weights if w != constant}
            probes.append({"seed": seed, "decision": decision, "time_s": sim.sim_time, "end_times_s": times})
        _take(sim, constant)
        decision += 1
    end = sim.sim_time if sim.end_reason() is EndReason.EXPLORED else math.inf
    for probe in probes:  # the constant's own end time is the same from every probe: the episode's
        probe["end_times_s"][f"{constant:.2f}"] = end
    return probes


def _take(sim: ExplorationSimulator, weight: float) -> ExplorationSimulator:
    context = decision_context(sim)
    sim.execute(rank(weighted_cost(context.frontiers, weight)), weight)
    return sim


def summarise(probes: list[dict[str, Any]], constant: float) -> dict[str, Any]:
    """The share of decisions where another weight saves time, and how much (s), in hindsight."""
    key = f"{constant:.2f}"
    probes = [p for p in probes if math.isfinite(p["end_times_s"][key])]  # the constant explored
    if not probes:
        return {"constant": constant, "probed_decisions": 0}
    savings = np.array([p["end_times_s"][key] - min(p["end_times_s"].values()) for p in probes])
    best = [min(p["end_times_s"], key=lambda w: (p["end_times_s"][w], w != key)) for p in probes]
    return {
        "constant": constant,
        "probed_decisions": len(probes),
        "share_where_another_weight_saves_time": float(np.mean(savings > 0)),
        "mean_saving_s": float(savings.mean()),
        "median_saving_s": float(np.median(savings)),
        "max_saving_s": float(savings.max()),
        "best_weight_counts": {w: best.count(w) for w in sorted(set(best))},
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=20, help="office worlds, seeds 0..N-1")
    parser.add_argument("--constant", type=float, default=0.95, help="the best constant weight of the sweep")
    parser.add_argument("--weights", default="0.0,0.25,0.5,0.75,0.85,0.9,0.95,1.0")
    parser.add_argument("--every", type=int, default=10, help="probe every N-th decision")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    weights = [float(w) for w in args.weights.split(",")]
    probes = [p for seed in range(args.episodes) for p in probe_episode(seed, args.constant, weights, args.every)]
    summary = summarise(probes, args.constant)
    write_text_atomic(args.out, json.dumps({"summary": summary, "probes": probes}, indent=1) + "\n")
    print(json.dumps(summary, indent=1))


if __name__ == "__main__":
    main()
