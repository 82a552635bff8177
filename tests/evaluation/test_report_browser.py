"""The HTML report as a reader opens it: headless Chromium (Debian's, installed by ``make``) at
1400 px and at a phone's 400 px. The page must not scroll sideways, every image must decode,
charts must keep a legible size, and the conclusion must name the best method with the numbers
of ``summary.json``."""

from __future__ import annotations

import json
import shutil
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from frontier_rl.core.sim.config import SimConfig
from frontier_rl.evaluation.running.evaluate import evaluate
from frontier_rl.evaluation.running.experiment import ExperimentConfig

pytestmark = pytest.mark.slow

CHROMIUM, CHROMEDRIVER = shutil.which("chromium"), shutil.which("chromedriver")
WIDTHS = (1400, 400)
MIN_CHART_SCALE = 0.8
"""A chart may be shown no smaller than this share of its drawn size (its labels are about 15 px
drawn, so at least 12 px on the screen)."""


@pytest.fixture(scope="module")
def report(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A small experiment with a learned model (so the weight-free methods table, Holm's p and the
    model's training command all appear) on two worlds."""
    out = tmp_path_factory.mktemp("browser") / "exp"
    methods = ("fixed:0.75", "nearest", "learned:models/model5.zip", "largest", "oracle")
    config = ExperimentConfig(
        methods=methods, worlds=("office", "rooms"), episodes=2, sim=SimConfig(max_sim_time=600.0)
    )
    evaluate(config, out, backend="serial", progress=False, command="frontier-rl evaluate (browser test)", pictures=1)
    return out


@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    if CHROMIUM is None or CHROMEDRIVER is None:
        pytest.skip("Chromium and chromedriver are not installed (make installs them where apt-get runs as root)")
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync",
                 "--disable-quic", "--hide-scrollbars"):  # fmt: skip
        options.add_argument(flag)
    driver = webdriver.Chrome(service=Service(executable_path=CHROMEDRIVER), options=options)
    try:
        yield driver
    finally:
        driver.quit()


def _open(driver: Any, page: Path, width: int) -> None:
    """Load ``page`` in a viewport ``width`` CSS px wide; narrow ones as a phone (which lays a page
    without a viewport tag out at 980 px and shrinks it)."""
    driver.execute_cdp_cmd("Emulation.setDeviceMetricsOverride",
                           {"width": width, "height": 900, "deviceScaleFactor": 1, "mobile": width < 700})  # fmt: skip
    driver.get(page.as_uri())


@pytest.mark.parametrize("width", WIDTHS)
def test_the_page_fits_the_screen_and_every_image_decodes(report: Path, browser: Any, width: int) -> None:
    _open(browser, report / "report.html", width)
    assert browser.execute_script("return window.innerWidth") == width
    page_width = browser.execute_script("return document.documentElement.scrollWidth")
    assert page_width <= width, f"the page scrolls sideways: {page_width} px in a {width} px window"
    images = browser.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "Promise.all([...document.images].map(img => img.decode().then("
        "  () => [img.className, img.naturalWidth, img.naturalHeight, img.getBoundingClientRect().width],"
        "  () => [img.className, 0, 0, 0]))).then(done);"
    )
    assert len(images) == 3 + 5  # box plot, scatter, coverage (model 5 picks frontiers, not weights); 5 runs
    for kind, natural_width, natural_height, shown in images:
        assert natural_width > 0 and natural_height > 0, "an image did not decode"
        if kind == "chart":
            assert shown >= MIN_CHART_SCALE * natural_width, f"a chart drawn {natural_width} px is shown at {shown} px"
        assert shown <= max(width, natural_width)


@pytest.mark.parametrize("width", WIDTHS)
def test_the_conclusion_names_the_best_method_with_the_summary_numbers(report: Path, browser: Any, width: int) -> None:
    _open(browser, report / "report.html", width)
    text = " ".join(browser.find_element("id", "conclusion").text.split())
    summary = json.loads((report / "summary.json").read_text())
    methods = summary["methods"]
    tested = [m for m in methods if m not in ("fixed:0.75", "oracle")]
    best = min(tested, key=lambda m: methods[m]["mean_time_s"])
    entry, base = methods[best], methods["fixed:0.75"]
    name = best.replace("learned:models/model5.zip", "learned:model5")
    box = browser.find_element("id", "conclusion").rect
    assert box["y"] < 400 and box["width"] <= width  # at the top, within the screen
    if entry["mean_diff_s"] > 0:
        low, high = entry["ci95_s"]
        expected = (
            f"{name} explored fastest: {entry['mean_time_s']:,.1f} s on average against {base['mean_time_s']:,.1f} s "
            f"for the baseline fixed:0.75, {entry['reduction_pct']:,.1f} % less time (mean saving "
            f"{entry['mean_diff_s']:,.1f} s, 95 % CI {low:,.1f} to {high:,.1f} s; one-tailed paired t-test p = "
            f"{entry['p_one_tailed']:.2g}, p Holm = {entry['p_holm']:.2g};"
        )
    else:
        expected = f"the fastest, {name}, took {entry['mean_time_s']:,.1f} s"
    assert expected in text, text
    assert f"{entry['oracle_ratio']:.2f} × the time of the oracle" in text
