"""Every ```python block of README.md and of the site's pages runs, as a reader would paste it: on
its own, in a fresh interpreter, in an empty working folder, within a time limit.

A block that cannot run here (it needs a robot or a ROS master) opts out with the line
``<!-- not run: REASON -->`` just above it (:data:`~tests.docs.markdown_pages.SKIP_MARKER`); the
reason is required and shown in the test report.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from tests.docs.markdown_pages import CodeBlock, code_blocks, pages

pytestmark = pytest.mark.slow

TIMEOUT_S = 300
"""A block runs at most this long (s): a tiny training run takes about a minute on two cores."""
PYTHON = ("python", "py", "python3", "pycon")


def python_language(block: CodeBlock) -> bool:
    """Whether ``block`` is Python: ```python, or MyST's ```{code-block} python."""
    info = block.language
    if info in ("{code-block}", "{code}", "{sourcecode}"):
        return _directive_language(block) in PYTHON
    return info in PYTHON


def _directive_language(block: CodeBlock) -> str:
    """The language argument of a ``{code-block}`` fence, read from its page."""
    line = block.page.read_text(encoding="utf-8").splitlines()[block.line - 1]
    words = line.strip("`~ ").split()
    return words[1] if len(words) > 1 else ""


def python_blocks() -> list[CodeBlock]:
    return [block for page in pages() for block in code_blocks(page) if python_language(block)]


@pytest.mark.parametrize("block", python_blocks(), ids=lambda b: b.name)
def test_the_block_runs(block: CodeBlock, tmp_path: Path) -> None:
    if block.skip_reason:
        pytest.skip(f"not run: {block.skip_reason}")
    try:
        run = subprocess.run(
            [sys.executable, "-c", block.code], cwd=tmp_path, capture_output=True, text=True, timeout=TIMEOUT_S
        )
    except subprocess.TimeoutExpired:
        pytest.fail(f"{block.name} ran longer than {TIMEOUT_S} s")
    assert run.returncode == 0, f"{block.name} failed:\n{run.stderr[-3000:]}"


def test_a_marked_block_is_left_out_and_others_are_run(tmp_path: Path) -> None:
    page = tmp_path / "page.md"
    page.write_text(
        "# Page\n\n<!-- not run: needs a ROS master -->\n```python\nimport rospy\n```\n\n"
        "```python\nprint(1)\n```\n\n```{code-block} python\nprint(2)\n```\n\n```bash\nls\n```\n"
    )
    blocks = [b for b in code_blocks(page) if python_language(b)]
    assert [(b.code, b.skip_reason) for b in blocks] == [
        ("import rospy\n", "needs a ROS master"),
        ("print(1)\n", None),
        ("print(2)\n", None),
    ]
