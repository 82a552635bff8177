"""The documentation site as a reader opens it: built, then shown in headless Chromium (Debian's,
installed by ``make browser-deps``) at 1400 px and at a phone's 400 px. The home page, a guide, an
environment page and a results page must not scroll sideways, every image must load, and nothing
may come from the network: the site works offline.

The site is the one ``make docs`` built in docs/_build/html where that is current (``make test``
builds it just before), else it is built into a temporary folder (:func:`current_build`).

Screenshots of every page and width are saved in the folder named by ``DOCS_SCREENSHOTS`` (a
temporary folder otherwise, printed with ``-s``), to look at.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from tests.docs.markdown_pages import DOCS, ROOT
from tests.evaluation.test_report_browser import WIDTHS, _open
from tests.evaluation.test_report_browser import browser as browser  # the shared Chromium fixture

pytestmark = pytest.mark.slow

BUILD_TIMEOUT_S = 300
SCREENSHOT_MAX_HEIGHT = 4000
"""Screenshots show at most this much of a page (CSS px)."""
_REMOTE = re.compile(
    r"<(?:script|img|iframe|source|video|audio)\b[^>]*\bsrc=[\"']\s*(?:https?:)?//"
    r"|<link\b[^>]*\bhref=[\"']\s*(?:https?:)?//"
    r"|url\(\s*[\"']?\s*(?:https?:)?//"
    r"|@import\s+[\"']\s*(?:https?:)?//",
    re.IGNORECASE,
)
"""What a page or stylesheet would fetch from the network: a script, image, frame, media, a linked
stylesheet, font or icon, a CSS url() or @import with a remote address. Plain links (``<a href>``) are
not fetched."""


BUILT = DOCS / "_build" / "html"
"""Where ``make docs`` builds the site."""
SOURCES = (
    DOCS,
    ROOT / "frontier_rl",
    ROOT / "models",
    ROOT / "CHANGELOG.md",
    ROOT / "README.md",
    ROOT / "pyproject.toml",
)
"""What the site is made from: its pages, extensions, static files and data, the code its reference
pages are generated from, the models its pictures run, the changelog it includes. More than it
reads, on purpose: a change anywhere there builds the site again."""
_NOT_SOURCES = ("_build", "__pycache__")
"""Folders under :data:`SOURCES` that are made from them: the build itself, Python's bytecode and
numba's caches."""


def current_build(built: Path, sources: tuple[Path, ...] = SOURCES) -> bool:
    """Whether the site in ``built`` was built (its ``.buildinfo`` written, which Sphinx does last)
    after the last change to any file of ``sources``. A file's modification time decides, so the
    answer is the same however the tests were started."""
    stamp = built / ".buildinfo"
    if not stamp.is_file():
        return False
    built_at = stamp.stat().st_mtime_ns
    return all(changed < built_at for changed in _modification_times(sources))


def _modification_times(sources: tuple[Path, ...]) -> Iterator[int]:
    for source in sources:
        if source.is_file():
            yield source.stat().st_mtime_ns
        for folder, subfolders, files in os.walk(source):
            subfolders[:] = [name for name in subfolders if name not in _NOT_SOURCES]
            yield from (os.stat(os.path.join(folder, name)).st_mtime_ns for name in files)


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The site ``make docs`` built, where it is current; else built as ``make docs`` builds it, into a
    temporary folder (warnings are the build's own test: not fatal here)."""
    if current_build(BUILT):
        return BUILT
    out = tmp_path_factory.mktemp("site")
    build = subprocess.run(
        [sys.executable, "-m", "sphinx", "-b", "html", "-q", str(DOCS), str(out)],
        capture_output=True,
        text=True,
        timeout=BUILD_TIMEOUT_S,
    )
    assert build.returncode == 0, build.stderr[-3000:]
    return out


@pytest.fixture(scope="module")
def screenshots(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    folder = Path(os.environ.get("DOCS_SCREENSHOTS") or tmp_path_factory.mktemp("docs-screenshots"))
    folder.mkdir(parents=True, exist_ok=True)
    yield folder
    print(f"screenshots of the site: {folder}")


def page_of(site: Path, kind: str) -> Path:
    """The home page, the first guide, a Gymnasium environment's page or the first results page."""
    if kind == "home":
        return site / "index.html"
    if kind == "environment":
        return site / "reference" / "envs" / "weightmap-v0.html"
    folder = {"guide": "guides", "results": "results"}[kind]
    found = sorted(p for p in (site / folder).rglob("*.html") if p.name != "index.html")
    assert found, f"the site has no page in {folder}/"
    return found[0]


@pytest.mark.parametrize("width", WIDTHS)
@pytest.mark.parametrize("kind", ["home", "guide", "environment", "results"])
def test_the_page_fits_the_screen_and_its_images_load_offline(
    site: Path, browser: Any, screenshots: Path, kind: str, width: int
) -> None:
    page = page_of(site, kind)
    _open(browser, page, width)
    page_width = browser.execute_script("return document.documentElement.scrollWidth")
    assert page_width <= width, f"{page.name} scrolls sideways: {page_width} px in a {width} px window"
    images = browser.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "Promise.all([...document.images].map(img => img.decode().then("
        "  () => [img.currentSrc, img.naturalWidth], () => [img.currentSrc, 0]))).then(done);"
    )
    broken = [source for source, natural_width in images if natural_width <= 0]
    assert not broken, f"images that did not load on {page.name}: {broken}"
    if kind in ("home", "environment"):
        assert images, f"{page.name} shows no picture"
    fetched = browser.execute_script("return performance.getEntriesByType('resource').map(e => e.name)")
    remote = [url for url in fetched if not url.startswith(("file:", "data:", "blob:"))]
    assert not remote, f"{page.name} fetched from the network: {remote}"
    _screenshot(browser, screenshots / f"{kind}-{width}.png", width)


def _screenshot(driver: Any, path: Path, width: int) -> None:
    """The page from its top, as tall as its content (at most :data:`SCREENSHOT_MAX_HEIGHT`)."""
    height = min(driver.execute_script("return document.documentElement.scrollHeight"), SCREENSHOT_MAX_HEIGHT)
    metrics = {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": width < 700}
    driver.execute_cdp_cmd("Emulation.setDeviceMetricsOverride", metrics)
    driver.save_screenshot(str(path))


def test_no_page_or_stylesheet_of_the_site_fetches_from_the_network(site: Path) -> None:
    files = [*site.rglob("*.html"), *site.rglob("*.css"), *site.rglob("*.js")]
    found = {str(p.relative_to(site)): _REMOTE.search(p.read_text(errors="replace")) for p in files}
    remote = {name: match.group(0) for name, match in found.items() if match}
    assert not remote, f"the site loads from the network: {remote}"


def test_the_site_make_docs_built_is_reused_only_while_no_source_changed_since(tmp_path: Path) -> None:
    built, docs, code = tmp_path / "docs/_build/html", tmp_path / "docs", tmp_path / "frontier_rl"
    for path in (docs / "index.md", docs / "_ext/pages.py", code / "core/world.py", code / "data/maps/map.png"):
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text("source")
    sources = (docs, code, tmp_path / "CHANGELOG.md")  # a file not there is no source
    assert not current_build(built, sources)  # never built
    built.mkdir(parents=True)
    (built / ".buildinfo").write_text("built")
    hour_ago = (built / ".buildinfo").stat().st_mtime - 3600
    for path in tmp_path.rglob("*"):
        if path.name != ".buildinfo":
            os.utime(path, (hour_ago, hour_ago))
    assert current_build(built, sources)
    for made in (built / "index.html", docs / "_ext/__pycache__/pages.pyc", code / "core/__pycache__/world.nbi"):
        made.parent.mkdir(parents=True, exist_ok=True)
        made.write_text("made from the sources")
    assert current_build(built, sources)  # the build's output, bytecode and numba's cache are not sources
    for changed in (docs / "index.md", docs / "_ext/pages.py", code / "core/world.py", code / "data/maps/map.png"):
        os.utime(changed)
        assert not current_build(built, sources), changed
        os.utime(changed, (hour_ago, hour_ago))
    (docs / "guides").mkdir()
    (docs / "guides/new.md").write_text("a new page")
    assert not current_build(built, sources)
