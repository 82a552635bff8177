"""The getting-started page's sample of ``explore --json`` is what the command above it prints
today: every field of the output but the wall time, with its value."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from tests.docs.markdown_pages import DOCS, CodeBlock, code_blocks
from tests.docs.test_cli_lines import SHELLS, invocations, shell_lines

pytestmark = pytest.mark.slow

PAGE = DOCS / "getting-started.md"
LEFT_OUT = {"wall_time_s", "real_time_factor"}
"""The fields the sample leaves out: they differ from run to run."""


def sample_and_command(page: Path) -> tuple[CodeBlock, list[str]]:
    """The first json block of ``page`` and the ``frontier-rl explore`` command of the shell block
    nearest above it, as arguments without ``frontier-rl`` and without ``--png FILE``."""
    blocks = code_blocks(page)
    first = next(i for i, block in enumerate(blocks) if block.language == "json")
    for block in reversed(blocks[:first]):
        found = [args for line in shell_lines(block) for args in invocations(line)] if block.language in SHELLS else []
        explore = [list(args) for args in found if args[:1] == ("explore",)]
        if explore:
            words = explore[0]
            if "--png" in words:
                at = words.index("--png")
                del words[at : at + 2]
            return blocks[first], words
    raise AssertionError(f"{page.name}: no frontier-rl explore line above its json block")


def test_the_json_sample_is_the_commands_output(tmp_path: Path) -> None:
    sample, command = sample_and_command(PAGE)
    assert "--json" in command, command
    shown = json.loads(sample.code)
    run = subprocess.run(
        [sys.executable, "-m", "frontier_rl.cli", *command], cwd=tmp_path, capture_output=True, text=True, timeout=300
    )
    assert run.returncode == 0, run.stderr[-2000:]
    printed = json.loads(run.stdout)
    assert set(printed) - set(shown) == LEFT_OUT, "the sample's fields differ from the output's"
    assert {key: printed[key] for key in shown} == shown, "the sample's values differ: run the command again"


def test_the_sample_is_read_with_the_command_above_it(tmp_path: Path) -> None:
    page = tmp_path / "page.md"
    page.write_text(
        "```bash\nfrontier-rl explore --world rooms --seed 1\n```\n\n"
        "```bash\nfrontier-rl explore --world office --seed 3 --policy tour --png run.png --json\n```\n\n"
        'Text.\n\n```json\n{"world": "office"}\n```\n\n```json\n{}\n```\n'
    )
    sample, command = sample_and_command(page)
    assert sample.code == '{"world": "office"}\n'
    assert command == ["explore", "--world", "office", "--seed", "3", "--policy", "tour", "--json"]
