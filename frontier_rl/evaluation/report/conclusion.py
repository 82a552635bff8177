"""The report's first paragraph, generated from the experiment's summary: which method was fastest against
the baseline, by how much and how surely, how far from the oracle, and how the episodes ended."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

from frontier_rl.core.sim.metrics import EndReason
from frontier_rl.evaluation.report.table import SIGNIFICANCE, number, p_value
from frontier_rl.evaluation.results.summary import ExperimentSummary, MethodSummary
from frontier_rl.evaluation.running.methods import ORACLE

_REASONS = {
    EndReason.UNREACHABLE: "unreachable: frontiers were left, none of them reachable for a robot of this size or "
    "each given up after its tries",
    EndReason.TIME_CAP: "time cap: cut at the sim-time cap, with the cap as its time (the default cap is about three "
    "times what the fastest method takes on large floors: a policy that meets it wanders)",
}
"""What each end reason other than ``EXPLORED`` means, said once when it occurs."""

_MAX_WORLDS_NAMED = 12
"""The fastest method per world is named for at most this many worlds."""


@dataclass(frozen=True)
class Conclusion:
    """The generated summary.

    Attributes:
        headline: the sentence naming the fastest method (or saying none beat the baseline).
        best: the fastest tested method (None when only the baseline and the oracle ran).
        details: further sentences: multiple comparisons, the fastest per world, how episodes ended.
    """

    headline: str
    best: str | None
    details: tuple[str, ...]


def conclude(summary: ExperimentSummary, labels: dict[str, str]) -> Conclusion:
    """The conclusion of ``summary``, methods named by ``labels``; every number is formatted as the
    report's tables format it."""
    methods = summary.methods
    baseline = summary.baseline
    times = {m: e.mean_time_s for m, e in methods.items() if m not in (baseline, ORACLE) and _finite(e.mean_time_s)}
    tested = list(times)
    best = min(tested, key=lambda m: _or_inf(times[m])) if tested else None
    timeless = [m for m in methods if m not in (baseline, ORACLE, *tested)]  # every episode a failed team's
    headline = _headline(methods, baseline, best, labels, len(tested), timeless)
    details = []
    if len(tested) > 1:
        details.append(
            f"{len(tested)} methods were tested against the baseline; p Holm is each one-tailed p adjusted by "
            f"Holm's method over all {len(tested)}, so that the chance of calling any of them faster by luck "
            f"stays at {100 * SIGNIFICANCE:.0f} % or less."
        )
    per_world = summary.per_world
    if tested and 1 < len(per_world) <= _MAX_WORLDS_NAMED:
        parts = []
        for world, entries in per_world.items():
            fastest = min(tested, key=lambda m: _or_inf(entries[m].mean_time_s))
            if _or_zero(entries[fastest].mean_diff_s) > 0:
                parts.append(f"{labels.get(world, world)}: {labels[fastest]} ({_change(entries[fastest])})")
            else:
                parts.append(f"{labels.get(world, world)}: none faster than the baseline")
        details.append("Fastest per world, against the baseline there: " + "; ".join(parts) + ".")
    details.append(_completion(methods, labels))
    return Conclusion(headline, best, tuple(details))


def _headline(
    methods: Mapping[str, MethodSummary],
    baseline: str,
    best: str | None,
    labels: dict[str, str],
    family: int,
    timeless: Sequence[str] = (),
) -> str:
    base = methods[baseline]
    oracle = methods.get(ORACLE)
    if best is None and timeless:
        names = ", ".join(labels[m] for m in timeless)
        return (
            f"No method has an exploration time to compare with the baseline {labels[baseline]} "
            f"({number(base.mean_time_s)} s on average): every episode of {names} ended with its team failed."
        )
    if best is None:
        if oracle is None:
            return f"Only the baseline {labels[baseline]} ran: {number(base.mean_time_s)} s on average."
        return (
            f"The baseline {labels[baseline]} took {number(base.mean_time_s)} s on average, "
            f"{number(base.oracle_ratio, 2)} × the oracle's {number(oracle.mean_time_s)} s."
        )
    entry = methods[best]
    name = labels[best]
    ratio = f", {number(entry.oracle_ratio, 2)} × the time of the oracle that knows the map" if oracle else ""
    if not _or_zero(entry.mean_diff_s) > 0:
        return (
            f"No method was faster than the baseline {labels[baseline]} ({number(base.mean_time_s)} s on average): "
            f"the fastest, {name}, took {number(entry.mean_time_s)} s ({_change(entry)}){ratio}."
        )
    low, high = entry.ci95_s
    tests = f"one-tailed paired t-test p = {p_value(entry.p_one_tailed)}"
    decisive = entry.p_one_tailed
    if family > 1:
        tests += f", p Holm = {p_value(entry.p_holm)}"
        decisive = entry.p_holm
    verdict = "significant" if decisive is not None and decisive < SIGNIFICANCE else "not significant"
    return (
        f"{name} explored fastest: {number(entry.mean_time_s)} s on average against "
        f"{number(base.mean_time_s)} s for the baseline {labels[baseline]}, "
        f"{number(entry.reduction_pct)} % less time (mean saving {number(entry.mean_diff_s)} s, 95 % CI "
        f"{number(low)} to {number(high)} s; {tests}; {verdict} at the {100 * SIGNIFICANCE:.0f} % level){ratio}."
    )


def _change(entry: MethodSummary) -> str:
    reduction = entry.reduction_pct
    if reduction is None or not math.isfinite(reduction):
        return "no paired comparison"
    return f"{number(reduction)} % less time" if reduction >= 0 else f"{number(-reduction)} % more time"


def unfinished(
    end_reasons: Mapping[str, Mapping[EndReason, int]],
    labels: dict[str, str],
    reason_text: Callable[[EndReason], str] = str,
) -> list[str]:
    """Per method with episodes that did not end explored: "LABEL N REASON, N REASON" (each
    reason as ``reason_text`` writes it), from each method's episodes per end reason."""
    parts = []
    for method, reasons in end_reasons.items():
        ends = [f"{n} {reason_text(reason)}" for reason, n in reasons.items() if n and reason != EndReason.EXPLORED]
        if ends:
            parts.append(f"{labels[method]} {', '.join(ends)}")
    return parts


def _completion(methods: Mapping[str, MethodSummary], labels: dict[str, str]) -> str:
    by_method = {method: entry.end_reasons or {} for method, entry in methods.items()}
    total = sum(e.n for e in methods.values())
    explored = sum(reasons.get(EndReason.EXPLORED, 0) for reasons in by_method.values())
    if explored == total:
        return f"All {total} episodes ended with the map explored."
    parts = unfinished(by_method, labels, lambda reason: reason.label)
    reasons = {r for counts in by_method.values() for r, n in counts.items() if n and r != EndReason.EXPLORED}
    meaning = [_REASONS[r] for r in sorted(reasons) if r in _REASONS]
    return f"{explored} of {total} episodes ended with the map explored; the others: {'; '.join(parts)}" + (
        f" ({'; '.join(meaning)})." if meaning else "."
    )


def _finite(value: float | None) -> bool:
    return value is not None and math.isfinite(value)


def _or_inf(value: float | None) -> float:
    return math.inf if value is None else value


def _or_zero(value: float | None) -> float:
    return 0.0 if value is None else value
