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

A copy explores on with the copied noise stream, so one rollout per weight also measures luck:
after a different first leg the same noise falls on other scans. With ``--noise-repeats R`` every
weight, the constant among them, is rolled out R times from the probed state with R fresh noise
streams (the same R for every weight: common random numbers), its time is the mean, and a saving
counts as real only where it exceeds twice its standard error.

    .venv/bin/python experiments/weight_headroom.py --episodes 20 --out results/weight_headroom.json
    .venv/bin/python experiments/weight_headroom.py --episodes 20 --every 8 --noise-repeats 4 --workers 2 \
        --out results/weight_headroom_noise.json
"""

from __future__ import annotations

import argparse
import copy
import json
import math
import multiprocessing
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import stats

from frontier_rl.atomic_write import write_text_atomic
from frontier_rl.core.frontiers.ranking import rank, weighted_cost
from frontier_rl.core.sim.episode import decision_context
from frontier_rl.core.sim.metrics import EndReason
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.catalog import generate_world


def finish(sim: ExplorationSimulator, weight: float) -> float:
    """Explore on with the constant ``weight``; the time (s) when the map is explored, inf when the
    episode ended otherwise (frontiers given up, the time cap): a weight must not win by giving up."""
    while not sim.truncated and not sim.finished:
        context = decision_context(sim)
        sim.execute(rank(weighted_cost(context.frontiers, weight)), weight)
    return sim.sim_time if sim.end_reason() is EndReason.EXPLORED else math.inf


def probe_episode(
    seed: int, constant: float, weights: list[float], every: int, repeats: int = 1
) -> list[dict[str, Any]]:
    """Every ``every``-th decision of an episode with the ``constant`` weight: the end time with
    each of ``weights`` taken there (the constant everywhere else); with ``repeats`` > 1, each
    over that many fresh noise streams (:func:`_noisy_end_times`)."""
    sim = ExplorationSimulator(generate_world("office", seed), rng=np.random.default_rng(seed))
    probes: list[dict[str, Any]] = []
    decision = 0
    while not sim.truncated and not sim.finished:
        if decision % every == 0:
            probe: dict[str, Any] = {"seed": seed, "decision": decision, "time_s": sim.sim_time}
            if repeats == 1:
                probe["end_times_s"] = {f"{w:.2f}": finish(_take(copy.deepcopy(sim), w), constant)
                                        for w in weights if w != constant}  # fmt: skip
            else:
                probe["repeat_end_times_s"] = _noisy_end_times(sim, constant, weights, repeats, (seed, decision))
                probe["end_times_s"] = {w: float(np.mean(t)) for w, t in probe["repeat_end_times_s"].items()}
            probes.append(probe)
        _take(sim, constant)
        decision += 1
    if repeats == 1:  # the constant's own end time is the same from every probe: the episode's
        end = sim.sim_time if sim.end_reason() is EndReason.EXPLORED else math.inf
        for probe in probes:
            probe["end_times_s"][f"{constant:.2f}"] = end
    return probes


def _noisy_end_times(
    sim: ExplorationSimulator, constant: float, weights: list[float], repeats: int, key: tuple[int, int]
) -> dict[str, list[float]]:
    """Per weight (the constant among them), the end times of ``repeats`` rollouts from ``sim``'s
    state, each with a fresh noise stream seeded by ``key`` and the repeat (the same streams for
    every weight). Weights that rank the frontiers alike take the same decision, so they share
    their rollouts."""
    frontiers = decision_context(sim).frontiers
    by_order: dict[tuple[int, ...], list[float]] = {}
    times: dict[str, list[float]] = {}
    for w in sorted(set(weights) | {constant}):
        order = tuple(int(i) for i in rank(weighted_cost(frontiers, w)))
        if order not in by_order:
            runs = []
            for r in range(repeats):
                twin = copy.deepcopy(sim)
                twin.rng = np.random.default_rng([*key, r])
                runs.append(finish(_take(twin, w), constant))
            by_order[order] = runs
        times[f"{w:.2f}"] = by_order[order]
    return times


def _take(sim: ExplorationSimulator, weight: float) -> ExplorationSimulator:
    context = decision_context(sim)
    sim.execute(rank(weighted_cost(context.frontiers, weight)), weight)
    return sim


def summarise(probes: list[dict[str, Any]], constant: float) -> dict[str, Any]:
    """The share of decisions where another weight saves time, and how much (s), in hindsight; for
    probes with repeated rollouts also the share where the saving exceeds twice its standard error
    (the differences of paired rollouts), and the spread of the constant's own rollouts."""
    key = f"{constant:.2f}"
    probes = [p for p in probes if math.isfinite(p["end_times_s"][key])]  # the constant explored
    if not probes:
        return {"constant": constant, "probed_decisions": 0}
    savings = np.array([p["end_times_s"][key] - min(p["end_times_s"].values()) for p in probes])
    best = [min(p["end_times_s"], key=lambda w: (p["end_times_s"][w], w != key)) for p in probes]
    summary: dict[str, Any] = {
        "constant": constant,
        "probed_decisions": len(probes),
        "share_where_another_weight_saves_time": float(np.mean(savings > 0)),
        "mean_saving_s": float(savings.mean()),
        "median_saving_s": float(np.median(savings)),
        "max_saving_s": float(savings.max()),
        "best_weight_counts": {w: best.count(w) for w in sorted(set(best))},
    }
    repeated = [p for p in probes if "repeat_end_times_s" in p]
    if repeated:
        real = [_significant_saving(p, key) for p in repeated]
        spreads = [float(np.std(p["repeat_end_times_s"][key], ddof=1)) for p in repeated]
        t_values = [t for p in repeated for t in _paired_t_values(p, key)]
        repeats = len(repeated[0]["repeat_end_times_s"][key])
        held_out = np.array([_held_out_saving(p, key) for p in repeated])
        summary |= {
            "noise_repeats": repeats,
            "share_with_a_saving_beyond_2_standard_errors": float(np.mean([s > 0 for s in real])),
            "mean_saving_beyond_2_standard_errors_s": float(np.mean(real)),
            "median_sd_of_the_constants_rollouts_s": float(np.median(spreads)),
            "other_decisions_tested": len(t_values),
            "other_decisions_faster_beyond_2_standard_errors": int(sum(t > 2 for t in t_values)),
            "expected_so_by_chance": float(stats.t.sf(2.0, repeats - 1) * len(t_values)),
            "other_decisions_slower_beyond_2_standard_errors": int(sum(t < -2 for t in t_values)),
            "held_out_saving_s": float(held_out.mean()),
            "held_out_saving_standard_error_s": (
                float(held_out.std(ddof=1) / math.sqrt(len(held_out))) if len(held_out) > 1 else None
            ),
        }
    return summary


def _paired_differences(probe: dict[str, Any], key: str) -> list[NDArray[np.float64]]:
    """Per decision other than the constant's (weights that decide alike share their rollouts),
    its rollouts' end times subtracted from the constant's, paired by noise stream (> 0: it ended
    sooner). A decision with a rollout that did not finish exploring is left out (none did in the
    run the README reports)."""
    base = np.array(probe["repeat_end_times_s"][key])
    others = {tuple(t) for t in probe["repeat_end_times_s"].values()} - {tuple(base)}
    diffs = [base - np.array(times) for times in sorted(others)]
    return [diff for diff in diffs if np.isfinite(diff).all()]


def _t_value(diff: NDArray[np.float64]) -> float | None:
    """The t value of the mean of paired differences; None when they do not vary (no test)."""
    error = float(np.std(diff, ddof=1)) / math.sqrt(len(diff))
    return float(diff.mean()) / error if error > 0 else None


def _paired_t_values(probe: dict[str, Any], key: str) -> list[float]:
    """The t value of each other decision's paired saving over the constant (:func:`_paired_differences`)."""
    values = (_t_value(diff) for diff in _paired_differences(probe, key))
    return [t for t in values if t is not None]


def _significant_saving(probe: dict[str, Any], key: str) -> float:
    """The largest mean saving (s) over the constant among the other decisions whose saving
    exceeds twice its standard error; 0 when none does."""
    savings = [float(d.mean()) for d in _paired_differences(probe, key) if (_t_value(d) or 0.0) > 2.0]
    return max(savings, default=0.0)


def _held_out_saving(probe: dict[str, Any], key: str) -> float:
    """What choosing the weight with the shortest mean on half of the rollouts saves on the other
    half, both ways round (s): an estimate of the headroom free of the luck that picking the best
    of noisy times adds. Weights with a rollout that did not finish exploring are left out of the
    choice (none did in the run the README reports)."""
    times = {w: np.array(t) for w, t in probe["repeat_end_times_s"].items() if np.isfinite(t).all()}
    half = len(times[key]) // 2
    savings = []
    for pick, judge in ((slice(0, half), slice(half, None)), (slice(half, None), slice(0, half))):
        best = min(times, key=lambda w: (times[w][pick].mean(), w != key))
        savings.append(float(times[key][judge].mean() - times[best][judge].mean()))
    return float(np.mean(savings))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=20, help="office worlds, seeds 0..N-1")
    parser.add_argument("--constant", type=float, default=0.95, help="the best constant weight of the sweep")
    parser.add_argument("--weights", default="0.0,0.25,0.5,0.75,0.85,0.9,0.95,1.0")
    parser.add_argument("--every", type=int, default=10, help="probe every N-th decision")
    parser.add_argument("--noise-repeats", type=int, default=1, help="rollouts per weight, each with fresh noise")
    parser.add_argument("--workers", type=int, default=1, help="episodes run at once")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    if args.noise_repeats < 1 or args.workers < 1 or args.every < 1 or args.episodes < 1:
        parser.error("--episodes, --every, --noise-repeats and --workers must be >= 1")
    weights = [float(w) for w in args.weights.split(",")]
    jobs = [(seed, args.constant, weights, args.every, args.noise_repeats) for seed in range(args.episodes)]
    with multiprocessing.get_context("spawn").Pool(args.workers) as pool:
        probes = [p for episode in pool.starmap(probe_episode, jobs) for p in episode]
    summary = summarise(probes, args.constant)
    write_text_atomic(args.out, json.dumps({"summary": summary, "probes": probes}, indent=1) + "\n")
    print(json.dumps(summary, indent=1))


if __name__ == "__main__":
    main()
