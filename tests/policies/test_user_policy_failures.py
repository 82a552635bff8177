"""A user's policy that fails during an episode: a rank() (or begin_episode()) that raises, or returns
what the simulator cannot follow, ends ``frontier-rl explore`` with one line naming the policy, what
went wrong and the user's file and line; an error of frontier_rl's own is not blamed on the policy;
and the check a policy object passes before it runs."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from frontier_rl.cli import app
from frontier_rl.errors import ConfigError
from frontier_rl.policies import NearestFrontier
from frontier_rl.policies.user_policies import checked_policy
from tests.policies.user_code import fake_distribution

runner = CliRunner()


FAILING = """
import sys

import numpy as np
from frontier_rl import Ranking


def helper(context):
    raise RuntimeError("boom [/x]")


class Raises:
    name = "raises"

    def rank(self, context, rng):
        return helper(context)


class NumpyRaises:
    name = "numpy-raises"

    def rank(self, context, rng):
        return Ranking(np.argsort(context.frontiers.sizes.reshape(-1, 1000)))


class BeginRaises:
    name = "begin-raises"

    def begin_episode(self, world, config):
        raise KeyError("no map")

    def rank(self, context, rng):
        return Ranking(np.argsort(context.frontiers.distances))


class ReturnsList:
    name = "returns-list"

    def rank(self, context, rng):
        return [0]


class OutOfRange:
    name = "out-of-range"

    def rank(self, context, rng):
        return Ranking(np.array([len(context.frontiers)]))


class Empty:
    name = "empty"

    def rank(self, context, rng):
        return Ranking(np.zeros(0, np.int64))


class Floats:
    name = "floats"

    def rank(self, context, rng):
        return Ranking(np.array([0.5]))


class Exits:
    name = "exits"

    def rank(self, context, rng):
        sys.exit("giving up")


class WeightTooLarge:
    name = "weight-too-large"

    def rank(self, context, rng):
        return Ranking(np.argsort(context.frontiers.distances), weight=1.7)
"""


FAILURES = [
    ("Raises", "policy 'failing.py:Raises' failed in rank(): RuntimeError: boom [/x] (failing.py:9)"),
    ("NumpyRaises", "policy 'failing.py:NumpyRaises' failed in rank(): ValueError: cannot reshape array of size"),
    ("ReturnsList", "policy 'returns-list': rank() returned [0] (type list), not a Ranking"),
    ("OutOfRange", "policy 'out-of-range': its Ranking's order holds"),
    ("Empty", "policy 'empty': its Ranking's order is empty and it sets no goal"),
    ("Floats", "policy 'floats': its Ranking's order is an array of float64 with shape (1,), not a 1-D integer"),
    # sys.exit() ended the command with the message alone, or with exit code 0 and nothing at all
    ("Exits", "policy 'failing.py:Exits' failed in rank(): SystemExit: giving up (failing.py:"),
    ("WeightTooLarge", "policy 'weight-too-large': its Ranking's weight is 1.7 (type float), not a number in [0, 1]"),
]
"""A policy of FAILING and the line its episode ends with, alone or in a team."""


@pytest.mark.parametrize(
    ("member", "line", "robots"),
    [
        *((member, line, robots) for member, line in FAILURES for robots in ("1", "2")),
        # a team refuses a policy that sees the true map before the episode: one robot only
        (
            "BeginRaises",
            "policy 'failing.py:BeginRaises' failed in begin_episode(): KeyError: 'no map' (failing.py:",
            "1",
        ),
    ],
)
def test_a_policy_that_fails_in_an_episode_is_one_line_with_exit_code_2(
    policy_dir: Path, monkeypatch: pytest.MonkeyPatch, member: str, line: str, robots: str
) -> None:
    (policy_dir / "failing.py").write_text(FAILING)
    monkeypatch.chdir(policy_dir)
    result = runner.invoke(app, ["explore", "--policy", f"failing.py:{member}", "--robots", robots, "--max-time", "30"])
    assert result.exit_code == 2, result.output
    assert result.stderr.startswith(f"error: {line}") and len(result.stderr.splitlines()) == 1, result.stderr
    assert result.stdout == "" and "Traceback" not in result.output


def test_the_failing_line_is_the_innermost_of_the_users_code(policy_dir: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (policy_dir / "failing.py").write_text(FAILING)
    (policy_dir.parent / "elsewhere").mkdir()
    monkeypatch.chdir(policy_dir.parent / "elsewhere")  # a file outside the working folder is named by its path
    result = runner.invoke(app, ["explore", "--policy", f"{policy_dir}/failing.py:NumpyRaises", "--max-time", "30"])
    assert result.exit_code == 2, result.output
    numpy_line = FAILING.splitlines().index(
        "        return Ranking(np.argsort(context.frontiers.sizes.reshape(-1, 1000)))"
    )
    assert result.stderr.rstrip().endswith(f"({policy_dir.resolve()}/failing.py:{numpy_line + 1})"), result.stderr


def test_a_module_policy_that_raises_names_its_file(policy_dir: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (policy_dir / "failing_module_xyz.py").write_text(FAILING)
    monkeypatch.syspath_prepend(str(policy_dir))
    monkeypatch.chdir(policy_dir)
    result = runner.invoke(app, ["explore", "--policy", "failing_module_xyz:Raises", "--max-time", "30"])
    assert result.exit_code == 2, result.output
    assert "error: policy 'failing_module_xyz:Raises' failed in rank(): RuntimeError: boom [/x]" in result.stderr
    assert result.stderr.rstrip().endswith("(failing_module_xyz.py:9)"), result.stderr


def test_an_installed_policy_that_raises_names_its_file_in_site_packages(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from frontier_rl.policies import user_failures

    monkeypatch.delitem(sys.modules, "fake_policies", raising=False)  # another test's module of that name
    root = fake_distribution(tmp_path / "site", "fake-raises = fake_policies:Raises\n", module=FAILING)
    monkeypatch.syspath_prepend(str(root))
    installed = (*user_failures._library_roots(), root.resolve())  # as if pip had installed it there
    monkeypatch.setattr(user_failures, "_library_roots", lambda: installed)
    monkeypatch.chdir(tmp_path)
    result = runner.invoke(app, ["explore", "--policy", "fake-raises", "--max-time", "30"])
    assert result.exit_code == 2, result.output
    # the class's own file counts as the user's; the helper it calls, in another file there, would not
    assert "policy 'fake-raises' failed in rank(): RuntimeError: boom [/x] (site/fake_policies.py:9)" in result.stderr


def test_an_error_of_frontier_rl_itself_is_not_blamed_on_the_policy(
    policy_dir: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from frontier_rl.core.sim.simulator import ExplorationSimulator

    # an engine that fails under the user's policy, in code of its own (no Python frame of the test's)
    monkeypatch.setattr(ExplorationSimulator, "execute", math.log)
    result = runner.invoke(app, ["explore", "--policy", f"{policy_dir / 'greedy.py'}:Greedy", "--max-time", "30"])
    assert isinstance(result.exception, TypeError) and "failed in" not in result.output, result.output


@pytest.mark.parametrize(
    ("value", "needle"),
    [
        (NearestFrontier, "got the class NearestFrontier, not a policy object: pass an instance, NearestFrontier()"),
        (None, "got None (type NoneType), not a policy: it needs a 'name' string"),
        (NearestFrontier().rank, "not a policy: it needs a 'name' string"),
        (type("Blank", (), {"name": " ", "rank": lambda s, c, r: None})(), "an object of type Blank, not a policy"),
        (type("NoRank", (), {"name": "x", "rank": 3})(), "it needs a rank(context, rng) method"),
        # a rank of another signature was a TypeError from inside the episode, a traceback at the command line
        (type("OneArg", (), {"name": "x", "rank": lambda s, c: None})(), "whose rank(c) cannot be called as rank("),
        (type("Three", (), {"name": "x", "rank": lambda s, c, r, k: None})(), "whose rank(c, r, k) cannot be"),
        (type("Bad", (), {"name": property(lambda s: 1 / 0)})(), "whose name raised ZeroDivisionError: division by"),
    ],
)
def test_checked_policy_refuses_what_is_not_a_policy_object(value: object, needle: str) -> None:
    with pytest.raises(ConfigError) as info:
        checked_policy(value)
    assert needle in str(info.value)
    policy = NearestFrontier()
    assert checked_policy(policy) is policy


def test_a_policy_files_object_is_named_by_its_type_not_its_module(
    policy_dir: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (policy_dir / "no_name.py").write_text("class NoName:\n    def rank(self, context, rng):\n        return None\n")
    monkeypatch.chdir(policy_dir)
    result = runner.invoke(app, ["explore", "--policy", "no_name.py:NoName"])
    assert result.exit_code == 2
    line = "error: policy 'no_name.py:NoName': NoName() gave an object of type NoName, not a policy: it needs a 'name'"
    assert result.stderr.startswith(line) and "frontier_rl_user_policy_" not in result.stderr, result.stderr
