"""Every ```python block of README.md and of the site's pages runs, as a reader would paste it: on
its own, in a fresh interpreter, in an empty working folder, within a time limit.

A block that cannot run here (it needs a robot or a ROS master) opts out with the line
``<!-- not run: REASON -->`` just above it (:data:`~tests.docs.markdown_pages.SKIP_MARKER`); the
reason is required and shown in the test report. A block that does what a block on another page
does is marked ``<!-- not run: same as PAGE -->`` (PAGE from the repository's root): it is not run
again, and a test checks that a block of PAGE that runs does what it does
(:mod:`tests.docs.same_code`), so the two cannot drift apart.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

from tests.docs.markdown_pages import CodeBlock, code_blocks, pages
from tests.docs.same_code import covers

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


def python_blocks(page_list: list[Path] | None = None) -> list[CodeBlock]:
    """The Python blocks of ``page_list`` (default: every page)."""
    return [block for page in page_list or pages() for block in code_blocks(page) if python_language(block)]


def check_block_runs(block: CodeBlock, folder: Path) -> None:
    """Run ``block`` in ``folder``; skipped where it is marked not to run, failed where it fails."""
    if block.skip_reason:
        pytest.skip(f"not run: {block.skip_reason}")
    try:
        run = subprocess.run(
            [sys.executable, "-c", block.code], cwd=folder, capture_output=True, text=True, timeout=TIMEOUT_S
        )
    except subprocess.TimeoutExpired:
        pytest.fail(f"{block.name} ran longer than {TIMEOUT_S} s")
    assert run.returncode == 0, f"{block.name} failed:\n{run.stderr[-3000:]}"


def check_same_as(block: CodeBlock) -> None:
    """Fail unless a block of the page ``block``'s marker names runs and does what ``block`` does."""
    assert block.same_as is not None, f"{block.name} is not marked 'same as PAGE'"
    page = block.skip_reason.removeprefix("same as ")
    assert block.same_as.is_file(), f"{block.name}: no page {page}"
    others = [b for b in python_blocks([block.same_as]) if not b.skip_reason]
    assert others, f"{block.name}: {page} has no python block that runs"
    gaps = {other.name: covers(other.code, block.code) for other in others}
    assert not all(gaps.values()), f"{block.name}: no block of {page} that runs does it all; it lacks {gaps}"


@pytest.mark.parametrize("block", python_blocks(), ids=lambda b: b.name)
def test_the_block_runs(block: CodeBlock, tmp_path: Path) -> None:
    check_block_runs(block, tmp_path)


@pytest.mark.parametrize("block", [b for b in python_blocks() if b.same_as], ids=lambda b: b.name)
def test_a_block_not_run_as_the_same_as_another_is_that_code(block: CodeBlock) -> None:
    check_same_as(block)


POLICY_CLASS = re.compile(r"^class (\w+)\b[^\n]*:\n(?:[ \t]+[^\n]*\n|\s*\n)*?[ \t]+def rank\(", re.MULTILINE)
"""A class with a ``rank`` method: a policy a reader may save to a file and name as ``FILE.py:CLASS``."""


def policy_classes(block: CodeBlock) -> list[str]:
    """The names of the policy classes ``block`` defines."""
    return POLICY_CLASS.findall(block.code)


LOAD = """
import sys
import frontier_rl.api

def _no_episode(*args, **kwargs):
    raise SystemExit("an episode ran while the file was loaded")

frontier_rl.api.explore = _no_episode  # what frontier_rl.explore names, looked up on first use
from frontier_rl.policies import make_policy
make_policy(sys.argv[1])
"""
"""Load a policy as a command does, with ``explore`` refusing to run."""


def check_loads_quietly(block: CodeBlock, folder: Path) -> None:
    """Save ``block`` as a file in ``folder`` and load each of its policy classes as a command does
    (``FILE.py:CLASS``): loading must run no episode and print nothing."""
    source = folder / "policy_file.py"
    source.write_text(block.code, encoding="utf-8")
    for name in policy_classes(block):
        run = subprocess.run(
            [sys.executable, "-c", LOAD, f"{source}:{name}"],
            cwd=folder,
            capture_output=True,
            text=True,
            timeout=TIMEOUT_S,
        )
        assert run.returncode == 0, f"{block.name}: loading {name} failed:\n{run.stderr[-3000:]}"
        assert run.stdout == "", f"{block.name}: loading {name} printed {run.stdout[:200]!r}"


@pytest.mark.parametrize(
    "block", [b for b in python_blocks() if policy_classes(b) and not b.skip_reason], ids=lambda b: b.name
)
def test_a_documented_policy_file_loads_without_running_anything(block: CodeBlock, tmp_path: Path) -> None:
    check_loads_quietly(block, tmp_path)


def test_a_policy_file_that_runs_an_episode_at_import_is_caught(tmp_path: Path) -> None:
    page = tmp_path / "page.md"
    policy = (
        "import numpy as np\nfrom frontier_rl import DecisionContext, Ranking\n\n\nclass First:\n"
        '    """The first candidate."""\n\n    name = "first"\n\n'
        "    def rank(self, context: DecisionContext, rng: np.random.Generator) -> Ranking:\n"
        "        return Ranking(np.arange(len(context.frontiers)))\n\n\n"
    )
    episode = "frontier_rl.explore(frontier_rl.load_world('lse_arena', seed=0), First(), seed=0)\n"
    page.write_text(
        f"```python\n{policy}print('a line')\n```\n\n"
        f"```python\nimport frontier_rl\n{policy}{episode}```\n\n"
        f"```python\nimport frontier_rl\n{policy}if __name__ == '__main__':\n    {episode}```\n"
    )
    printing, running, guarded = python_blocks([page])
    assert policy_classes(printing) == policy_classes(running) == policy_classes(guarded) == ["First"]
    folders = [tmp_path / name for name in ("printing", "running", "guarded")]  # each its own file
    for folder in folders:
        folder.mkdir()
    with pytest.raises(AssertionError, match="loading First printed 'a line"):
        check_loads_quietly(printing, folders[0])
    with pytest.raises(AssertionError, match="an episode ran while the file was loaded"):
        check_loads_quietly(running, folders[1])
    check_loads_quietly(guarded, folders[2])


def test_a_marked_block_is_left_out_and_others_are_run(tmp_path: Path) -> None:
    page = tmp_path / "page.md"
    page.write_text(
        "# Page\n\n<!-- not run: needs a ROS master -->\n```python\nraise SystemExit(3)\n```\n\n"
        "```python\nopen('ran-1', 'w')\n```\n\n```{code-block} python\nopen('ran-2', 'w')\n```\n\n"
        "```bash\ntouch ran-3\n```\n\n```python\nraise SystemExit(4)\n```\n"
    )
    marked, first, second, failing = python_blocks([page])
    assert marked.skip_reason == "needs a ROS master"
    with pytest.raises(pytest.skip.Exception, match="not run: needs a ROS master"):
        check_block_runs(marked, tmp_path)
    check_block_runs(first, tmp_path)
    check_block_runs(second, tmp_path)
    assert sorted(p.name for p in tmp_path.glob("ran-*")) == ["ran-1", "ran-2"]
    with pytest.raises(AssertionError, match=r"page.md:20 failed"):
        check_block_runs(failing, tmp_path)


def test_a_block_the_same_as_another_must_be_its_code(tmp_path: Path) -> None:
    head = "import tempfile\n\nfrom frontier_rl import evaluate\n\nwith tempfile.TemporaryDirectory() as out:\n"
    run = tmp_path / "run.md"
    run.write_text(
        "<!-- not run: needs a robot -->\n```python\nprint(1)\n```\n\n```python\n"
        f'{head}    summary = evaluate(["nearest"], ["office=2,rooms"], 2, out=out)\n'
        '    print(summary.methods["nearest"].mean_time_s)\n```\n'
    )
    call = '    summary = evaluate(["nearest"], ["office"], 1, out=out)\n'
    variants = [
        head + call,  # other values, nothing printed
        head + call.replace("out=out", 'out=out, baseline="tour"'),
        head + call.replace("1", '"1"'),
        head.replace("evaluate", "evaluate, train") + call,
        head + call + '    print(summary.methods["nearest"].mean)\n',
    ]
    same = tmp_path / "same.md"
    same.write_text("".join(f"<!-- not run: same as {run} -->\n```python\n{code}```\n\n" for code in variants))
    same_as_run, more, other_type, more_imported, other_field = python_blocks([same])
    assert same_as_run.same_as == run and same_as_run.skip_reason == f"same as {run}"
    check_same_as(same_as_run)
    for drifted, missing in [
        (more, 'line 6: summary = evaluate(["nearest"], ["office"], 1, out=out, baseline="tour")'),
        (other_type, 'line 6: summary = evaluate(["nearest"], ["office"], "1", out=out)'),
        (more_imported, "import frontier_rl:train as train"),
        (other_field, ".mean (never read there)"),
    ]:
        with pytest.raises(AssertionError, match=re.escape(missing)):
            check_same_as(drifted)
