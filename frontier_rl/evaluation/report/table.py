"""A small table type rendered both as Markdown and as HTML, so the two reports show the same cells."""

from __future__ import annotations

import html
import math
from collections import Counter
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

from frontier_rl.errors import ConfigError, UnknownNameError
from frontier_rl.evaluation.results.summary import MethodSummary, PairedSummary
from frontier_rl.evaluation.statistics.paired import PairedStats
from frontier_rl.policies.spec import BuiltinPolicy, PolicyKind
from frontier_rl.swarm.config import TeamMethod


@dataclass(frozen=True)
class Table:
    """A titled table of text cells; the first column is left-aligned, the others right-aligned.

    Attributes:
        header: column names.
        rows: the cells, one list per row, as many as ``header``.
        title: shown above the table (may be empty).
        note: shown below it (may be empty).
        wrap: cells of prose that wrap and align left (in HTML), not figures kept on one line.
    """

    header: tuple[str, ...]
    rows: list[list[str]] = field(default_factory=list)
    title: str = ""
    note: str = ""
    wrap: bool = False

    def markdown(self) -> str:
        """GitHub-flavoured Markdown."""
        lines = [f"**{self.title}**", ""] if self.title else []
        lines.append("| " + " | ".join(self.header) + " |")
        lines.append("|---|" + ("---|" if self.wrap else "---:|") * (len(self.header) - 1))
        lines += ["| " + " | ".join(cell.replace("|", "\\|") for cell in row) + " |" for row in self.rows]
        if self.note:
            lines += ["", self.note]
        return "\n".join(lines) + "\n"

    def html(self) -> str:
        """An HTML ``<table>`` with the title as caption, in a box that scrolls sideways on its own
        when the table is wider than the page, and the note below it."""
        caption = f"<caption>{html.escape(self.title)}</caption>" if self.title else ""
        head = "".join(f"<th>{html.escape(h)}</th>" for h in self.header)
        body = "".join("<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in row) + "</tr>" for row in self.rows)
        note = f'<p class="note">{html.escape(self.note)}</p>' if self.note else ""
        kind = ' class="prose"' if self.wrap else ""
        table = f"<table{kind}>{caption}<thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"
        return f'<div class="scroll">{table}</div>{note}'


def short_labels(names: Iterable[str]) -> dict[str, str]:
    """Display names: ``learned:models/model4.zip`` → ``learned:model4``, a policy file's class by
    the file's name (``runs/mine.py:Greedy`` → ``mine.py:Greedy``), a map file → its stem;
    names whose short forms would coincide keep their full form."""
    names = list(names)
    short = {n: _short(n) for n in names}
    counts = Counter(short.values())
    return {n: short[n] if counts[short[n]] == 1 else n for n in names}


def _short(name: str) -> str:
    try:
        method = TeamMethod.parse(name)
    except (ConfigError, UnknownNameError):  # not a method (a world's file name)
        return _short_text(name)
    policy = method.policy
    if policy.builtin is BuiltinPolicy.LEARNED:
        short = f"learned:{Path(policy.argument).stem}"
    elif policy.kind is PolicyKind.FILE:  # a long folder pushed the figures' axes off their canvas
        short = f"{Path(policy.name).name}:{policy.argument}"
    else:
        short = _short_text(str(policy))
    return short if method.robots is None else method.label(short)


def _short_text(name: str) -> str:
    """A file's stem for a name that is a path (a map file), else the name."""
    return Path(name).stem if ":" not in name and ("/" in name or "." in name) else name


def number(value: float | None, digits: int = 1, unit: str = "") -> str:
    """``value`` with thousands separators and ``digits`` decimals, or "n/a"."""
    if value is None or not math.isfinite(value):
        return "n/a"
    return f"{value:,.{digits}f}{unit}"


def percent(share: float | None, digits: int = 2) -> str:
    """A share (0-1) as a percentage with ``digits`` decimals, or "n/a"."""
    return number(None if share is None else 100 * share, digits, " %")


SIGNIFICANCE = 0.05
"""The level the reports call a result significant at (a p below it)."""


def p_value(value: float | None) -> str:
    """A p-value with two significant digits (more where two would round it onto
    :data:`SIGNIFICANCE`: 0.0496 is "0.0496", not "0.05" beside "significant"), or "n/a"."""
    if value is None or not math.isfinite(value):
        return "n/a"
    text = f"{value:.2g}"
    for digits in (3, 4, 5, 6):
        if float(text) != SIGNIFICANCE or value == SIGNIFICANCE:
            break
        text = f"{value:.{digits}g}"
    return text


TABLE_4_1_HEADER = (
    "method",
    "n",
    "mean time (s)",
    "variance (s²)",
    "sd (s)",
    "mean saving (s)",
    "95 % CI (s)",
    "p one-tailed",
    "p two-tailed",
    "p Wilcoxon",
    "reduction",
)


def table_4_1_row(name: str, s: PairedSummary, is_baseline: bool) -> list[str]:
    """One row of :func:`table_4_1`; the baseline's has no comparison cells."""
    if is_baseline:
        return [f"{name} (baseline)", str(s.n), number(s.mean_time_s), number(s.var_time_s), _sd(s), *[""] * 6]
    ci = f"{number(s.ci95_s[0])} … {number(s.ci95_s[1])}"
    return [
        name,
        str(s.n),
        number(s.mean_time_s),
        number(s.var_time_s),
        _sd(s),
        number(s.mean_diff_s),
        ci,
        p_value(s.p_one_tailed),
        p_value(s.p_two_tailed),
        p_value(s.p_wilcoxon),
        number(s.reduction_pct, unit=" %"),
    ]


def _sd(s: PairedSummary) -> str:
    variance = s.var_time_s
    return number(math.sqrt(variance)) if variance is not None and math.isfinite(variance) and variance >= 0 else "n/a"


def table_4_1(results: dict[str, PairedStats], baseline: str, title: str = "") -> Table:
    """A table laid out like the thesis's Table 4.1: per method the mean and variance of the
    exploration time, the mean saving against the baseline with its 95 % CI, the p-values and
    the reduction of the mean time (``.markdown()`` and ``.html()`` render it)."""
    rows = [
        table_4_1_row(name, PairedSummary(**PairedSummary.values_of(s)), name == baseline)
        for name, s in results.items()
    ]
    return Table(TABLE_4_1_HEADER, rows, title)


def completion_table(entries: Mapping[str, MethodSummary], labels: dict[str, str] | None = None) -> Table:
    """How the episodes of each method ended, from the methods' summaries: how many were
    explored, ended with unreachable frontiers left or at the sim-time cap (and for any other reason
    a method gave, such as a team's "failed"), the mean and lowest coverage, the mean share of all
    free cells mapped and the mean unknown area left beside the frontiers left."""
    labels = labels or {}
    reasons = list(dict.fromkeys(reason for e in entries.values() for reason in e.end_reasons or {}))
    table = Table(
        (
            "method",
            "episodes",
            *(reason.label for reason in reasons),
            "mean coverage",
            "min coverage",
            "free coverage",
            "unknown left (m²)",
        ),
        title="Completion",
        note="explored: no frontier left that the robot could see from where it can go; unreachable: frontiers "
        "left with free space unseen beside or behind them, none of them reachable or each given up after its "
        "tries; time cap: cut at the sim-time cap. coverage: share of the explorable space mapped; free "
        "coverage: share of all free cells mapped; unknown left: the unknown area beside the frontiers left (mean "
        "over episodes).",
    )
    for method, e in entries.items():
        table.rows.append(
            [
                labels.get(method, method),
                str(e.n),
                *(str((e.end_reasons or {}).get(r, 0)) for r in reasons),
                percent(e.mean_coverage),
                percent(e.min_coverage),
                percent(e.mean_free_coverage),
                number(e.mean_unknown_left_m2, 2),
            ]
        )
    return table
