"""The Markdown pages a reader sees (README.md and the committed pages of docs/), parsed once with
markdown-it (the parser MyST builds on): their code blocks, links and heading anchors."""

from __future__ import annotations

import functools
import re
import subprocess
from dataclasses import dataclass
from pathlib import Path

from markdown_it import MarkdownIt
from markdown_it.token import Token

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
README = ROOT / "README.md"

SKIP_MARKER = re.compile(r"<!--\s*not run:\s*(?P<reason>\S.*?)\s*-->")
"""Put ``<!-- not run: REASON -->`` on the line just above a ```python block to keep the tests from
running it (for code that needs a robot or a ROS master); the reason is required."""
SAME_AS = re.compile(r"same as (?P<page>\S+\.md)")
"""The reason ``same as PAGE`` (PAGE from the repository's root): a block that runs on PAGE does what
this one does, which the tests check instead of running it again."""

_LABEL = re.compile(r"^\((?P<name>[\w.:-]+)\)=\s*$", re.MULTILINE)
_HTML_IMAGE = re.compile(r"<img\b[^>]*\bsrc=[\"'](?P<src>[^\"']+)[\"']", re.IGNORECASE)
_PATH_DIRECTIVES = ("{figure}", "{image}", "{include}", "{literalinclude}")


@dataclass(frozen=True)
class CodeBlock:
    """A fenced code block: its language (the first word of the info string), its text, and
    whether a ``not run`` marker stands above it."""

    page: Path
    line: int
    language: str
    code: str
    skip_reason: str | None

    @property
    def name(self) -> str:
        """``PAGE:LINE``, relative to the repository (a page outside it by its absolute path)."""
        return f"{self.page.relative_to(ROOT) if self.page.is_relative_to(ROOT) else self.page}:{self.line}"

    @property
    def same_as(self) -> Path | None:
        """The page named by a ``not run: same as PAGE`` marker; None for any other block."""
        match = SAME_AS.fullmatch(self.skip_reason or "")
        return ROOT / match["page"] if match else None


@dataclass(frozen=True)
class Link:
    """A link or image target on a page (the line it is on, from 1)."""

    page: Path
    line: int
    target: str


def pages() -> list[Path]:
    """README.md and every Markdown page of docs/ that git tracks (generated pages are checked by
    the build itself)."""
    listed = subprocess.run(
        ["git", "ls-files", "--cached", "--others", "--exclude-standard", "docs"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=True,
    ).stdout.split()
    return [README, *sorted(ROOT / p for p in listed if p.endswith(".md") and (ROOT / p).is_file())]


@functools.cache
def tokens(page: Path) -> list[Token]:
    """The block tokens of ``page`` (tables and MyST's directive fences included)."""
    return MarkdownIt("commonmark").enable("table").parse(page.read_text(encoding="utf-8"))


def code_blocks(page: Path) -> list[CodeBlock]:
    """Every fenced code block of ``page``."""
    lines = page.read_text(encoding="utf-8").splitlines()
    blocks = []
    for token in tokens(page):
        if token.type != "fence" or token.map is None:
            continue
        start = token.map[0]
        above = lines[start - 1] if start > 0 else ""
        marker = SKIP_MARKER.search(above)
        language = token.info.split()[0] if token.info.split() else ""
        blocks.append(CodeBlock(page, start + 1, language, token.content, marker["reason"] if marker else None))
    return blocks


def links(page: Path) -> list[Link]:
    """Every link and image target of ``page``: Markdown links and images, HTML ``<img>`` and the
    paths of MyST's figure, image and include directives."""
    found = []
    for token in tokens(page):
        line = token.map[0] + 1 if token.map else 0
        if token.type == "fence" and token.info.startswith(_PATH_DIRECTIVES):
            found.append(Link(page, line, token.info.split(maxsplit=1)[1].strip()))
        for child in token.children or []:
            if child.type == "link_open":
                found.append(Link(page, line, str(child.attrs["href"])))
            elif child.type == "image":
                found.append(Link(page, line, str(child.attrs["src"])))
            elif child.type == "html_inline":
                found += [Link(page, line, m["src"]) for m in _HTML_IMAGE.finditer(child.content)]
        if token.type == "html_block":
            found += [Link(page, line, m["src"]) for m in _HTML_IMAGE.finditer(token.content)]
    return found


def anchors(page: Path) -> set[str]:
    """The ``#anchor`` names of ``page``: its headings' slugs (GitHub's, made as MyST makes them: a
    repeated one numbered ``-1``, ``-2``, ...) and its explicit targets (``(name)=``). Needs the docs extra."""
    from myst_parser.slugs import github_slugify, unique_slug

    labels = set(_LABEL.findall(page.read_text(encoding="utf-8")))
    slugs: list[str] = []
    items = tokens(page)
    for index, token in enumerate(items):
        if token.type == "heading_open":
            text = "".join(c.content for c in items[index + 1].children or [] if c.type in ("text", "code_inline"))
            slug = github_slugify(text)
            if slug:  # a heading without one gets no anchor
                slugs.append(unique_slug(slug, slugs))
    return labels | set(slugs)
