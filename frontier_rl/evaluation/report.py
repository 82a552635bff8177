"""The experiment's report: ``summary.json``, the figures, ``report.md`` and a self-contained
``report.html`` (figures embedded), all from the rows and traces of the results folder."""

from __future__ import annotations

import base64
import html
import json
from pathlib import Path
from typing import Any

import numpy as np

from frontier_rl.atomic_write import write_text_atomic
from frontier_rl.evaluation.analysis import paired_times, summarise
from frontier_rl.evaluation.experiment import ORACLE, ExperimentConfig
from frontier_rl.evaluation.plots import box_plot, coverage_plot, paired_scatter, team_size_plot, weight_plot
from frontier_rl.evaluation.results import ResultStore
from frontier_rl.evaluation.statistics import stats_from_dict
from frontier_rl.evaluation.tables import (
    TABLE_4_1_HEADER,
    Table,
    completion_table,
    number,
    short_labels,
    table_4_1_row,
)
from frontier_rl.swarm.config import TeamMethod

_MAX_WORLD_TABLES = 12
"""Per-world tables are written for at most this many worlds (a folder of maps can hold hundreds)."""

_CSS = (
    "body{font-family:system-ui,sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}"
    "table{border-collapse:collapse;margin:1em 0;font-size:0.9em}caption{font-weight:bold;text-align:left;"
    "padding:0.3em 0}th,td{border:1px solid #ccc;padding:0.25em 0.6em;text-align:right}"
    "th:first-child,td:first-child{text-align:left}img{max-width:100%}.note{font-size:0.85em;color:#555}"
)


def write_report(store: ResultStore, config: ExperimentConfig, outliers: tuple[float, ...], command: str) -> Path:
    """Write the summary, figures and reports of ``config``'s experiment into ``store.out``;
    returns the Markdown report's path. Each file is replaced atomically: a failure (a full disk)
    leaves its previous version and raises :class:`~frontier_rl.atomic_write.OutputWriteError`."""
    out = store.out
    summary = summarise(store.rows, config, outliers)
    write_text_atomic(out / "summary.json", json.dumps(summary, indent=1) + "\n")
    figures = _figures(store, config, summary)
    traces = {m: [t for (method, _, _), t in store.traces.items() if method == m] for m in config.methods}
    tables = report_tables(summary, config, traces)
    worlds = list(short_labels(config.worlds).values())
    shown = ", ".join(worlds[:6]) + (f" and {len(worlds) - 6} more worlds" if len(worlds) > 6 else "")
    title = f"Paired experiment: {len(config.methods)} methods, {shown}"
    intro = (
        f"{config.episodes} episode(s) per world, seeds {config.seed} to {config.seed + config.episodes - 1}; "
        f"episode i of every method has the same world, start pose and sensor noise. Baseline: "
        f"{short_labels(config.methods)[config.baseline]}."
    )
    markdown = [f"# {title}", "", intro, "", f"Command: `{command}`", ""]
    for table in tables:
        markdown += [table.markdown()]
    for caption, path in figures:
        markdown += [f"![{caption}]({path.name})", ""]
    markdown += ["Files: `episodes.csv` (one row per episode), `traces.jsonl` (coverage curves, weights), "
                 "`checksums.jsonl` (each row's checksum), `summary.json` (the numbers above), `experiment.json` "
                 "(what the rows depend on).", ""]  # fmt: skip
    report_md = out / "report.md"
    write_text_atomic(report_md, "\n".join(markdown))
    body = [f"<h1>{html.escape(title)}</h1>", f"<p>{html.escape(intro)}</p>",
            f"<p>Command: <code>{html.escape(command)}</code></p>", *(t.html() for t in tables)]  # fmt: skip
    for caption, path in figures:
        data = base64.b64encode(path.read_bytes()).decode()
        body.append(f'<figure><img alt="{html.escape(caption)}" src="data:image/png;base64,{data}"></figure>')
    page = (
        f'<!DOCTYPE html><html lang="en"><head><meta charset="utf-8"><title>{html.escape(title)}</title>'
        f"<style>{_CSS}</style></head><body>{''.join(body)}</body></html>\n"
    )
    write_text_atomic(out / "report.html", page)
    return report_md


def report_tables(
    summary: dict[str, Any], config: ExperimentConfig, teams_traces: dict[str, list[dict[str, Any]]] | None = None
) -> list[Table]:
    """Table 4.1 of all episodes (with the ratio to the oracle), of each outlier cut and of each
    world, a table of the other metrics, one of how the episodes ended, and one of the team methods
    (``teams_traces``: their traces, for the per-robot figures)."""
    labels = short_labels(config.methods)
    world_labels = short_labels(config.worlds)
    main = _table_4_1(summary["methods"], config, labels, "Exploration time, all episodes", oracle=True)
    capped = {m: e["end_reasons"]["time_cap"] for m, e in summary["methods"].items() if e["end_reasons"]["time_cap"]}
    if capped:
        note = ", ".join(f"{labels[m]} {k}" for m, k in capped.items())
        note = f"{main.note} Episodes cut at the sim-time cap (their time counts as the cap): {note}.".strip()
        main = Table(main.header, main.rows, main.title, note)
    tables = [main]
    for threshold, cut in summary["outliers"].items():
        table = _table_4_1(cut["methods"], config, labels, f"Without episodes above {threshold} s")
        extra = [
            ["" if m == config.baseline else number(e["baseline_mean_time_s"]), str(e["excluded"])]
            for m, e in cut["methods"].items()
        ]
        tables.append(Table(
            (*table.header, "paired baseline mean (s)", "excluded"),
            [[*row, *more] for row, more in zip(table.rows, extra, strict=True)],
            table.title,
            "Each method against the baseline on the episodes where neither took longer than the threshold; the "
            "baseline's own row drops only its own long episodes.",
        ))  # fmt: skip
    per_world = summary.get("per_world", {})
    for world, part in list(per_world.items())[:_MAX_WORLD_TABLES]:
        tables.append(_table_4_1(part["methods"], config, labels, f"World {world_labels[world]}", oracle=True))
    if len(per_world) > _MAX_WORLD_TABLES:
        tables[-1] = Table(tables[-1].header, tables[-1].rows, tables[-1].title,
                           f"Tables of the other {len(per_world) - _MAX_WORLD_TABLES} worlds: per_world in "
                           "summary.json.")  # fmt: skip
    metrics = Table(
        ("method", "episodes done", "coverage", "path (m)", "t90 (s)", "t99 (s)", "aborts", "mean weight",
         "wall per episode (s)"),
        title="Other metrics (means over episodes; t90 and t99 over the episodes that reached them)",
    )  # fmt: skip
    for method, e in summary["methods"].items():
        metrics.rows.append([
            labels[method], f"{e['episodes_done']} / {e['n']}", number(100 * e["mean_coverage"], 2, " %"),
            number(e["mean_path_length_m"]), number(e["mean_t90_s"]), number(e["mean_t99_s"]),
            number(e["mean_aborts"], 2), number(e["mean_weight"], 3), number(e["mean_wall_time_s"], 2),
        ])  # fmt: skip
    tables.append(metrics)
    tables.append(completion_table(summary["methods"], labels))
    if "teams" in summary:
        tables.append(_team_table(summary, labels, teams_traces or {}))
    return tables


def _team_table(summary: dict[str, Any], labels: dict[str, str], traces: dict[str, list[dict[str, Any]]]) -> Table:
    """Team methods: size, speed-up over the same policy alone, overlap, per-robot coverage, failures."""
    table = Table(
        ("method", "robots", "mean time (s)", "speed-up over 1 robot", "overlap", "coverage per robot",
         "robots failed"),
        title="Teams (speed-up: the policy's one-robot mean time over the team's)",
        note="overlap: share of the cells the robots' own sensors reached that more than one robot's did; "
        "coverage per robot: the share of the explorable space each robot's own sensor reached (mean, min - max "
        "over robots, averaged over episodes).",
    )  # fmt: skip
    methods = summary["methods"]
    for method, entry in methods.items():
        team = TeamMethod.parse(method)
        if team.robots is None:
            continue
        alone = methods.get(team.policy)
        speedup = alone["mean_time_s"] / entry["mean_time_s"] if alone and entry["mean_time_s"] > 0 else None
        own = traces.get(method, [])
        per_robot = [t["robot_coverage"] for t in own if t.get("robot_coverage")]
        coverage = "n/a"
        if per_robot:
            mean, low, high = (float(np.mean([f(c) for c in per_robot])) for f in (np.mean, np.min, np.max))
            coverage = f"{100 * mean:.0f} % ({100 * low:.0f} - {100 * high:.0f} %)"
        failed = sum(sum(f is not None for f in t.get("failed_at_s", [])) for t in own)
        table.rows.append([labels[method], str(team.robots), number(entry["mean_time_s"]),
                           number(speedup, 2, " ×"), number(100 * entry["mean_overlap"], 0, " %"), coverage,
                           f"{failed} in {len(own)} episodes"])  # fmt: skip
    return table


def _table_4_1(
    entries: dict[str, dict[str, Any]], config: ExperimentConfig, labels: dict[str, str], title: str,
    oracle: bool = False,
) -> Table:  # fmt: skip
    rows = [table_4_1_row(labels[m], stats_from_dict(e), m == config.baseline) for m, e in entries.items()]
    if not oracle or ORACLE not in entries:
        return Table(TABLE_4_1_HEADER, rows, title)
    ratios = [number(e["oracle_ratio"], 2, " ×") for e in entries.values()]
    return Table(
        (*TABLE_4_1_HEADER, "time / oracle"),
        [[*row, ratio] for row, ratio in zip(rows, ratios, strict=True)],
        title,
        "time / oracle: mean exploration time over the full-knowledge coverage tour's (1.00 × would be as fast "
        "as a robot that knows the map).",
    )


def _figures(store: ResultStore, config: ExperimentConfig, summary: dict[str, Any]) -> list[tuple[str, Path]]:
    out = store.out
    labels = short_labels(config.methods)
    times = {labels[m]: t for m, t in paired_times(store.rows, config.methods, config.worlds, config.episodes).items()}
    keys = [(w, e) for e in range(config.episodes) for w in config.worlds]
    traces = {m: [store.traces[(m, w, e)] for w, e in keys if (m, w, e) in store.traces] for m in config.methods}
    baseline = labels[config.baseline]
    figures = [
        ("Exploration time per method", box_plot(times, out / "boxplot.png", "Exploration time per method")),
        ("Paired episodes against the baseline", paired_scatter(times, baseline, out / "scatter.png")),
        ("Coverage over time", coverage_plot({labels[m]: t for m, t in traces.items()}, out / "coverage.png")),
    ]
    learned = {labels[m]: t for m, t in traces.items() if m.startswith("learned:") and any(tr["weight"] for tr in t)}
    if learned:
        figures.append(("Weight chosen over time", weight_plot(learned, out / "weights.png")))
    if "teams" in summary:
        figures.append(("Exploration time against team size", team_size_plot(summary["teams"], out / "teams.png")))
    return figures
