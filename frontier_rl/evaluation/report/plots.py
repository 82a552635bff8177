"""The experiment's figures (dict keys are the methods' display names): box plot and paired
scatter of exploration times (the thesis's figures 4.2 to 4.8), coverage over time, and the weight
learned-weight methods chose over time.

Figures are drawn on :class:`matplotlib.figure.Figure` objects (no pyplot state) and saved as PNG,
each through a temporary file renamed into place (a failed write leaves the previous figure).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from frontier_rl.atomic_write import save_figure_atomic
from frontier_rl.core.frontiers.thesis import THESIS_WEIGHT
from frontier_rl.core.sim.metrics import sample_step
from frontier_rl.evaluation.results.episode_record import EpisodeTrace
from frontier_rl.evaluation.results.summary import TeamPoint
from frontier_rl.evaluation.statistics.analysis import finite_times

_DPI = 110


def box_plot(times: Mapping[str, Sequence[float]], path: Path, title: str) -> Path:
    """Box-and-whisker plot of exploration time (s) per method, one row per method (the first on
    top, so that any number of methods stays legible); the triangle marks the mean. A time that is
    NaN (a team whose robots all failed) is left out."""
    names = list(times)[::-1]
    fig = Figure(figsize=(6.4, 1.3 + 0.42 * len(names)), dpi=_DPI)
    ax = fig.subplots()
    ax.boxplot([finite_times(times[n]) for n in names], orientation="horizontal", showmeans=True, widths=0.55)
    ax.set_yticks(range(1, len(names) + 1), names)
    ax.set_xlabel("exploration time (s)")
    ax.set_title(title)
    ax.grid(axis="x", alpha=0.3)
    fig.tight_layout()
    return save_figure_atomic(fig, path)


def paired_scatter(times: Mapping[str, Sequence[float]], baseline: str, path: Path) -> Path:
    """Each episode's time with a method (y) against the baseline's time in it (x); points under
    the diagonal are episodes the method explored faster. Both axes span the times measured (with
    a margin), the same on both so that the diagonal is the line of equal time. An episode whose
    time is NaN on either side (a team whose robots all failed) has no point."""
    fig = Figure(figsize=(5.6, 5.2), dpi=_DPI)
    ax = fig.subplots()
    base = np.asarray(times[baseline])
    values = np.concatenate([finite_times(v) for v in times.values()])
    low, high = (float(np.min(values)), float(np.max(values))) if len(values) else (0.0, 1.0)
    margin = max(0.05 * (high - low), 1.0)
    low, high = max(0.0, low - margin), high + margin
    ax.plot([low, high], [low, high], color="0.6", lw=1, ls="--", label="equal time")
    for method, method_times in times.items():
        if method != baseline:
            ax.scatter(base, method_times, s=14, alpha=0.7, label=method)
    ax.set_xlim(low, high)
    ax.set_ylim(low, high)
    ax.set_aspect("equal")
    ax.set_xlabel(f"{baseline}: exploration time (s)")
    ax.set_ylabel("method: exploration time (s)")
    ax.set_title("Paired episodes (below the diagonal: faster)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    return save_figure_atomic(fig, path)


def coverage_plot(traces: Mapping[str, Sequence[EpisodeTrace]], path: Path) -> Path:
    """Mean coverage over time per method with the band between the 25th and 75th percentiles;
    an episode that has ended keeps its final coverage."""
    fig = Figure(figsize=(6.4, 4.2), dpi=_DPI)
    ax = fig.subplots()
    end = max((t.coverage_t[-1] for ts in traces.values() for t in ts if t.coverage_t), default=1.0)
    grid = np.linspace(0.0, end, 300)
    for method, method_traces in traces.items():
        curves = np.array([sample_step(np.asarray(t.coverage_t), np.asarray(t.coverage), grid) for t in method_traces])
        if curves.size == 0:
            continue
        low, high = np.percentile(curves, [25, 75], axis=0)
        (line,) = ax.plot(grid, 100 * curves.mean(axis=0), lw=1.6, label=method)
        ax.fill_between(grid, 100 * low, 100 * high, color=line.get_color(), alpha=0.15, lw=0)
    ax.set_xlabel("sim time (s)")
    ax.set_ylabel("explored (% of the reachable free space)")
    ax.set_ylim(0, 101)
    ax.set_xlim(0, end if end > 0 else 1.0)  # every episode ended at t = 0: an empty axis, not a warning
    ax.set_title("Coverage over time (mean, band: 25th to 75th percentile)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    return save_figure_atomic(fig, path)


def weight_plot(traces: Mapping[str, Sequence[EpisodeTrace]], path: Path) -> Path:
    """The weight each learned-weight method chose at each decision (dots) and its mean per time
    bin (line)."""
    fig = Figure(figsize=(6.4, 4.0), dpi=_DPI)
    ax = fig.subplots()
    for method, method_traces in traces.items():
        t = np.concatenate([np.asarray(tr.weight_t, float) for tr in method_traces])
        w = np.concatenate([np.asarray(tr.weight, float) for tr in method_traces])
        if t.size == 0:
            continue
        (line,) = ax.plot([], [])  # takes the next colour of the cycle for both
        colour = line.get_color()
        ax.scatter(t, w, s=4, alpha=0.15, color=colour)
        edges = np.linspace(0.0, float(t.max()) + 1e-9, 21)
        which = np.digitize(t, edges) - 1
        centres, means = [], []
        for b in range(len(edges) - 1):
            if np.any(which == b):
                centres.append(0.5 * (edges[b] + edges[b + 1]))
                means.append(float(w[which == b].mean()))
        ax.plot(centres, means, lw=1.8, color=colour, label=method)
    ax.axhline(THESIS_WEIGHT, color="0.6", lw=1, ls="--", label=f"w = {THESIS_WEIGHT} (thesis baseline)")
    ax.set_ylim(-0.02, 1.02)
    ax.set_xlabel("sim time (s)")
    ax.set_ylabel("weight w of eq. 3.1")
    ax.set_title("Weight chosen over time")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return save_figure_atomic(fig, path)


def team_size_plot(points: Sequence[TeamPoint], path: Path) -> Path:
    """Mean exploration time against team size, one line per policy and strategy (in the order of
    ``points``), with 95 % confidence intervals."""
    fig = Figure(figsize=(6.4, 4.2), dpi=_DPI)
    ax = fig.subplots()
    lines: dict[tuple[str, str], list[TeamPoint]] = {}
    for point in points:
        lines.setdefault((point.policy, point.strategy), []).append(point)
    for (policy, strategy), line in lines.items():
        robots = [point.robots for point in line]
        means = [point.mean_time_s for point in line]
        errors = [point.ci95_half_s or 0.0 for point in line]
        ax.errorbar(robots, means, yerr=errors, marker="o", capsize=3, lw=1.6, label=f"{policy}, {strategy}")
    sizes = {point.robots for point in points}
    ax.set_xticks(sorted(sizes))
    ax.set_xlabel("robots")
    ax.set_ylabel("exploration time (s)")
    ax.set_ylim(bottom=0)
    ax.set_title("Exploration time against team size (mean, 95 % CI)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return save_figure_atomic(fig, path)
