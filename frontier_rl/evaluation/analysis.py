"""From an experiment's rows to its summary: paired statistics, outlier cuts, the oracle ratio.

The summary is what ``summary.json`` holds and what the report lays out:

    {"baseline": ..., "reference": "oracle" | null, "worlds": [...], "episodes": N, "seed": S,
     "methods": {NAME: {"n", "mean_time_s", "var_time_s", "mean_diff_s", "ci95_s", "p_one_tailed",
                        "p_two_tailed", "p_wilcoxon", "reduction_pct", "oracle_ratio",
                        "std_time_s", "p_holm" (Holm-adjusted one-tailed p over the methods tested:
                        all but the baseline and the oracle, counting those whose p is undefined),
                        "end_reasons": {"explored": n, "unreachable": n, "time_cap": n, ...},
                        "mean_coverage", "min_coverage", "mean_free_coverage", "mean_unknown_left_m2", ...}},
     "outliers": {"1000": {"methods": {NAME: {..., "excluded"}}}, ...},
     "per_world": {WORLD: {"methods": {...}}},           # only with more than one world
     "teams": {POLICY: {STRATEGY: {ROBOTS: {"method", "n", "mean_time_s", "ci95_half_s"}}}}}
                                                           # only with team methods (POLICY@N[:STRATEGY])
"""

from __future__ import annotations

import math
from collections import Counter
from typing import Any

import numpy as np
from scipy import stats as scipy_stats

from frontier_rl.core.sim.episode_log import EndReason
from frontier_rl.evaluation.experiment import ORACLE, ExperimentConfig
from frontier_rl.evaluation.statistics import compare_methods, holm_adjust
from frontier_rl.swarm.config import TeamMethod

Rows = dict[tuple[str, str, int], dict[str, Any]]


def paired_times(
    rows: Rows, methods: tuple[str, ...], worlds: tuple[str, ...], episodes: int
) -> dict[str, list[float]]:
    """Each method's exploration times (s), aligned by (world, episode)."""
    return {m: [float(rows[(m, w, e)]["sim_time_s"]) for e in range(episodes) for w in worlds] for m in methods}


def summarise(rows: Rows, config: ExperimentConfig, outlier_thresholds: tuple[float, ...] = ()) -> dict[str, Any]:
    """The experiment's summary (see the module docstring); every row of ``config`` must be in ``rows``."""
    summary: dict[str, Any] = {
        "baseline": config.baseline,
        "reference": ORACLE if ORACLE in config.methods else None,
        "worlds": list(config.worlds),
        "episodes": config.episodes,
        "seed": config.seed,
        "methods": _method_table(rows, config, config.worlds),
        "outliers": {},
    }
    times = paired_times(rows, config.methods, config.worlds, config.episodes)
    base = np.asarray(times[config.baseline])
    for threshold in outlier_thresholds:
        cut = compare_methods(times, config.baseline, threshold)
        entries = {}
        for method, stats in cut.items():
            t = np.asarray(times[method])
            excluded = int(np.count_nonzero((t > threshold) | (base > threshold)))
            paired_base = stats.mean_time_s + stats.mean_diff_s  # the baseline's mean on the same episodes
            entries[method] = stats.to_dict() | {"excluded": excluded, "baseline_mean_time_s": _finite(paired_base)}
        summary["outliers"][f"{threshold:g}"] = {"methods": entries}
    if len(config.worlds) > 1:
        summary["per_world"] = {w: {"methods": _method_table(rows, config, (w,))} for w in config.worlds}
    teams = team_scaling(times, config.methods)
    if teams:
        summary["teams"] = teams
    return summary


def team_scaling(times: dict[str, list[float]], methods: tuple[str, ...]) -> dict[str, Any]:
    """Mean exploration time (s) against team size, per policy and strategy, with the 95 % CI
    half-width (Student's t) of each mean; a policy's one-robot method, if run, starts every line."""
    parsed = {m: TeamMethod.parse(m) for m in methods}
    scaling: dict[str, Any] = {}
    for method, team in parsed.items():
        if team.robots is None:
            continue
        alone = str(team.policy)
        line = scaling.setdefault(alone, {}).setdefault(team.strategy.value, {})
        line[str(team.robots)] = _time_entry(method, times[method])
        if alone in parsed and "1" not in line:
            line["1"] = _time_entry(alone, times[alone])
    for lines in scaling.values():
        for strategy, line in lines.items():
            lines[strategy] = dict(sorted(line.items(), key=lambda kv: int(kv[0])))
    return scaling


def _time_entry(method: str, values: list[float]) -> dict[str, Any]:
    t = np.asarray(values, dtype=np.float64)
    half = float(scipy_stats.t.ppf(0.975, len(t) - 1) * t.std(ddof=1) / math.sqrt(len(t))) if len(t) > 1 else None
    return {"method": method, "n": len(t), "mean_time_s": float(t.mean()), "ci95_half_s": half}


def _method_table(rows: Rows, config: ExperimentConfig, worlds: tuple[str, ...]) -> dict[str, dict[str, Any]]:
    times = paired_times(rows, config.methods, worlds, config.episodes)
    stats = compare_methods(times, config.baseline)
    oracle_mean = float(np.mean(times[ORACLE])) if ORACLE in times else math.nan
    tested = {m: _finite(stats[m].p_one_tailed) for m in config.methods if m not in (config.baseline, ORACLE)}
    # a method tested on two or more pairs counts in the family even where its p is undefined
    holm = holm_adjust(tested, family_size=sum(stats[m].n >= 2 for m in tested))
    table: dict[str, dict[str, Any]] = {}
    for method in config.methods:
        own = [rows[(method, w, e)] for e in range(config.episodes) for w in worlds]
        entry = stats[method].to_dict()
        entry["std_time_s"] = _finite(math.sqrt(entry["var_time_s"])) if entry["var_time_s"] is not None else None
        entry["p_holm"] = holm.get(method)
        entry["median_time_s"] = float(np.median(times[method]))
        entry["oracle_ratio"] = _ratio(float(np.mean(times[method])), oracle_mean)
        entry["episodes_done"] = sum(bool(r["done"]) for r in own)
        entry["end_reasons"] = end_reasons(own)
        entry["mean_coverage"] = float(np.mean([r["coverage"] for r in own]))
        entry["min_coverage"] = float(np.min([r["coverage"] for r in own]))
        entry["mean_free_coverage"] = float(np.mean([r["free_coverage"] for r in own]))
        entry["mean_unknown_left_m2"] = float(np.mean([r["unknown_left_m2"] for r in own]))
        entry["mean_path_length_m"] = float(np.mean([r["path_length_m"] for r in own]))
        entry["mean_t90_s"] = _mean_of_present(r["t90_s"] for r in own)
        entry["mean_t99_s"] = _mean_of_present(r["t99_s"] for r in own)
        entry["mean_aborts"] = float(np.mean([r["aborts"] for r in own]))
        entry["mean_weight"] = _mean_of_present(r["mean_weight"] for r in own)
        entry["mean_wall_time_s"] = float(np.mean([r["wall_time_s"] for r in own]))
        entry["robots"] = int(own[0]["robots"]) if own else 1
        entry["mean_overlap"] = float(np.mean([r["overlap"] for r in own]))
        table[method] = entry
    return table


def end_reasons(rows: list[dict[str, Any]]) -> dict[str, int]:
    """How many of ``rows`` ended for each reason: "explored", "unreachable" and "time_cap" always
    (0 if none did), then any other reason a row gives (a team's "failed"), by name."""
    counts = Counter(str(r["end_reason"]) for r in rows if r["end_reason"] is not None)
    standard = {reason.value: counts.pop(reason.value, 0) for reason in EndReason}
    return standard | dict(sorted(counts.items()))


def _finite(value: float) -> float | None:
    return value if math.isfinite(value) else None


def _ratio(value: float, reference: float) -> float | None:
    return value / reference if math.isfinite(reference) and reference > 0 else None


def _mean_of_present(values: Any) -> float | None:
    present = [float(v) for v in values if v is not None]
    return float(np.mean(present)) if present else None
