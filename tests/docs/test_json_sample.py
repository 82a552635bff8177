"""The getting-started page's sample of ``explore --json`` is what the command prints for that
episode today: every field of the output but the wall time, with its value."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from tests.docs.markdown_pages import DOCS, code_blocks

pytestmark = pytest.mark.slow

PAGE = DOCS / "getting-started.md"
COMMAND = ("explore", "--world", "office", "--seed", "3", "--policy", "tour", "--json")
LEFT_OUT = {"wall_time_s", "real_time_factor"}
"""The fields the sample leaves out: they differ from run to run."""


def test_the_json_sample_is_the_commands_output() -> None:
    samples = [block for block in code_blocks(PAGE) if block.language == "json"]
    assert len(samples) == 1, f"{PAGE.name} has {len(samples)} json blocks"
    shown = json.loads(samples[0].code)
    assert (shown["world"], str(shown["seed"]), shown["policy"]) == (COMMAND[2], COMMAND[4], COMMAND[6])
    run = subprocess.run(
        [sys.executable, "-m", "frontier_rl.cli", *COMMAND], capture_output=True, text=True, timeout=300
    )
    assert run.returncode == 0, run.stderr[-2000:]
    printed = json.loads(run.stdout)
    assert set(printed) - set(shown) == LEFT_OUT, "the sample's fields differ from the output's"
    assert {key: printed[key] for key in shown} == shown, "the sample's values differ: run the command again"
