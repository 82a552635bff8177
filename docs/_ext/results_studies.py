"""The results pages of the office policies, the families of worlds and the thesis's four models."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from matplotlib.figure import Figure
from results_data import Experiment, Study, label, labels
from results_format import markdown_table, p_text, percent, ratio, relative, reproduce_section, save, seconds
from results_thesis import COMPARISON_HEADER, comparison_rows, tested_p

from frontier_rl.evaluation.report.plots import box_plot
from frontier_rl.evaluation.statistics.paired import paired_stats
from frontier_rl.rl.validation_log import VALIDATION_FILE, read_validations

SWEEP_PREFIX = "fixed:"


def _sweep(methods: list[str]) -> list[str]:
    """The methods of the weight sweep (fixed:0.00 ... fixed:1.00, written with two decimals)."""
    sweep = [m for m in methods if m.startswith(SWEEP_PREFIX) and len(m) == len("fixed:0.00")]
    return sorted(sweep, key=lambda m: float(m.removeprefix(SWEEP_PREFIX)))


def office_page(study: Study, images: Path) -> str:
    """Every policy on the same office worlds, with the sweep of the fixed weight."""
    run = study.experiment()
    summary = run.summary
    methods = list(summary.methods)
    sweep = _sweep(methods)
    main = [m for m in methods if m not in sweep or m == summary.baseline]
    sweep_info = study.json("summary.json")["sweep"]  # type: ignore[index]
    best = f"fixed:{sweep_info['best_weight']:.2f}"
    shown = sorted([*main, best] if best not in main else main, key=lambda m: summary.methods[m].mean_time_s or 0.0)
    names = labels(methods)
    subset = Experiment(replace(summary, methods={m: summary.methods[m] for m in shown}), run.episodes)
    times = {names[m]: run.times(m) for m in shown}
    box = box_plot(times, images / "office_box.png", "Time to explore an office world")
    curve = save(_sweep_figure(run, sweep, [m for m in main if m not in sweep]), images / "office_sweep.png")
    low, q1, median, q3, high = sweep_info["per_world_best_weight_quartiles"]
    twins = _identical(run, shown)
    return f"""# Every policy on office worlds

The thesis's world: procedural office mazes of 12.5 m × 12.5 m, {summary.episodes} of them (seeds
{summary.seed} to {summary.seed + summary.episodes - 1}, never drawn in training). Every method explores
the same worlds from the same starts with the same sensor noise, so the comparison is paired;
`{summary.baseline}` is the baseline and the p-values are Holm-adjusted over the
{len(summary.tested)} methods tested (the weight sweep included). Beside the built-in policies and the
shipped models, the experiment sweeps the fixed weight of eq. 3.1 from 0 to 1 in steps of 0.05: how
good can a constant weight be, and what is left for a weight chosen from the map?

## Exploration time

{markdown_table(COMPARISON_HEADER, comparison_rows(subset, names))}
The table shows the sweep's best weight; the others are in the figure below. {twins}

![Box plot of the time to explore]({relative(box)})

## The weight sweep

![Mean time against the fixed weight]({curve})

The best constant weight is w = {sweep_info["best_weight"]:.2f}
({seconds(sweep_info["best_mean_time_s"])} s on average). The weight that is best for a world,
picked in hindsight from the sweep, ranges from {low:.2f} to {high:.2f} (quartiles {q1:.2f},
{median:.2f}, {q3:.2f}); using each world's best weight would take
{seconds(sweep_info["per_world_oracle_mean_time_s"])} s on average, an optimistic bound for any
weight policy (the hindsight pick also picks each world's luckiest run).

{reproduce_section(study)}"""


def _identical(run: Experiment, methods: list[str]) -> str:
    """A sentence naming the methods that took the same time in every episode (the same ranking)."""
    pairs = [(a, b) for i, a in enumerate(methods) for b in methods[i + 1 :] if run.times(a) == run.times(b)]
    return " ".join(
        f"`{label(a)}` and `{label(b)}` took the same time in every episode: they rank the frontiers alike."
        for a, b in pairs
    )


def _sweep_figure(run: Experiment, sweep: list[str], others: list[str]) -> Figure:
    fig = Figure(figsize=(7.0, 4.2), layout="constrained")
    ax = fig.subplots()
    weights = [float(m.split(":")[1]) for m in sweep]
    means = [run.summary.methods[m].mean_time_s for m in sweep]
    ax.plot(weights, means, marker="o", ms=3, color="0.3", label="fixed weight w")
    for index, method in enumerate(others):
        mean_s = run.summary.methods[method].mean_time_s or 0.0
        ax.axhline(mean_s, lw=1, ls="--", color=f"C{index % 10}", label=label(method))
    ax.set_xlabel("weight w of eq. 3.1 (1: distance only, 0: size only)")
    ax.set_ylabel("mean time to explore (s)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncols=2)
    return fig


FAMILY_NAMES = {
    "office": "office (12.5 m mazes)",
    "rooms": "rooms",
    "cluttered": "cluttered (rubble)",
    "building": "building (30–60 m floors)",
    "cave": "cave",
    "dungeon-easy": "DungeonMaps easy",
    "dungeon-medium": "DungeonMaps medium",
    "dungeon-complex": "DungeonMaps complex",
}


def families_page(study: Study, images: Path) -> str:
    """A learned policy in buildings it never saw: every family against ``nearest``."""
    rows = []
    order = list(FAMILY_NAMES)
    parts = sorted(study.parts(), key=lambda part: order.index(part) if part in order else len(order))
    for part in parts:
        run = study.experiment(part)
        s = run.summary
        tested = list(s.tested)
        base = s.methods[s.baseline]
        cells = [f"{FAMILY_NAMES.get(part, part)} ({base.n})", seconds(base.mean_time_s)]
        for method in tested:
            e = s.methods[method]
            cells.append(
                f"{seconds(e.mean_time_s)} s, {percent(e.reduction_pct)}, p = {p_text(e.p_one_tailed)}, "
                f"{ratio(e.oracle_ratio)}"
            )
        if len(tested) == 2:
            versus = paired_stats(run.times(tested[1]), run.times(tested[0]))
            more = "less" if (versus.reduction_pct or 0.0) >= 0 else "more"
            cells.append(f"{percent(abs(versus.reduction_pct or 0.0))} {more}, p = {p_text(versus.p_two_tailed)}")
        unfinished = sum(e.n - (e.end_reasons or {}).get("explored", 0) for e in s.methods.values())
        cells += [seconds(s.methods[s.reference].mean_time_s) if s.reference else "n/a", str(unfinished)]
        rows.append(cells)
    first = study.experiment(parts[0]).summary
    tested = [label(m) for m in first.tested]
    header = (
        "family (episodes)",
        f"`{first.baseline}` (s)",
        *(f"{t}: time, less than `{first.baseline}`, p, × oracle" for t in tested),
        *([f"{tested[1]} against {tested[0]}"] if len(tested) == 2 else []),
        "oracle (s)",
        "episodes not explored",
    )
    return f"""# Any building: the families of worlds

A policy is only worth using if it holds in buildings it never saw. Each family below is a paired
experiment against `{first.baseline}` with the oracle as the reference: the generators' worlds at
seeds training never drew, the 30–60 m `building` floors, `cave` systems no shipped model was
trained on, and the test maps of DungeonMaps (Chen et al. 2019, as ARiADNE ships them; training
reads only their `train` folder), one episode per map. Model 7 was trained on office worlds
alone. The p-values are one-tailed paired t-tests against `{first.baseline}`; the column of the two
methods against each other is a two-sided paired t-test.

{markdown_table(header, rows)}
`× oracle`: mean time over the full-knowledge oracle's. The oracle plans the shortest tour of the true
map's viewpoints, which is not always the fastest way to explore (on rubble and caves the policies can
beat it). `episodes not explored`: over every method, those that ended unreachable or at the time cap.

{reproduce_section(study)}"""


def thesis_models_page(study: Study, images: Path) -> str:
    """The thesis's four models trained with the project's command, beside the shipped ones."""
    run = study.experiment("evaluation")
    s = run.summary
    names = labels(list(s.methods))
    curves = save(_curves_figure(study), images / "thesis_models_curves.png")
    rows = []
    for method, e in s.methods.items():
        reasons = e.end_reasons or {}
        weights = sorted({x.mean_weight for x in run.of(method) if x.mean_weight is not None})
        chosen = (
            "—"
            if not weights
            else (
                f"{weights[0]:.2f} in every episode" if len(weights) == 1 else f"{weights[0]:.2f} to {weights[-1]:.2f}"
            )
        )
        rows.append(
            [
                names[method] + (" (baseline)" if method == s.baseline else ""),
                seconds(e.mean_time_s),
                "" if method == s.baseline else f"{percent(e.reduction_pct)}, p = {p_text(tested_p(e))}",
                percent(100 * (e.mean_coverage or 0.0)),
                f"{reasons.get('explored', 0)} / {e.n}",
                str(reasons.get("time_cap", 0)),
                chosen,
            ]
        )
    table = markdown_table(
        (
            "model",
            "mean time (s)",
            f"less time than `{s.baseline}` (p: one-tailed, Holm)",
            "mean coverage",
            "explored",
            "time cap",
            "mean weight chosen",
        ),
        rows,
    )
    return f"""# The thesis's four models

The thesis defined four models and trained them with A2C: models 1 and 2 choose a map cell to drive
to (1 with frontier and pose channels beside the map, 2 from the map alone), models 3 and 4 choose
the weight of eq. 3.1 (3 with the channels, 4 from the map alone; only model 4 converged for the
thesis). Models 1 to 3 are trained here by the project's own command with a quarter of model 4's
budget; models 4, 5 (a frontier chosen directly, the thesis's future work) and 7 (model 5 with a
tour column) are the shipped ones. All run on the same {s.episodes} office worlds against
`{s.baseline}`.

{table}
A weight model whose mean weight is the same in every episode chose one constant: it did not learn
to read the map. A point model that reaches the time cap never learned to drive to a frontier.

![Validation time during training]({curves})

The validation curve is the mean time of the run's validation episodes at each evaluation during
training (an episode cut at the time cap counts its full time).

{reproduce_section(study)}"""


def _curves_figure(study: Study) -> Figure:
    fig = Figure(figsize=(7.0, 4.0), layout="constrained")
    ax = fig.subplots()
    for path in sorted(study.folder.glob(f"model*/{VALIDATION_FILE}")):
        validations = read_validations(path)
        ax.plot(
            [v.timesteps for v in validations],
            [v.mean_time_s for v in validations],
            marker="o",
            ms=3,
            label=f"model {path.parent.name.removeprefix('model')}",
        )
    ax.set_xlabel("training decisions")
    ax.set_ylabel("validation mean time (s)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return fig


def office_readme_table(study: Study, figure: Path) -> tuple[str, str]:
    """The README's table (every policy but the sweep's other weights, fastest first) and its caption;
    draws its box plot into ``figure``."""
    run = study.experiment()
    summary = run.summary
    methods = [m for m in summary.methods if m not in _sweep(list(summary.methods)) or m == summary.baseline]
    methods.sort(key=lambda m: summary.methods[m].mean_time_s or 0.0)
    names = labels(methods)
    rows = []
    for method in methods:
        e = summary.methods[method]
        compared = method != summary.baseline
        shown = f"`{method}`" if names[method] == method else f"{names[method]} (`{method}`)"
        rows.append(
            [
                f"{shown} (knows the map: a reference)" if method == summary.reference else shown,
                seconds(e.mean_time_s),
                percent(e.reduction_pct) if compared else "baseline",
                p_text(e.p_holm) if compared and method != summary.reference else "",
                ratio(e.oracle_ratio),
            ]
        )
    box_plot({names[m]: run.times(m) for m in methods}, figure, f"Time to explore {summary.episodes} office worlds")
    caption = (
        f"Mean time to explore {summary.episodes} office worlds that training never saw; every method on the "
        "same worlds, starts and sensor noise. p: one-tailed paired t-test against the thesis's baseline "
        f"`{summary.baseline}`, Holm-adjusted. More in the [results](docs/results/index.md)."
    )
    header = ("method", "mean time (s)", f"less time than `{summary.baseline}`", "p", "time / oracle")
    return markdown_table(header, rows), caption
