"""The results page of the thesis's own experiment: model 4 against the fixed weight 0.75."""

from __future__ import annotations

from pathlib import Path

from results_data import Experiment, Study, label, labels
from results_format import markdown_table, p_text, percent, ratio, relative, reproduce_section, seconds

from frontier_rl.evaluation.report.plots import box_plot, paired_scatter
from frontier_rl.evaluation.results.summary import MethodSummary, PairedSummary

THESIS_REDUCTION_PCT = 8.4
"""What the thesis reported for its model 4 against w = 0.75 (%), quoted from it, not measured here."""


def comparison_rows(run: Experiment, names: dict[str, str]) -> list[list[str]]:
    """Per method: n, mean and sd of the time, the saving against the baseline with its 95 % CI,
    the one-tailed paired t-test (Holm-adjusted where several methods are tested), Wilcoxon, the
    time over the oracle's and the episodes explored."""
    summary = run.summary
    rows = []
    for method, entry in summary.methods.items():
        compared = method != summary.baseline
        rows.append(
            [
                names[method] + (" (baseline)" if not compared else ""),
                str(entry.n),
                seconds(entry.mean_time_s),
                seconds(entry.std_time_s),
                percent(entry.reduction_pct) if compared else "",
                _ci(entry) if compared else "",
                p_text(tested_p(entry)) if compared else "",
                p_text(entry.p_wilcoxon) if compared else "",
                ratio(entry.oracle_ratio),
                _explored(entry),
            ]
        )
    return rows


COMPARISON_HEADER = (
    "method",
    "n",
    "mean time (s)",
    "sd (s)",
    "less time than the baseline",
    "95 % CI of the saving (s)",
    "p (one-tailed t, Holm)",
    "p (Wilcoxon)",
    "time / oracle",
    "explored",
)


def tested_p(entry: MethodSummary) -> float | None:
    """A method's one-tailed p against the baseline, Holm-adjusted over the methods tested where it is
    one of them (the oracle, a reference, is not)."""
    return entry.p_holm if entry.p_holm is not None else entry.p_one_tailed


def _ci(entry: PairedSummary) -> str:
    low, high = entry.ci95_s
    return f"{seconds(low)} … {seconds(high)}"


def _explored(entry: MethodSummary) -> str:
    reasons = entry.end_reasons or {}
    return f"{reasons.get('explored', 0)} / {entry.n}"


OUTLIER_HEADER = (
    "threshold",
    "method",
    "pairs left out",
    "pairs kept",
    "baseline mean (s)",
    "method mean (s)",
    "less time",
    "p (one-tailed t)",
)


def _outlier_rows(run: Experiment, names: dict[str, str]) -> list[list[str]]:
    rows = []
    for cut in run.summary.outliers:
        for method, entry in cut.methods.items():
            if method in (run.summary.baseline, run.summary.reference):
                continue
            rows.append(
                [
                    f"> {cut.threshold_s:,.0f} s",
                    names[method],
                    str(entry.excluded),
                    str(entry.n),
                    seconds(entry.baseline_mean_time_s),
                    seconds(entry.mean_time_s),
                    percent(entry.reduction_pct),
                    p_text(entry.p_one_tailed),
                ]
            )
    return rows


def thesis_page(study: Study, images: Path) -> str:
    """The page: the thesis's protocol, its table and figures, the outlier cuts, the reproduction."""
    run = study.experiment()
    summary = run.summary
    names = labels(list(summary.methods))
    model = next(m for m in summary.tested)
    entry = summary.methods[model]
    times = {names[m]: run.times(m) for m in summary.methods}
    box = box_plot(times, images / "thesis_box.png", "Time to explore an office world")
    scatter = paired_scatter(
        {names[m]: times[names[m]] for m in summary.methods if m != summary.reference},
        names[summary.baseline],
        images / "thesis_scatter.png",
    )
    weights = sorted({e.mean_weight for e in run.of(model) if e.mean_weight is not None})
    verdict = "faster" if (entry.p_one_tailed or 1.0) < 0.05 else "not significantly faster"
    return f"""# The thesis's experiment

The thesis trained an A2C agent that reads the robot's map and chooses the weight w of the frontier
cost `w·d + (1−w)·(1−g)` (its model 4), and compared it with the fixed weight w = 0.75 over 120
paired episodes, with a one-tailed paired t-test at α = 0.05 and the episodes over 1,000 s and
2,000 s reported apart. It reported {THESIS_REDUCTION_PCT} % less time. This page runs the same
protocol on {summary.episodes} procedural office worlds whose seeds training never drew
(seeds {summary.seed} to {summary.seed + summary.episodes - 1}), with the shipped model 4
(`{model}`, trained by `frontier-rl train --model 4`), and the full-knowledge oracle as a reference
for how much time is left to gain.

**Result:** {label(model)} took {percent(entry.reduction_pct)} less time than `{summary.baseline}`
(p = {p_text(entry.p_one_tailed)}, one-tailed paired t-test; Wilcoxon p = {p_text(entry.p_wilcoxon)}):
{verdict} at α = 0.05, as the thesis found, by less. It chose
{_weights_text(weights)} The oracle, which plans a tour of the true map, took
{percent(summary.methods[summary.reference].reduction_pct if summary.reference else None)} less time than the
baseline.

## Exploration time

{markdown_table(COMPARISON_HEADER, comparison_rows(run, names))}
`time / oracle`: the mean time over the oracle's. `explored`: episodes that ended with no frontier
left that the robot could reach ([end reasons](../../concepts.md#end-reasons)).

![Box plot of the time to explore]({relative(box)})

![Each episode's time with model 4 against the baseline's]({relative(scatter)})

## Without the long episodes

The thesis reported its comparison again without the episodes over 1,000 s and over 2,000 s; a pair
is left out when either method's episode is over the threshold.

{markdown_table(OUTLIER_HEADER, _outlier_rows(run, names))}
{reproduce_section(study)}"""


def _weights_text(weights: list[float]) -> str:
    if not weights:
        return "no weight."
    if len(weights) == 1:
        return f"the same mean weight in every episode, w = {weights[0]:.2f}: it behaves as a constant."
    return f"mean weights per episode from {weights[0]:.2f} to {weights[-1]:.2f}."
