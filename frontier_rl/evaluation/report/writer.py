"""The experiment's report: ``summary.json``, the figures, ``report.md`` and a self-contained
``report.html``, all from the rows and traces of the results folder (and the runs drawn by
:mod:`~frontier_rl.evaluation.report.run_pictures`).

The page reads like a results section: the conclusion first, then the methods, the exploration
times with their statistics, the figures with how to read them, the runs, and the other metrics.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

from frontier_rl.atomic_write import write_text_atomic
from frontier_rl.core.frontiers.thesis import THESIS_WEIGHT
from frontier_rl.evaluation.report.conclusion import conclude
from frontier_rl.evaluation.report.page import Block, Figure, Heading, Paragraph, render_html, render_markdown
from frontier_rl.evaluation.report.plots import box_plot, coverage_plot, paired_scatter, team_size_plot, weight_plot
from frontier_rl.evaluation.report.run_pictures import RunPicture
from frontier_rl.evaluation.report.table import Table, short_labels
from frontier_rl.evaluation.report.tables import methods_table, outcome_tables, outlier_note, time_tables
from frontier_rl.evaluation.results.episode_record import EpisodeKey, EpisodeTrace
from frontier_rl.evaluation.results.store import ResultStore
from frontier_rl.evaluation.results.summary import SUMMARY_FILE, ExperimentSummary
from frontier_rl.evaluation.running.experiment import ExperimentConfig
from frontier_rl.evaluation.statistics.analysis import paired_times, summarise
from frontier_rl.policies.spec import BuiltinPolicy
from frontier_rl.swarm import TeamMethod

_FILES_NOTE = (
    "Files: episodes.csv (one row per episode), traces.jsonl (coverage curves, weights), checksums.jsonl (each "
    "row's checksum), summary.json (the numbers above), experiment.json (what the rows depend on), pictures/ (the "
    "runs shown)."
)


def write_report(
    store: ResultStore,
    config: ExperimentConfig,
    outliers: tuple[float, ...],
    command: str,
    pictures: Sequence[RunPicture] = (),
) -> Path:
    """Write the summary, figures and reports of ``config``'s experiment into ``store.out``, with
    ``pictures`` shown per world; returns the Markdown report's path. Each file is replaced
    atomically: a failure (a full disk) leaves its previous version and raises
    :class:`~frontier_rl.atomic_write.OutputWriteError`."""
    out = store.out
    summary = summarise(store.rows, config, outliers)
    write_text_atomic(out / SUMMARY_FILE, json.dumps(summary.to_json(), indent=1) + "\n")
    traces = _run_traces(store, config)
    labels = short_labels(config.methods)
    worlds = list(short_labels(config.worlds).values())
    shown = ", ".join(worlds[:6]) + (f" and {len(worlds) - 6} more worlds" if len(worlds) > 6 else "")
    title = f"Paired experiment: {len(config.methods)} methods, {shown}"
    conclusion = conclude(summary, labels | short_labels(config.worlds))
    blocks: list[Block] = [
        Paragraph(conclusion.headline, lead=True),
        *(Paragraph(text, lead=True) for text in conclusion.details),
        Paragraph(
            f"{config.episodes} episode(s) per world on {len(config.worlds)} world(s), seeds {config.seed} to "
            f"{config.seed + config.episodes - 1}. Paired design: episode i of every method has the same world, start "
            f"pose and sensor noise, so each method is compared with the baseline ({labels[config.baseline]}) "
            "episode by episode. The exploration time is the sim time until no frontier the robot could reach was "
            "left (or the cap)."
        ),
        Paragraph(command, code=True),
        Heading("Methods"),
        methods_table(config.methods),
        Heading("Exploration time"),
        *_with_note(time_tables(summary, config), outlier_note(summary)),
        Heading("Figures"),
        *_figures(store, config, summary),
    ]
    if pictures:
        blocks += [Heading("Runs"), *_run_blocks(pictures, config)]
    blocks += [Heading("How the episodes ended"), *outcome_tables(summary, config, traces)]
    blocks.append(Paragraph(_FILES_NOTE))
    report_md = out / "report.md"
    write_text_atomic(report_md, render_markdown(title, blocks, out))
    write_text_atomic(out / "report.html", render_html(title, blocks))
    return report_md


def _with_note(tables: list[Table], note: str) -> list[Block]:
    """The tables, with ``note`` (the outlier cuts left out) after the first."""
    return [tables[0], *([Paragraph(note)] if note else []), *tables[1:]]


def _run_traces(store: ResultStore, config: ExperimentConfig) -> dict[str, list[EpisodeTrace]]:
    """Each method's traces of this run's episodes: a folder run before with more episodes or
    other worlds keeps theirs too, and they are not this run's."""
    keys = [(w, e) for e in range(config.episodes) for w in config.worlds]
    return {
        m: [store.traces[key] for w, e in keys if (key := EpisodeKey(m, w, e)) in store.traces] for m in config.methods
    }


def _figures(store: ResultStore, config: ExperimentConfig, summary: ExperimentSummary) -> list[Figure]:
    out = store.out
    labels = short_labels(config.methods)
    times = {labels[m]: t for m, t in paired_times(store.rows, config.methods, config.worlds, config.episodes).items()}
    traces = _run_traces(store, config)
    baseline = labels[config.baseline]
    figures = [
        Figure(
            box_plot(times, out / "boxplot.png", "Exploration time per method"),
            "Exploration time per method",
            "Exploration time of every episode, per method. The box spans the 25th to the 75th percentile, the "
            "line in it is the median and the triangle the mean; the whiskers reach the farthest episodes "
            "within 1.5 box lengths, circles are the episodes beyond.",
        ),
        Figure(
            paired_scatter(times, baseline, out / "scatter.png"),
            "Paired episodes against the baseline",
            f"Each point is one episode: its exploration time with the baseline {baseline} (x) and with the "
            "method (y). Points below the dashed diagonal are episodes the method explored faster than the "
            "baseline, points above it slower; the axes span the times measured.",
        ),
        Figure(
            coverage_plot({labels[m]: t for m, t in traces.items()}, out / "coverage.png"),
            "Coverage over time",
            "Share of the explorable space mapped over sim time: the line is the mean over episodes, the band "
            "spans the 25th to the 75th percentile; an episode that has ended keeps its final coverage.",
        ),
    ]
    chosen = {labels[m]: t for m, t in traces.items() if _chooses_weights(m) and any(tr.weight for tr in t)}
    if chosen:
        caption = (
            "The weight w of eq. 3.1 each method that chooses it (a learned weight model, a policy of yours that "
            "reports it) chose at each decision (dots) and its mean per time bin (line); the dashed line is the "
            f"thesis's w = {THESIS_WEIGHT}."
        )
        figures.append(Figure(weight_plot(chosen, out / "weights.png"), "Weight chosen over time", caption))
    if summary.teams:
        figures.append(
            Figure(
                team_size_plot(summary.teams, out / "teams.png"),
                "Exploration time against team size",
                "Mean exploration time against team size, per policy and strategy; the bars are 95 % "
                "confidence intervals of the mean.",
            )
        )
    return figures


def _run_blocks(pictures: Sequence[RunPicture], config: ExperimentConfig) -> list[Block]:
    """The pictures under a heading per world."""
    world_labels = short_labels(config.worlds)
    blocks: list[Block] = []
    for world in dict.fromkeys(p.world for p in pictures):
        blocks.append(Heading(f"World {world_labels[world]}", level=3))
        blocks += [Figure(p.path, p.title, p.caption, chart=False) for p in pictures if p.world == world]
    return blocks


def _chooses_weights(method: str) -> bool:
    """Whether ``method`` may choose a weight at each decision: any but ``fixed:W``, whose weight is
    its name (a user's policy that reports weights in its rankings has a weight plot too)."""
    return TeamMethod.parse(method).policy.builtin is not BuiltinPolicy.FIXED
