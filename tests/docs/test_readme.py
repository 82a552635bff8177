"""The README stays short, and neither it nor the site's user pages carry history: no dates and no
issue numbers (those belong in the changelog and the research log)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from tests.docs.markdown_pages import DOCS, README, ROOT, pages

MAX_README_LINES = 200
DATE = re.compile(r"\b(19|20)\d\d-(0[1-9]|1[0-2])-(0[1-9]|[12]\d|3[01])\b")
ISSUE = re.compile(r"\bissues?\s*#?\s*\d+\b|(?<![\w&/#])#\d+\b", re.IGNORECASE)
HISTORY_PAGES = frozenset({DOCS / "changelog.md", DOCS / "research-log.md"})
"""The pages whose subject is history, where dates and issue numbers belong."""


def user_pages() -> list[Path]:
    return [page for page in pages() if page not in HISTORY_PAGES]


def history_in(page: Path) -> list[str]:
    """The lines of ``page`` that carry a date or an issue number, as ``LINE: TEXT``."""
    found = []
    for number, line in enumerate(page.read_text(encoding="utf-8").splitlines(), start=1):
        for pattern in (DATE, ISSUE):
            match = pattern.search(line)
            if match:
                found.append(f"{number}: {match.group(0)!r} in {line.strip()[:100]}")
    return found


def test_the_readme_is_at_most_200_lines() -> None:
    lines = len(README.read_text(encoding="utf-8").splitlines())
    assert lines <= MAX_README_LINES, f"README.md has {lines} lines"


@pytest.mark.parametrize("page", user_pages(), ids=lambda p: str(p.relative_to(ROOT)))
def test_no_date_or_issue_number_on_a_user_page(page: Path) -> None:
    found = history_in(page)
    assert not found, f"{page.relative_to(ROOT)} carries history:\n" + "\n".join(found)


@pytest.mark.parametrize(
    ("text", "history"),
    [
        ("measured on 2026-11-27", True),
        ("see issue #15", True),
        ("issue 57 asks for it", True),
        ("(#3)", True),
        ("fixed in #120.", True),
        ("a [link](#section-3) and a colour #fff", False),
        ("w = 0.75, 120 episodes, seeds 0 to 119", False),
        ("&#8212; an HTML entity", False),
    ],
)
def test_the_patterns_find_dates_and_issue_numbers_only(tmp_path: Path, text: str, history: bool) -> None:
    page = tmp_path / "page.md"
    page.write_text(f"# Page\n\n{text}\n")
    assert bool(history_in(page)) is history
