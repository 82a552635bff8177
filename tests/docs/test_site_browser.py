"""The documentation site as a reader opens it: built, then shown in headless Chromium (Debian's,
installed by ``make browser-deps``) at 1400 px and at a phone's 400 px. The home page, a guide, an
environment page and a results page must not scroll sideways, every image must load, and nothing
may come from the network: the site works offline.

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

from tests.docs.markdown_pages import DOCS
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


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The site built as ``make docs`` builds it (warnings are the build's own test: not fatal here)."""
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
