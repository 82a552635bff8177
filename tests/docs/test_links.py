"""Every relative link and image of README.md and of the site's pages resolves: the file exists, and
a ``#anchor`` is a heading (or explicit target) of the page it points to. Links into the folders
the build generates are checked against what the generators write."""

from __future__ import annotations

import atexit
import functools
import re
import shutil
import tempfile
from pathlib import Path
from urllib.parse import unquote

import pytest

from tests.docs.markdown_pages import DOCS, ROOT, Link, anchors, links, pages

EXTERNAL = re.compile(r"^[a-z][a-z0-9+.-]*:", re.IGNORECASE)
"""A target with a scheme (https:, mailto:, ...): not a file of the project."""


@functools.cache
def generated_root() -> Path:
    """A folder holding what every page generator writes, each in its folder as under docs/ (made
    once, and only when a link points into a generated folder; removed when the tests end)."""
    import generated_pages

    root = Path(tempfile.mkdtemp(prefix="generated-docs-"))
    atexit.register(shutil.rmtree, root, ignore_errors=True)
    for generator in generated_pages.GENERATORS:
        target = root / generator.folder
        target.mkdir(parents=True)
        generator.generate(target)
    return root


def _generated_folder(path: Path) -> str | None:
    """The generated folder (relative to docs/) that ``path`` lies in, if any."""
    import generated_pages

    for generator in generated_pages.GENERATORS:
        if path.is_relative_to(DOCS / generator.folder):
            return generator.folder
    return None


def problem(link: Link) -> str | None:
    """What is wrong with ``link``, or None."""
    target = link.target.strip()
    if not target or EXTERNAL.match(target) or target.startswith("{"):
        return None
    path_part, _, anchor = target.partition("#")
    path = (link.page.parent / unquote(path_part)).resolve() if path_part else link.page
    if _generated_folder(path) is not None:
        path = generated_root() / path.relative_to(DOCS)
    if path.is_dir() and link.page == ROOT / "README.md" and not anchor:
        return None  # GitHub shows a folder's listing; the site's pages link files only
    if not path.is_file():
        return f"{target}: no such file"
    if anchor and path.suffix == ".md" and anchor not in anchors(path):
        return f"{target}: no heading or target #{anchor} in {path.name}"
    return None


@pytest.mark.parametrize("page", pages(), ids=lambda p: str(p.relative_to(ROOT)))
def test_every_relative_link_and_image_resolves(page: Path) -> None:
    broken = [f"line {link.line}: {message}" for link in links(page) if (message := problem(link))]
    assert not broken, f"{page.relative_to(ROOT)}:\n" + "\n".join(broken)


def test_a_broken_link_or_anchor_is_found(tmp_path: Path) -> None:
    (tmp_path / "other.md").write_text("# Other page\n\n## A `code` heading\n\n(a-label)=\n## Twice\n\n## Twice\n")
    page = tmp_path / "page.md"
    page.write_text(
        "# Page\n\n[ok](other.md#a-code-heading) [ok](other.md#a-label) [ok](other.md#twice-1) [ok](#page)\n"
        "[ok](https://example.org/x) ![ok](other.md)\n\n"
        "[bad](missing.md) [bad](other.md#nowhere) ![bad](pic.png) [bad](#no-such-heading)\n\n"
        '<img src="gone.gif">\n\n```{figure} nothere.png\n```\n'
    )
    found = [problem(link) for link in links(page)]
    assert [f for f in found if f] == [
        "missing.md: no such file",
        "other.md#nowhere: no heading or target #nowhere in other.md",
        "pic.png: no such file",
        "#no-such-heading: no heading or target #no-such-heading in page.md",
        "gone.gif: no such file",
        "nothere.png: no such file",
    ]
