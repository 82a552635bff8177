"""From an experiment's rows to its summary: paired statistics, outlier cuts, the oracle ratio,
team scaling, as the typed values of :mod:`frontier_rl.evaluation.results.summary` (which writes them as
``summary.json`` and reads them back)."""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Iterable, Mapping, Sequence

import numpy as np
from numpy.typing import NDArray
from scipy import stats as scipy_stats

from frontier_rl.core.sim.metrics import EndReason
from frontier_rl.evaluation.results.episode_record import EpisodeKey, EpisodeRow
from frontier_rl.evaluation.results.summary import (
    ExperimentSummary,
    MethodSummary,
    OutlierCut,
    OutlierSummary,
    TeamPoint,
    defined,
)
from frontier_rl.evaluation.running.experiment import ExperimentConfig
from frontier_rl.evaluation.running.methods import ORACLE
from frontier_rl.evaluation.statistics.paired import compare_methods, holm_adjust
from frontier_rl.swarm.config import Strategy, TeamMethod, one_robot_methods

Rows = Mapping[EpisodeKey, EpisodeRow]


def paired_times(
    rows: Rows, methods: tuple[str, ...], worlds: tuple[str, ...], episodes: int
) -> dict[str, list[float]]:
    """Each method's exploration times (s), aligned by (world, episode): NaN for a team whose robots all
    failed, which has no time to explore (its time is when the last one stopped); such episodes are
    left out of the method's comparisons, as their pairs (:func:`compare_methods`)."""
    return {m: [_exploration_time(rows[EpisodeKey(m, w, e)]) for e in range(episodes) for w in worlds] for m in methods}


def _exploration_time(row: EpisodeRow) -> float:
    return math.nan if row.end_reason is EndReason.FAILED else row.sim_time_s


def summarise(rows: Rows, config: ExperimentConfig, outlier_thresholds: tuple[float, ...] = ()) -> ExperimentSummary:
    """The experiment's summary; every row of ``config`` must be in ``rows``. ``per_world`` is
    filled only with more than one world, ``teams`` only with team methods (``POLICY@N[:STRATEGY]``)."""
    times = paired_times(rows, config.methods, config.worlds, config.episodes)
    per_world = {w: _method_table(rows, config, (w,)) for w in config.worlds} if len(config.worlds) > 1 else {}
    return ExperimentSummary(
        baseline=config.baseline,
        reference=ORACLE if ORACLE in config.methods else None,
        worlds=config.worlds,
        episodes=config.episodes,
        seed=config.seed,
        methods=_method_table(rows, config, config.worlds),
        outliers=tuple(_outlier_cut(times, config.baseline, threshold) for threshold in outlier_thresholds),
        per_world=per_world,
        teams=team_scaling(times, config.methods),
    )


def _outlier_cut(times: dict[str, list[float]], baseline: str, threshold: float) -> OutlierCut:
    """Every method against ``baseline`` without the episodes above ``threshold`` (s)."""
    base = np.asarray(times[baseline])
    entries = {}
    for method, stats in compare_methods(times, baseline, threshold).items():
        t = np.asarray(times[method])
        excluded = int(np.count_nonzero((t > threshold) | (base > threshold)))
        paired_base = stats.mean_time_s + stats.mean_diff_s  # the baseline's mean on the same episodes
        entries[method] = OutlierSummary(
            **OutlierSummary.values_of(stats), excluded=excluded, baseline_mean_time_s=defined(paired_base)
        )
    return OutlierCut(threshold, entries)


def team_scaling(times: dict[str, list[float]], methods: tuple[str, ...]) -> tuple[TeamPoint, ...]:
    """Mean exploration time (s) against team size, per policy and strategy, with the 95 % CI
    half-width (Student's t) of each mean; a policy's one-robot method, if run, starts every line.
    The points come by policy, then strategy (each in the order of the methods), then team size."""
    alone_of = one_robot_methods(methods)
    policies: dict[str, dict[Strategy, dict[int, TeamPoint | None]]] = {}  # by the policy's canonical text
    labels: dict[str, str] = {}  # the policy as the methods write it
    for method in methods:
        team = TeamMethod.parse(method)
        if team.robots is None:
            continue
        alone = alone_of.get(team.policy.canonical)
        policy = labels.setdefault(team.policy.canonical, alone or str(team.policy))  # one per line
        line = policies.setdefault(team.policy.canonical, {}).setdefault(team.strategy, {})
        line[team.robots] = _team_point(policy, team.strategy, team.robots, method, times[method])
        if alone is not None and 1 not in line:
            line[1] = _team_point(policy, team.strategy, 1, alone, times[alone])
    return tuple(
        point
        for lines in policies.values()
        for line in lines.values()
        for _, point in sorted(line.items())
        if point is not None
    )


def _team_point(policy: str, strategy: Strategy, robots: int, method: str, values: list[float]) -> TeamPoint | None:
    """The point of a team size; None where every episode of it failed (no time to plot)."""
    t = finite_times(values)
    if not len(t):
        return None
    half = float(scipy_stats.t.ppf(0.975, len(t) - 1) * t.std(ddof=1) / math.sqrt(len(t))) if len(t) > 1 else None
    return TeamPoint(policy, strategy, robots, method, len(t), float(t.mean()), half)


def _method_table(rows: Rows, config: ExperimentConfig, worlds: tuple[str, ...]) -> dict[str, MethodSummary]:
    times = paired_times(rows, config.methods, worlds, config.episodes)
    stats = compare_methods(times, config.baseline)
    oracle_mean = _finite_mean(times[ORACLE]) if ORACLE in times else math.nan
    tested = {m: defined(stats[m].p_one_tailed) for m in config.methods if m not in (config.baseline, ORACLE)}
    # a method tested on two or more pairs counts in the family even where its p is undefined
    holm = holm_adjust(tested, family_size=sum(stats[m].n >= 2 for m in tested))
    table: dict[str, MethodSummary] = {}
    for method in config.methods:
        own = [rows[EpisodeKey(method, w, e)] for e in range(config.episodes) for w in worlds]
        variance = defined(stats[method].var_time_s)
        table[method] = MethodSummary(
            **MethodSummary.values_of(stats[method]),
            std_time_s=defined(math.sqrt(variance)) if variance is not None else None,
            p_holm=holm.get(method),
            median_time_s=defined(_finite_median(times[method])),
            oracle_ratio=_ratio(_finite_mean(times[method]), oracle_mean),
            episodes_done=sum(bool(r.done) for r in own),
            end_reasons=end_reasons(own),
            mean_coverage=float(np.mean([r.coverage for r in own])),
            min_coverage=float(np.min([r.coverage for r in own])),
            mean_free_coverage=float(np.mean([r.free_coverage for r in own])),
            mean_unknown_left_m2=float(np.mean([r.unknown_left_m2 for r in own])),
            mean_path_length_m=float(np.mean([r.path_length_m for r in own])),
            mean_t90_s=_mean_of_present(r.t90_s for r in own),
            mean_t99_s=_mean_of_present(r.t99_s for r in own),
            mean_aborts=float(np.mean([r.aborts for r in own])),
            mean_weight=_mean_of_present(r.mean_weight for r in own),
            mean_wall_time_s=float(np.mean([r.wall_time_s for r in own])),
            robots=own[0].robots if own else 1,
            mean_overlap=float(np.mean([r.overlap for r in own])),
        )
    return table


ALWAYS_COUNTED = (EndReason.EXPLORED, EndReason.UNREACHABLE, EndReason.TIME_CAP)
"""The end reasons a method's summary counts even where no episode ended so (a team's ``FAILED`` is
counted only where one did)."""


def end_reasons(rows: Sequence[EpisodeRow]) -> dict[EndReason, int]:
    """How many of ``rows`` ended for each reason: those of :data:`ALWAYS_COUNTED` always (0 if none
    did), then any other reason a row gives, in :class:`EndReason`'s order."""
    counts = Counter(r.end_reason for r in rows if r.end_reason is not None)
    return {reason: counts[reason] for reason in EndReason if reason in ALWAYS_COUNTED or counts[reason]}


def _ratio(value: float, reference: float) -> float | None:
    return value / reference if math.isfinite(value) and math.isfinite(reference) and reference > 0 else None


def finite_times(values: Sequence[float]) -> NDArray[np.float64]:
    """The values of :func:`paired_times` that are times (NaN: a team whose robots all failed)."""
    array = np.asarray(values, dtype=np.float64)
    return array[np.isfinite(array)]


def _finite_mean(values: Sequence[float]) -> float:
    finite = finite_times(values)
    return float(np.mean(finite)) if len(finite) else math.nan


def _finite_median(values: Sequence[float]) -> float:
    finite = finite_times(values)
    return float(np.median(finite)) if len(finite) else math.nan


def _mean_of_present(values: Iterable[float | None]) -> float | None:
    present = [float(v) for v in values if v is not None]
    return float(np.mean(present)) if present else None
