"""Numbers, tables and figures of the results pages, in one style."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

from matplotlib.figure import Figure
from results_data import Study

from frontier_rl.evaluation.report.table import Table, number

_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")
DPI = 100


def p_text(value: float | None) -> str:
    """A p-value: two significant digits, as mantissa·10ⁿ below 0.001; "n/a" when undefined."""
    if value is None or not math.isfinite(value):
        return "n/a"
    if value >= 0.001:
        return f"{value:.2g}"
    mantissa, exponent = f"{value:.1e}".split("e")
    return f"{mantissa}·10{str(int(exponent)).translate(_SUPERSCRIPT)}"


def seconds(value: float | None) -> str:
    """A time (s) with one decimal and thousands separators."""
    return number(value, 1)


def percent(value: float | None, digits: int = 1) -> str:
    """A percentage already in percent (12.3 → "12.3 %")."""
    return number(value, digits, " %")


def ratio(value: float | None) -> str:
    """A ratio such as time over the oracle's ("1.04 ×")."""
    return number(value, 2, " ×")


def duration(value_s: float | None) -> str:
    """A wall time as minutes and seconds."""
    if value_s is None:
        return "not recorded"
    minutes, secs = divmod(round(value_s), 60)
    return f"{minutes} min {secs} s" if minutes else f"{secs} s"


def markdown_table(header: Sequence[str], rows: Sequence[Sequence[str]], note: str = "") -> str:
    """A Markdown table (first column left, the others right-aligned)."""
    return Table(tuple(header), [list(r) for r in rows], note=note).markdown()


def save(fig: Figure, path: Path) -> str:
    """Save ``fig`` as PNG at ``path``; its path relative to the page (a page's images are in a
    folder beside it)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=DPI)
    return relative(path)


def relative(path: Path) -> str:
    """An image's path as the page beside its folder links it."""
    return f"{path.parent.name}/{path.name}"


def reproduce_section(study: Study) -> str:
    """The page's last section: the commands behind it, how long they took, on what."""
    made = study.provenance
    lines = ["## Reproduce", "", "```bash", *(c.command for c in made.commands), "```", ""]
    code = f"commit `{made.commit}`" + (" with changes not yet committed" if made.changes_not_committed else "")
    lines.append(
        f"Measured on {code}, on {made.cores} cores ({made.cpu}): {duration(made.wall_time_s)} of wall time. "
        f"`python experiments/studies.py run {study.name}` runs these commands and keeps the files this page is "
        "generated from in `docs/results/data/`; `make docs` then rebuilds the page."
    )
    return "\n".join(lines) + "\n"
