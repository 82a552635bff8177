"""Tests of the user's own policies: FILE.py:CLASS, MODULE:CLASS and the frontier_rl.policies entry points,
parsed into a PolicySpec, loaded, checked, and run by explore (the CLI); evaluate's runs are in
tests/policies/test_user_policy_experiments.py."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from frontier_rl.cli import app
from frontier_rl.core.sim.episode import run_episode
from frontier_rl.core.world.catalog import generate_world
from frontier_rl.errors import ConfigError, FrontierRLError, UnknownNameError
from frontier_rl.evaluation.report.method_notes import describe_method
from frontier_rl.evaluation.running.fingerprints import method_fingerprint
from frontier_rl.evaluation.running.methods import episode_policy
from frontier_rl.policies import (
    BuiltinPolicy,
    NearestFrontier,
    PolicyKind,
    PolicySpec,
    installed_policies,
    make_policy,
)
from frontier_rl.swarm.config import TeamMethod
from tests.policies.user_code import GREEDY, fake_distribution

runner = CliRunner()


@pytest.mark.parametrize(
    ("text", "kind", "name", "argument"),
    [
        ("nearest", PolicyKind.BUILTIN, "nearest", ""),
        (" fixed:0.75 ", PolicyKind.BUILTIN, "fixed", "0.75"),
        ("learned:runs/a:b.zip", PolicyKind.BUILTIN, "learned", "runs/a:b.zip"),
        ("tour:4", PolicyKind.BUILTIN, "tour", "4"),
        ("my.py:Greedy", PolicyKind.FILE, "my.py", "Greedy"),
        ("/abs/dir:x/my.py:Outer.Inner", PolicyKind.FILE, "/abs/dir:x/my.py", "Outer.Inner"),
        ("my_pkg.policies:Greedy", PolicyKind.MODULE, "my_pkg.policies", "Greedy"),
        ("my-policy", PolicyKind.ENTRY_POINT, "my-policy", ""),
    ],
)
def test_a_spec_is_parsed_once_into_its_kind_and_parts(text: str, kind: PolicyKind, name: str, argument: str) -> None:
    spec = PolicySpec.parse(text)
    assert (spec.kind, spec.name, spec.argument) == (kind, name, argument)
    assert PolicySpec.parse(str(spec)) == spec
    assert spec.is_user_code == (kind is not PolicyKind.BUILTIN)


@pytest.mark.parametrize(
    ("text", "builtin", "weight", "stops"),
    [
        ("nearest", BuiltinPolicy.NEAREST, None, None),
        ("explore-lite", BuiltinPolicy.EXPLORE_LITE, None, None),
        ("fixed:0.75", BuiltinPolicy.FIXED, 0.75, None),
        ("fixed:1e-1", BuiltinPolicy.FIXED, 0.1, None),
        ("tour", BuiltinPolicy.TOUR, None, 10),
        ("tour:4", BuiltinPolicy.TOUR, None, 4),
        ("learned:m.zip", BuiltinPolicy.LEARNED, None, None),
        ("my.py:Greedy", None, None, None),
        ("my-policy", None, None, None),
    ],
)
def test_a_built_in_policy_is_typed_when_parsed(
    text: str, builtin: BuiltinPolicy | None, weight: float | None, stops: int | None
) -> None:
    spec = PolicySpec.parse(text)
    assert (spec.builtin, spec.weight, spec.stops) == (builtin, weight, stops)
    assert str(spec) == text  # the method's name as written, whatever the typed values


@pytest.mark.parametrize(
    ("name", "argument", "error", "needle"),
    [
        ("fixed", "1.5", ConfigError, "weight must be in [0, 1], got 1.5"),
        ("fixed", "", ConfigError, "fixed:W needs a weight"),
        ("tour", "x", ConfigError, "whole number of stops"),
        ("tour", "0", ConfigError, "tour:N takes 1 to 16 stops, got 'tour:0'"),
        ("learned", "", ConfigError, "needs a model file"),
        ("nearest", "3", UnknownNameError, "unknown policy 'nearest:3'"),
        ("greedy", "", UnknownNameError, "unknown policy 'greedy'"),
    ],
)
def test_a_built_in_spec_made_directly_is_checked_as_a_parsed_one(
    name: str, argument: str, error: type[Exception], needle: str
) -> None:
    with pytest.raises(error, match=re.escape(needle)):
        PolicySpec(PolicyKind.BUILTIN, name, argument)


def test_relative_files_resolve_against_a_base_folder(tmp_path: Path) -> None:
    assert PolicySpec.parse("sub/my.py:G").against(tmp_path).name == str(tmp_path / "sub/my.py")
    assert PolicySpec.parse("learned:m.zip").against(tmp_path).argument == str(tmp_path / "m.zip")
    assert PolicySpec.parse("/abs/my.py:G").against(tmp_path).name == "/abs/my.py"
    assert PolicySpec.parse("nearest").against(tmp_path) == PolicySpec.parse("nearest")


def test_a_team_method_of_a_file_policy_keeps_the_spec() -> None:
    method = TeamMethod.parse("my.py:Greedy@2:coordinated")
    assert (method.policy, method.robots, method.strategy.value) == (
        PolicySpec(PolicyKind.FILE, "my.py", "Greedy"),
        2,
        "coordinated",
    )
    assert str(method) == "my.py:Greedy@2:coordinated"  # printed back as it was written


@pytest.mark.parametrize(
    "text", ["nearest", "fixed:0.75", "learned:models/model7.zip@3", "tour:4@2:rendezvous", "pkg.mod:Cls@8:coordinated"]
)
def test_a_method_prints_back_as_written(text: str) -> None:
    assert str(TeamMethod.parse(text)) == text


def test_a_policy_file_outside_the_repository_runs_an_episode(policy_dir: Path) -> None:
    policy = make_policy(f"{policy_dir / 'greedy.py'}:Greedy")
    assert policy.name == "greedy"
    world = generate_world("office", 1)
    result = run_episode(world, policy, seed=1)
    nearest = run_episode(world, NearestFrontier(), seed=1)
    assert result.decisions > 0 and result.coverage > 0.5
    assert result.sim_time_s != nearest.sim_time_s  # it ranks by its own rule, not the nearest's


def test_a_relative_policy_file_resolves_against_the_working_folder(
    policy_dir: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(policy_dir)
    assert make_policy("greedy.py:Greedy").name == "greedy"


def test_explore_json_runs_a_policy_file(policy_dir: Path) -> None:
    spec = f"{policy_dir / 'greedy.py'}:Greedy"
    result = runner.invoke(app, ["explore", "--policy", spec, "--seed", "2", "--max-time", "120", "--json"])
    assert result.exit_code == 0, result.output
    summary = json.loads(result.output)
    assert summary["policy"] == "greedy" and summary["decisions"] > 0


def test_explore_runs_a_team_of_a_policy_file(policy_dir: Path) -> None:
    spec = f"{policy_dir / 'greedy.py'}:Greedy"
    args = ["explore", "--policy", spec, "--robots", "2", "--strategy", "coordinated", "--max-time", "60", "--json"]
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    assert json.loads(result.output)["robots"] == 2


def _frontier_rl(args: list[str], cwd: Path, pythonpath: Path) -> subprocess.CompletedProcess[str]:
    """The installed ``frontier-rl`` command, run in ``cwd`` with ``pythonpath`` on PYTHONPATH."""
    command = Path(sys.executable).with_name("frontier-rl")
    env = os.environ | {"PYTHONPATH": str(pythonpath)}
    return subprocess.run([str(command), *args], cwd=cwd, env=env, capture_output=True, text=True, timeout=120)


def test_module_class_works_with_pythonpath(policy_dir: Path, tmp_path: Path) -> None:
    package = policy_dir / "my_policies"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "greedy.py").write_text(GREEDY)
    run = _frontier_rl(
        ["explore", "--policy", "my_policies.greedy:Greedy", "--max-time", "60", "--json"], tmp_path, policy_dir
    )
    assert run.returncode == 0, run.stderr
    assert json.loads(run.stdout)["policy"] == "greedy"


def test_an_installed_package_registers_policies_by_entry_point(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    root = fake_distribution(tmp_path / "site", "fake-greedy = fake_policies:Greedy\nnearest = fake_policies:Greedy\n")
    monkeypatch.syspath_prepend(str(root))
    assert installed_policies() == ("fake-greedy",)  # a built-in name is never taken from a package
    assert make_policy("fake-greedy").name == "greedy"
    assert isinstance(make_policy("nearest"), NearestFrontier)  # built-in names win
    assert method_fingerprint("fake-greedy") == "fake-greedy#dist:fake-policies==1.2"
    note = describe_method("fake-greedy")
    assert note.description == "A user policy: The largest frontier per metre to drive."
    assert "package fake-policies 1.2" in note.parameters


def test_explore_runs_an_installed_policy(tmp_path: Path) -> None:
    root = fake_distribution(tmp_path / "site", "fake-greedy = fake_policies:Greedy\n")
    run = _frontier_rl(["explore", "--policy", "fake-greedy", "--max-time", "60", "--json"], tmp_path, root)
    assert run.returncode == 0, run.stderr
    assert json.loads(run.stdout)["policy"] == "greedy"


def test_a_user_policy_is_built_afresh_for_every_episode(policy_dir: Path) -> None:
    spec = f"{policy_dir / 'greedy.py'}:Counting"
    first, second = episode_policy(spec, False), episode_policy(spec, False)
    assert first is not second and type(first) is type(second)  # the module is loaded once
    assert episode_policy("nearest", False) is episode_policy("nearest", False)  # built-ins stay cached


def test_the_fingerprint_holds_the_policy_file_hash(policy_dir: Path) -> None:
    path = policy_dir / "greedy.py"
    before = method_fingerprint(f"{path}:Greedy@2")
    assert before.startswith(f"{path}:Greedy@2#sha256:")
    path.write_text(GREEDY + "\n# edited\n")
    assert method_fingerprint(f"{path}:Greedy@2") != before


def test_the_method_note_names_the_file_the_class_and_its_docstring(policy_dir: Path) -> None:
    note = describe_method("greedy.py:Greedy@2", base_dir=policy_dir)
    assert "a user policy: The largest frontier per metre to drive." in note.description
    assert f"Greedy from file {policy_dir / 'greedy.py'}" in note.parameters and "sha256 " in note.parameters


BAD_MODULES = {
    "syntax.py": "x = 1\ndef broken(:\n",
    "raises.py": "raise RuntimeError('no map server here')\n",
    "needs_args.py": "class Weighted:\n    name = 'w'\n    def __init__(self, w):\n        self.w = w\n"
    "    def rank(self, context, rng):\n        return None\n",
    "no_rank.py": "class NoRank:\n    name = 'no-rank'\n",
    "bad_name.py": "class BadName:\n    name = 3\n    def rank(self, context, rng):\n        return None\n",
    "constant.py": "GREEDY = 3\n",
    "imports_missing.py": "import no_such_dependency_xyz\n",
    "run.png": "not python",
    # a script that parses its command line on import, and a constructor that gives up: the command ended
    # with the script's usage line, or with exit code 0 and nothing
    # (it exits whatever the command line: a condition on sys.argv made the test depend on how pytest was started)
    "parses_argv.py": "import sys\nsys.exit(2)  # as argparse does, after its usage line\n",
    "exits.py": "import sys\nclass Quits:\n    name = 'q'\n    def __init__(self):\n        sys.exit(0)\n",
}


@pytest.mark.parametrize(
    ("spec", "error", "needle"),
    [
        ("missing.py:Greedy", ConfigError, "policy file 'missing.py' does not exist"),
        ("syntax.py:X", ConfigError, "syntax error at {dir}/syntax.py:2"),
        ("raises.py:X", ConfigError, "raised on import: RuntimeError: no map server here"),
        ("needs_args.py:Weighted", ConfigError, "calling Weighted() with no arguments raised TypeError"),
        ("no_rank.py:NoRank", ConfigError, "not a policy: it needs a rank(context, rng) method"),
        ("bad_name.py:BadName", ConfigError, "not a policy: it needs a 'name' string"),
        ("constant.py:GREEDY", ConfigError, "'GREEDY' is 3 (type int), not a class"),
        ("greedy.py:Nope", UnknownNameError, "has no 'Nope' (classes with a rank method there: Greedy, Counting)"),
        ("greedy.py", ConfigError, "names a file: write FILE.py:CLASS"),
        ("greedy.py:1x", ConfigError, "needs a class name after its last colon"),
        ("no_such_module_xyz:Greedy", UnknownNameError, "no module named 'no_such_module_xyz' on the Python path"),
        ("run.png:Greedy", ConfigError, "'run.png' is a file but not Python: a policy file's name ends in .py"),
        ("imports_missing.py:X", ConfigError, "ModuleNotFoundError: No module named 'no_such_dependency_xyz'"),
        ("no-such-policy", UnknownNameError, "unknown policy 'no-such-policy'; choose one of nearest"),
        ("parses_argv.py:X", ConfigError, "'parses_argv.py' exited on import (SystemExit: 2): a script's command-line"),
        ("exits.py:Quits", ConfigError, "calling Quits() with no arguments raised SystemExit: 0"),
    ],
)
def test_every_bad_user_policy_is_one_line_with_exit_code_2(
    policy_dir: Path, monkeypatch: pytest.MonkeyPatch, spec: str, error: type[FrontierRLError], needle: str
) -> None:
    for name, text in BAD_MODULES.items():
        (policy_dir / name).write_text(text)
    monkeypatch.chdir(policy_dir)
    needle = needle.format(dir=policy_dir.resolve())
    with pytest.raises(error) as info:
        make_policy(spec)
    assert needle in str(info.value)
    result = runner.invoke(app, ["explore", "--policy", spec, "--max-time", "5"])
    assert result.exit_code == 2, result.output
    assert needle in result.output and len(result.output.strip().splitlines()) == 1, result.output
    assert "Traceback" not in result.output


def test_an_entry_point_that_fails_to_load_is_one_line(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    root = fake_distribution(tmp_path / "site", "broken = fake_policies:Missing\n", module="X = 1\n")
    monkeypatch.syspath_prepend(str(root))
    with pytest.raises(ConfigError, match=r"installed policy 'broken' \(fake_policies:Missing\) raised on load"):
        make_policy("broken")


def test_a_model_file_never_names_code(policy_dir: Path) -> None:
    """learned: reads a model file and never runs it, even where it names a Python file."""
    code = policy_dir / "evil.py"
    code.write_text("import pathlib\npathlib.Path(__file__).with_suffix('.ran').write_text('ran')\n")
    for spec in (f"learned:{code}", f"learned:{code}:Greedy"):
        with pytest.raises(FrontierRLError, match=r"evil\.py"):
            make_policy(spec)
    assert not code.with_suffix(".ran").exists()
    with pytest.raises(UnknownNameError):  # named as FILE.py:CLASS, the same file runs: the user's consent
        make_policy(f"{code}:Greedy")
    assert code.with_suffix(".ran").exists()
