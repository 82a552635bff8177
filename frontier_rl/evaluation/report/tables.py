"""The report's tables, from an experiment's summary: Table 4.1 of all episodes (with the oracle ratio
and, when several methods are tested, Holm's adjusted p), of the outlier cuts that excluded an
episode, of each world; the other metrics, how episodes ended, the team methods and the methods
themselves."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from frontier_rl.core.sim.metrics import EndReason
from frontier_rl.evaluation.report.method_notes import describe_method
from frontier_rl.evaluation.report.table import (
    TABLE_4_1_HEADER,
    Table,
    completion_table,
    number,
    p_value,
    percent,
    short_labels,
    table_4_1_row,
)
from frontier_rl.evaluation.results.episode_record import EpisodeTrace
from frontier_rl.evaluation.results.summary import ExperimentSummary, MethodSummary, OutlierCut, PairedSummary
from frontier_rl.evaluation.running.experiment import ExperimentConfig
from frontier_rl.evaluation.running.methods import ORACLE
from frontier_rl.evaluation.statistics.paired import THESIS_OUTLIERS_S
from frontier_rl.swarm.config import TeamMethod, one_robot_methods

TeamTraces = Mapping[str, Sequence[EpisodeTrace]]
"""The traces of each team method's episodes (their per-robot coverage and failures)."""

_MAX_WORLD_TABLES = 12
"""Per-world tables are written for at most this many worlds (a folder of maps can hold hundreds)."""


def report_tables(
    summary: ExperimentSummary,
    config: ExperimentConfig,
    teams_traces: TeamTraces | None = None,
) -> list[Table]:
    """:func:`time_tables` then :func:`outcome_tables`."""
    return [*time_tables(summary, config), *outcome_tables(summary, config, teams_traces)]


def time_tables(summary: ExperimentSummary, config: ExperimentConfig) -> list[Table]:
    """Table 4.1 of all episodes (with the ratio to the oracle and Holm's p), of each outlier cut
    that left an episode out, and of each world."""
    labels = short_labels(config.methods)
    world_labels = short_labels(config.worlds)
    main = _table_4_1(summary.methods, config, labels, "Exploration time, all episodes", oracle=True)
    capped = {m: _capped(e) for m, e in summary.methods.items() if _capped(e)}
    if capped:
        note = ", ".join(f"{labels[m]} {k}" for m, k in capped.items())
        note = f"{main.note} Episodes cut at the sim-time cap (their time counts as the cap): {note}.".strip()
        main = Table(main.header, main.rows, main.title, note)
    tables = [main, *outlier_tables(summary, config, labels)]
    per_world = summary.per_world
    for world, part in list(per_world.items())[:_MAX_WORLD_TABLES]:
        tables.append(_table_4_1(part, config, labels, f"World {world_labels[world]}", oracle=True))
    if len(per_world) > _MAX_WORLD_TABLES:
        tables[-1] = Table(
            tables[-1].header,
            tables[-1].rows,
            tables[-1].title,
            f"Tables of the other {len(per_world) - _MAX_WORLD_TABLES} worlds: per_world in summary.json.",
        )
    return tables


def outcome_tables(
    summary: ExperimentSummary,
    config: ExperimentConfig,
    teams_traces: TeamTraces | None = None,
) -> list[Table]:
    """How the episodes ended, the other metrics, and the team methods (``teams_traces``: their
    traces, for the per-robot coverage)."""
    labels = short_labels(config.methods)
    metrics = Table(
        (
            "method",
            "episodes done",
            "coverage",
            "path (m)",
            "t90 (s)",
            "t99 (s)",
            "aborts",
            "mean weight",
            "wall per episode (s)",
        ),
        title="Other metrics (means over episodes; t90 and t99 over the episodes that reached them)",
    )
    for method, e in summary.methods.items():
        metrics.rows.append(
            [
                labels[method],
                f"{e.episodes_done} / {e.n}",
                percent(e.mean_coverage),
                number(e.mean_path_length_m),
                number(e.mean_t90_s),
                number(e.mean_t99_s),
                number(e.mean_aborts, 2),
                number(e.mean_weight, 3),
                number(e.mean_wall_time_s, 2),
            ]
        )
    tables = [completion_table(summary.methods, labels), metrics]
    if summary.teams:
        tables.append(_team_table(summary, labels, teams_traces or {}))
    return tables


def outlier_tables(summary: ExperimentSummary, config: ExperimentConfig, labels: dict[str, str]) -> list[Table]:
    """Table 4.1 without the episodes above each outlier threshold, for the thresholds that left an
    episode out (the others would repeat the table of all episodes)."""
    tables = []
    for cut in summary.outliers:
        if not _left_out(cut):
            continue
        table = _table_4_1(cut.methods, config, labels, f"Without episodes above {cut.threshold_s:g} s")
        extra = [
            ["" if m == config.baseline else number(e.baseline_mean_time_s), str(e.excluded)]
            for m, e in cut.methods.items()
        ]
        tables.append(
            Table(
                (*table.header, "paired baseline mean (s)", "excluded"),
                [[*row, *more] for row, more in zip(table.rows, extra, strict=True)],
                table.title,
                "Each method against the baseline on the episodes where neither took longer than the threshold; the "
                "baseline's own row drops only its own long episodes.",
            )
        )
    return tables


def outlier_note(summary: ExperimentSummary) -> str:
    """One line naming the outlier thresholds that left no episode out ("" if there are none)."""
    clean = [f"{cut.threshold_s:g}" for cut in summary.outliers if not _left_out(cut)]
    if not clean:
        return ""
    thesis = {cut.threshold_s for cut in summary.outliers} == set(THESIS_OUTLIERS_S)
    whose = " (the thesis's outlier thresholds)" if thesis else ""
    return (
        f"No episode took longer than {' or '.join(f'{t} s' for t in clean)}{whose}, so the tables "
        "without outliers would repeat the one above and are left out."
    )


def _left_out(cut: OutlierCut) -> bool:
    """Whether an outlier cut left any episode out."""
    return any(e.excluded for e in cut.methods.values())


def _capped(entry: MethodSummary) -> int:
    """The episodes of ``entry`` cut at the time cap."""
    return (entry.end_reasons or {}).get(EndReason.TIME_CAP, 0)


def methods_table(methods: tuple[str, ...]) -> Table:
    """What every method of the run is and its parameters."""
    labels = short_labels(methods)
    table = Table(("method", "what it does", "parameters"), wrap=True)
    for method in methods:
        note = describe_method(method)
        table.rows.append([labels[method], note.description, note.parameters or "none"])
    return table


def _team_table(summary: ExperimentSummary, labels: dict[str, str], traces: TeamTraces) -> Table:
    """Team methods: size, speed-up over the same policy alone, overlap, per-robot coverage, failures."""
    table = Table(
        (
            "method",
            "robots",
            "mean time (s)",
            "speed-up over 1 robot",
            "overlap",
            "coverage per robot",
            "robots failed",
        ),
        title="Teams (speed-up: the policy's one-robot mean time over the team's)",
        note="overlap: share of the cells the robots' own sensors reached that more than one robot's did; "
        "coverage per robot: the share of the explorable space each robot's own sensor reached (mean, min - max "
        "over robots, averaged over episodes).",
    )
    methods = summary.methods
    alone_of = one_robot_methods(methods)
    for method, entry in methods.items():
        team = TeamMethod.parse(method)
        if team.robots is None:
            continue
        alone = methods[alone_of[team.policy.canonical]] if team.policy.canonical in alone_of else None
        speedup = None
        if alone and alone.mean_time_s is not None and entry.mean_time_s:  # a time of 0 s: no speed-up
            speedup = alone.mean_time_s / entry.mean_time_s
        own = traces.get(method, [])
        per_robot = [t.robot_coverage for t in own if t.robot_coverage]
        coverage = "n/a"
        if per_robot:
            mean, low, high = (float(np.mean([f(c) for c in per_robot])) for f in (np.mean, np.min, np.max))
            coverage = f"{100 * mean:.0f} % ({100 * low:.0f} - {100 * high:.0f} %)"
        failed = sum(sum(f is not None for f in t.failed_at_s or ()) for t in own)
        table.rows.append(
            [
                labels[method],
                str(team.robots),
                number(entry.mean_time_s),
                number(speedup, 2, " ×"),
                percent(entry.mean_overlap, 0),
                coverage,
                f"{failed} in {len(own)} episodes",
            ]
        )
    return table


def _table_4_1(
    entries: Mapping[str, PairedSummary],
    config: ExperimentConfig,
    labels: dict[str, str],
    title: str,
    oracle: bool = False,
) -> Table:
    rows = [table_4_1_row(labels[m], e, m == config.baseline) for m, e in entries.items()]
    header: tuple[str, ...] = TABLE_4_1_HEADER
    notes = []
    tested = [m for m in entries if m not in (config.baseline, ORACLE)]
    holm_of = {m: e.p_holm for m, e in entries.items() if isinstance(e, MethodSummary)}  # not an outlier cut's
    if len(tested) > 1 and all(m in holm_of for m in tested):
        at = header.index("p one-tailed") + 1
        header = (*header[:at], "p Holm", *header[at:])
        holm = ["" if m not in tested else p_value(holm_of[m]) for m in entries]
        rows = [[*row[:at], cell, *row[at:]] for row, cell in zip(rows, holm, strict=True)]
        notes.append(
            f"p Holm: the one-tailed p adjusted by Holm's method over the {len(tested)} methods tested "
            "(the oracle is a reference, not tested)."
        )
    if oracle and ORACLE in entries:
        header = (*header, "time / oracle")
        ratios = [e.oracle_ratio if isinstance(e, MethodSummary) else None for e in entries.values()]
        rows = [[*row, number(ratio, 2, " ×")] for row, ratio in zip(rows, ratios, strict=True)]
        notes.append(
            "time / oracle: mean exploration time over the full-knowledge coverage tour's (1.00 × would be "
            "as fast as a robot that knows the map; the tour is planned for viewpoints, not the fastest "
            "possible, so a method may come in below 1.00 ×)."
        )
    return Table(header, rows, title, " ".join(notes))
