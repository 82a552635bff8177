"""The report as a list of blocks (headings, paragraphs, tables, figures) rendered twice: as
Markdown beside its figures, and as one self-contained, responsive HTML page (figures embedded as
data URIs; no external reference, no script)."""

from __future__ import annotations

import base64
import html
import os
from dataclasses import dataclass
from pathlib import Path

from frontier_rl.evaluation.report.table import Table


@dataclass(frozen=True)
class Heading:
    """A section heading (``level`` 2 or 3)."""

    text: str
    level: int = 2


@dataclass(frozen=True)
class Paragraph:
    """Plain text; ``lead`` marks the conclusion at the top; ``code`` shows it as a command."""

    text: str
    lead: bool = False
    code: bool = False


@dataclass(frozen=True)
class Figure:
    """An image file with a short title and a caption that says how to read it; a ``chart`` keeps
    a legible width on narrow screens (it scrolls within its frame), a picture of a map shrinks to
    fit."""

    path: Path
    title: str
    caption: str
    chart: bool = True


Block = Heading | Paragraph | Table | Figure

_MIME = {".png": "image/png", ".gif": "image/gif"}

# On narrow screens a chart keeps its drawn size (about 700 px wide) in a frame that scrolls,
# so that its labels stay legible; tables scroll in their own box; the page itself never scrolls sideways.
_CSS = """
*{box-sizing:border-box}
body{font-family:system-ui,-apple-system,"Segoe UI",sans-serif;line-height:1.45;color:#222;max-width:1200px;
 margin:0 auto;padding:1em;overflow-wrap:anywhere}
h1{font-size:1.45em;margin:.4em 0}h2{font-size:1.2em;margin:1.6em 0 .5em;border-bottom:1px solid #ddd}
h3{font-size:1.05em;margin:1.2em 0 .4em}
.lead{background:#f2f6fa;border-left:4px solid #2a6fb0;padding:.6em 1em;margin:1em 0}
.lead p{margin:.35em 0}.lead p:first-child{font-weight:600}
code{font-size:.9em;background:#f4f4f4;padding:.1em .3em}
.scroll{overflow-x:auto;max-width:100%;margin:.8em 0}
table{border-collapse:collapse;font-size:.9em;overflow-wrap:normal}
caption{font-weight:bold;text-align:left;padding:.3em 0}
th,td{border:1px solid #ccc;padding:.25em .6em;text-align:right;white-space:nowrap}
th:first-child,td:first-child{text-align:left;position:sticky;left:0;background:#fff}
table.prose td,table.prose th{white-space:normal;text-align:left;vertical-align:top;min-width:9em}
table.prose td:nth-child(n+2){min-width:16em}
.note{font-size:.85em;color:#555;margin:.2em 0 1em}
figure{margin:1.2em 0}.frame{overflow-x:auto;max-width:100%}
figure img{display:block;max-width:100%;height:auto}
figcaption{font-size:.88em;color:#444;margin-top:.3em}
@media (max-width:700px){body{padding:.6em}h1{font-size:1.25em}
 figure img.chart{max-width:none}table{font-size:.85em}}
"""


def render_markdown(title: str, blocks: list[Block], base: Path) -> str:
    """The report as Markdown; figures are linked relative to ``base`` (the report's folder)."""
    lines = [f"# {title}", ""]
    first_lead = True
    for block in blocks:
        if isinstance(block, Heading):
            lines += ["#" * block.level + f" {block.text}", ""]
        elif isinstance(block, Paragraph):
            text = f"`{block.text}`" if block.code else block.text
            lines += [f"**{text}**" if block.lead and first_lead else text, ""]
            first_lead = first_lead and not block.lead
        elif isinstance(block, Table):
            lines += [block.markdown()]
        else:
            link = Path(os.path.relpath(block.path, base)).as_posix()
            lines += [f"![{block.title}]({link})", "", f"*{block.title}.* {block.caption}", ""]
    return "\n".join(lines)


def render_html(title: str, blocks: list[Block]) -> str:
    """The report as one HTML page with every figure embedded."""
    body = [f"<h1>{html.escape(title)}</h1>"]
    lead: list[str] = []
    for block in blocks:
        if isinstance(block, Paragraph) and block.lead:
            lead.append(f"<p>{html.escape(block.text)}</p>")
            continue
        if lead:  # the conclusion's sentences share one box
            body.append(f'<section class="lead" id="conclusion">{"".join(lead)}</section>')
            lead = []
        body.append(_html_block(block))
    if lead:
        body.append(f'<section class="lead" id="conclusion">{"".join(lead)}</section>')
    return (
        '<!DOCTYPE html><html lang="en"><head><meta charset="utf-8">'
        '<meta name="viewport" content="width=device-width, initial-scale=1">'
        f"<title>{html.escape(title)}</title><style>{_CSS}</style></head><body>{''.join(body)}</body></html>\n"
    )


def _html_block(block: Block) -> str:
    if isinstance(block, Heading):
        return f"<h{block.level}>{html.escape(block.text)}</h{block.level}>"
    if isinstance(block, Paragraph):
        text = html.escape(block.text)
        return f"<p><code>{text}</code></p>" if block.code else f"<p>{text}</p>"
    if isinstance(block, Table):
        return block.html()
    data = base64.b64encode(block.path.read_bytes()).decode()
    mime = _MIME.get(block.path.suffix.lower(), "application/octet-stream")
    kind = ' class="chart"' if block.chart else ""
    title, caption = html.escape(block.title), html.escape(block.caption)
    return (
        f'<figure><div class="frame"><img{kind} alt="{title}" src="data:{mime};base64,{data}"></div>'
        f"<figcaption><b>{title}.</b> {caption}</figcaption></figure>"
    )
