"""A small table type rendered both as Markdown and as HTML, so the two reports show the same cells."""

from __future__ import annotations

import html
import math
from dataclasses import dataclass, field


@dataclass(frozen=True)
class Table:
    """A titled table of text cells; the first column is left-aligned, the others right-aligned.

    Attributes:
        header: column names.
        rows: the cells, one list per row, as many as ``header``.
        title: shown above the table (may be empty).
        note: shown below it (may be empty).
    """

    header: tuple[str, ...]
    rows: list[list[str]] = field(default_factory=list)
    title: str = ""
    note: str = ""

    def markdown(self) -> str:
        """GitHub-flavoured Markdown."""
        lines = [f"**{self.title}**", ""] if self.title else []
        lines.append("| " + " | ".join(self.header) + " |")
        lines.append("|---|" + "---:|" * (len(self.header) - 1))
        lines += ["| " + " | ".join(row) + " |" for row in self.rows]
        if self.note:
            lines += ["", self.note]
        return "\n".join(lines) + "\n"

    def html(self) -> str:
        """An HTML ``<table>`` with the title as caption."""
        caption = f"<caption>{html.escape(self.title)}</caption>" if self.title else ""
        head = "".join(f"<th>{html.escape(h)}</th>" for h in self.header)
        body = "".join("<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in row) + "</tr>" for row in self.rows)
        note = f'<p class="note">{html.escape(self.note)}</p>' if self.note else ""
        return f"<table>{caption}<thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>{note}"


def number(value: float | None, digits: int = 1, unit: str = "") -> str:
    """``value`` with thousands separators and ``digits`` decimals, or "n/a"."""
    if value is None or not math.isfinite(value):
        return "n/a"
    return f"{value:,.{digits}f}{unit}"


def p_value(value: float | None) -> str:
    """A p-value with two significant digits, or "n/a"."""
    return "n/a" if value is None or not math.isfinite(value) else f"{value:.2g}"
