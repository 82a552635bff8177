"""Tests of the package's Python API: the lazy top-level names, frontier_rl.api's load_world / explore /
evaluate / train, and the typed experiment summary read back from summary.json."""

from __future__ import annotations

import json
import math
import re
import subprocess
import sys
import textwrap
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import frontier_rl
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.metrics import EndReason
from frontier_rl.core.world.robot import Pose
from frontier_rl.errors import ConfigError, PolicyError, UnknownNameError
from frontier_rl.evaluation.results.summary import ExperimentSummary, MethodSummary
from frontier_rl.seeds import MAX_SEED
from frontier_rl.swarm import TeamConfig, TeamResult

HEAVY = ("numba", "gymnasium", "torch", "stable_baselines3")
"""Modules the light imports must not load."""

SHORT = SimConfig(max_sim_time=90.0)


def _loaded_after(code: str) -> set[str]:
    """The top-level modules loaded after ``code`` runs in a fresh interpreter."""
    script = f"{code}\nimport sys, json\nprint(json.dumps(sorted({{m.split('.')[0] for m in sys.modules}})))"
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120, check=True)
    return set(json.loads(run.stdout.strip().splitlines()[-1]))


def test_importing_the_package_loads_none_of_the_heavy_libraries() -> None:
    loaded = _loaded_after("import frontier_rl")
    assert not loaded & {*HEAVY, "numpy", "scipy"}, loaded & {*HEAVY, "numpy", "scipy"}


def test_the_policy_interface_and_the_api_load_neither_gymnasium_nor_torch() -> None:
    light = [n for n in frontier_rl.__all__ if n not in ("train", "TrainConfig")]
    loaded = _loaded_after(f"from frontier_rl import {', '.join(light)}")
    assert not loaded & {"gymnasium", "torch", "stable_baselines3"}


def test_every_public_name_resolves_and_is_listed() -> None:
    for name in frontier_rl.__all__:
        assert getattr(frontier_rl, name) is not None, name
    assert set(frontier_rl.__all__) <= set(dir(frontier_rl))
    assert frontier_rl.Ranking.__module__ == "frontier_rl.core.sim.episode"
    assert frontier_rl.ExperimentSummary is ExperimentSummary
    assert isinstance(frontier_rl.__version__, str)
    with pytest.raises(AttributeError, match="no attribute 'Nope'"):
        _ = frontier_rl.Nope  # type: ignore[attr-defined]


def test_the_package_docstring_example_runs() -> None:
    doc = frontier_rl.__doc__ or ""
    example = textwrap.dedent(doc.split("office::\n", 1)[1].split("\nSaved in", 1)[0])
    namespace: dict[str, object] = {}
    exec(compile(example, "frontier_rl.__doc__", "exec"), namespace)
    assert namespace["result"].coverage > 0.9  # type: ignore[attr-defined]


def test_load_world_draws_a_generator_and_reads_a_file(tmp_path: Path) -> None:
    world = frontier_rl.load_world("office", seed=3)
    assert world.name == "office"
    assert np.array_equal(world.grid.data, frontier_rl.load_world("office", 3).grid.data)
    moved = frontier_rl.load_world("office", 3, start=Pose(1.0, 1.0, 0.0))
    assert (moved.start.x, moved.start.y) == (1.0, 1.0)
    with pytest.raises(UnknownNameError, match="unknown world 'atlantis'"):
        frontier_rl.load_world("atlantis")


def test_load_world_finds_a_catalogue_map() -> None:
    world = frontier_rl.load_world("nav2_depot")
    assert world.grid.shape[0] > 100 and world.explorable_count > 0


def test_explore_takes_a_policy_object_or_a_spec_and_repeats_exactly() -> None:
    by_spec = frontier_rl.explore("rooms", "nearest", seed=4, config=SHORT)
    by_object = frontier_rl.explore(
        frontier_rl.load_world("rooms", 4), frontier_rl.NearestFrontier(), seed=4, config=SHORT
    )
    assert by_spec.sim_time_s == by_object.sim_time_s and by_spec.decisions == by_object.decisions
    assert np.array_equal(by_spec.trajectory, by_object.trajectory)
    other = frontier_rl.explore("rooms", "largest", seed=4, config=SHORT)
    assert other.sim_time_s != by_spec.sim_time_s or other.path_length_m != by_spec.path_length_m


@pytest.mark.parametrize("seed", [-1, 1.5, MAX_SEED + 1, True, "3", None])
def test_a_bad_seed_is_one_line_naming_it(tmp_path: Path, seed: object) -> None:
    needle = f"seed must be a whole number from 0 to {MAX_SEED}, got "
    with pytest.raises(ConfigError, match=needle):
        frontier_rl.load_world("office", seed=seed)  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match=needle):
        frontier_rl.explore("office", "nearest", seed=seed)  # type: ignore[call-overload]
    with pytest.raises(ConfigError, match=needle):
        frontier_rl.explore(frontier_rl.load_world("office"), "nearest", seed=seed)  # type: ignore[call-overload]
    with pytest.raises(ConfigError, match=needle):
        frontier_rl.evaluate(["nearest"], ["office"], 1, out=tmp_path / "run", seed=seed)  # type: ignore[arg-type]
    assert not (tmp_path / "run").exists()


def test_the_report_says_how_to_run_the_call_again() -> None:
    """It listed the baseline and the oracle among the methods and left out out= and baseline=: run as
    written, it added fixed:0.75 and failed for want of out."""
    from frontier_rl.api import _call_text
    from frontier_rl.evaluation.running.experiment import ExperimentConfig
    from frontier_rl.swarm import Failure

    plain = ExperimentConfig(("nearest", "my.py:P"), ("office", "rooms"), 10, baseline="nearest")
    given = {"out": "results/x", "oracle": True, "outliers": None, "pictures": None}
    text = _call_text(["my.py:P"], ["office", "rooms"], plain, given)
    assert text == "frontier_rl.evaluate(['my.py:P'], ['office', 'rooms'], 10, out='results/x', baseline='nearest')"
    changed = ExperimentConfig(("nearest@2",), ("office",), 1, seed=3, baseline="nearest@2",
                               sim=SimConfig(max_sim_time=60.0), failures=(Failure(0, 5.0),))  # fmt: skip
    given = {"out": "r", "oracle": False, "outliers": [500.0], "pictures": 0}
    text = _call_text(["nearest@2"], ["office"], changed, given)
    assert text.endswith(
        "out='r', baseline='nearest@2', oracle=False, seed=3, outliers=[500.0], pictures=0, "
        "failures=<the failures in experiment.json>, config=<the sim settings in experiment.json>)"
    )


def test_a_script_without_the_main_guard_is_told_why_its_workers_died(tmp_path: Path) -> None:
    """Each worker imported the script again and died starting a pool of its own: the error said only
    that the workers had died."""
    script = tmp_path / "no_guard.py"
    script.write_text('import frontier_rl\n\nfrontier_rl.evaluate(["nearest"], ["office"], 1, out="run", workers=2)\n')
    done = subprocess.run(
        [sys.executable, str(script)], cwd=tmp_path, capture_output=True, text=True, timeout=300, check=False
    )
    assert done.returncode == 1
    last = done.stderr.strip().splitlines()[-1]
    assert "(exit code 3)" in last and last.endswith(
        "the script calls frontier_rl.evaluate() where its worker processes import it again: call it under "
        '`if __name__ == "__main__":`'
    )
    assert done.stderr.count("Traceback") == 1  # the script's own: no worker's


def test_a_worker_killed_in_a_command_gets_no_hint_about_scripts(tmp_path: Path) -> None:
    """Every worker death of `frontier-rl evaluate` (a console script) ended with the hint."""
    (tmp_path / "killer.py").write_text(
        "import os, signal\n\n\nclass Killer:\n    name = 'killer'\n\n"
        "    def rank(self, context, rng):\n        os.kill(os.getpid(), signal.SIGKILL)\n"
    )
    args = ["evaluate", "--methods", "killer.py:Killer", "--worlds", "office", "--episodes", "1", "--no-oracle",
            "--workers", "2", "--no-progress", "--out", "run"]  # fmt: skip
    command = str(Path(sys.executable).with_name("frontier-rl"))
    done = subprocess.run([command, *args], cwd=tmp_path, capture_output=True, text=True, timeout=300, check=False)
    assert done.returncode != 0 and "(exit code -9)" in done.stderr, done.stderr
    assert "__main__" not in done.stderr


def test_a_start_that_is_no_pose_is_one_line_naming_it() -> None:
    needle = "start pose must be a Pose (x, y, theta) in m, m and rad, got (2.0, 2.0)"
    with pytest.raises(ConfigError, match=re.escape(needle)):
        frontier_rl.load_world("office", start=(2.0, 2.0))  # type: ignore[arg-type]


def test_a_numpy_seed_is_a_seed() -> None:
    assert frontier_rl.load_world("office", np.int64(3)).start == frontier_rl.load_world("office", 3).start  # type: ignore[arg-type]


def test_evaluate_takes_numpy_numbers_as_load_world_and_explore_do(tmp_path: Path) -> None:
    """episodes=np.int64(1), seed=np.int64(2) and outliers=np.array([10.0]) were refused."""
    summary = frontier_rl.evaluate(
        ["nearest"], ["office"], np.int64(1), out=tmp_path / "run", baseline="nearest",  # type: ignore[arg-type]
        seed=np.int64(2), outliers=np.array([10.0, 20.0]), pictures=np.int64(0),  # type: ignore[arg-type]
        config=SimConfig(max_sim_time=30.0), workers=1, backend="serial",
    )  # fmt: skip
    assert summary.episodes == 1
    # the line to run it again holds Python's numbers (a NumPy array's text would not run)
    assert "seed=2, outliers=[10.0, 20.0], pictures=0," in (tmp_path / "run" / "report.md").read_text()


class _Answers:
    """A policy whose rank() returns ``answer``."""

    name = "answers"

    def __init__(self, answer: object = None) -> None:
        self.answer = answer

    def rank(self, context: frontier_rl.DecisionContext, rng: np.random.Generator) -> frontier_rl.Ranking:
        return self.answer  # type: ignore[return-value]


@pytest.mark.parametrize(
    ("policy", "needle"),
    [
        (None, "explore() got None (type NoneType), not a policy: it needs a 'name' string"),
        (frontier_rl.NearestFrontier, "got the class NearestFrontier, not a policy object: pass an instance"),
        (_Answers, "got the class _Answers, not a policy object: pass an instance, _Answers()"),
        (3, "explore() got 3 (type int), not a policy"),
        (type("Unnamed", (), {})(), "explore() got an object of type Unnamed, not a policy: it needs a 'name' string"),
    ],
)
def test_what_is_not_a_policy_is_refused_before_the_episode(policy: object, needle: str) -> None:
    with pytest.raises(ConfigError) as info:
        frontier_rl.explore("office", policy)  # type: ignore[call-overload]
    assert needle in str(info.value)


def test_a_policy_object_that_returns_a_bad_ranking_is_one_line() -> None:
    with pytest.raises(
        PolicyError, match=r"^policy 'answers': rank\(\) returned \[2, 1\] \(type list\), not a Ranking$"
    ):
        frontier_rl.explore("office", _Answers([2, 1]), config=SHORT)


def test_explore_runs_a_team_and_calls_the_decision_hook() -> None:
    team = frontier_rl.explore("office", "nearest", seed=1, config=SHORT, team=TeamConfig(robots=2))
    assert isinstance(team, TeamResult) and team.robots == 2
    seen: list[float] = []
    result = frontier_rl.explore(
        "office", "nearest", seed=1, config=SHORT, on_decision=lambda s, c, r: seen.append(c.sim_time)
    )
    assert len(seen) == result.decisions
    with pytest.raises(ConfigError, match="on_decision"):
        frontier_rl.explore("office", "nearest", team=TeamConfig(robots=2), on_decision=lambda s, c, r: None)


def test_evaluate_returns_the_typed_summary_it_wrote(tmp_path: Path) -> None:
    summary = frontier_rl.evaluate(
        ["nearest", "largest"],
        ["office"],
        2,
        out=tmp_path / "run",
        baseline="nearest",
        oracle=False,
        config=SHORT,
        backend="serial",
        pictures=0,
        command="python my_study.py",
    )
    assert isinstance(summary, ExperimentSummary)
    assert "python my_study.py" in (tmp_path / "run/report.md").read_text()
    assert (summary.baseline, summary.reference, summary.worlds, summary.episodes) == ("nearest", None, ("office",), 2)
    assert list(summary.methods) == ["nearest", "largest"] and summary.tested == ("largest",)
    largest = summary.methods["largest"]
    assert isinstance(largest, MethodSummary) and largest.n == 2 and largest.robots == 1
    assert largest.end_reasons is not None and sum(largest.end_reasons.values()) == 2
    assert [cut.threshold_s for cut in summary.outliers] == [1000.0, 2000.0]
    raw = json.loads((tmp_path / "run/summary.json").read_text())
    assert largest.mean_time_s == raw["methods"]["largest"]["mean_time_s"]
    assert ExperimentSummary.load(tmp_path / "run") == summary == ExperimentSummary.load(tmp_path / "run/summary.json")


@pytest.mark.parametrize(
    ("kwargs", "needle"),
    [
        ({"methods": "nearest"}, "methods and worlds must be lists"),
        ({"outliers": [-1.0]}, "outliers must be positive"),
        ({"outliers": "1000"}, "outliers must be a list of seconds, got '1000'"),
        ({"outliers": [math.inf]}, "outliers must be positive numbers of seconds, got inf"),
        ({"pictures": True}, "pictures must be a whole number"),
        ({"methods": ["nearest", None]}, "methods and worlds must be lists of names"),
        ({"worlds": [3]}, "methods and worlds must be lists of names"),
        ({"pictures": -1}, "pictures must be a whole number"),
        ({"methods": ["nearest", "bogus"]}, "unknown policy 'bogus'"),
    ],
)
def test_evaluate_refuses_bad_arguments_before_running(tmp_path: Path, kwargs: dict[str, object], needle: str) -> None:
    arguments: dict[str, object] = {"methods": ["nearest"], "worlds": ["office"], "episodes": 1} | kwargs
    with pytest.raises((ConfigError, UnknownNameError), match=needle):
        frontier_rl.evaluate(**arguments, out=tmp_path / "run", backend="serial")  # type: ignore[arg-type]
    assert not (tmp_path / "run" / "summary.json").exists()


def test_a_summary_with_a_bad_field_is_one_line_naming_it(tmp_path: Path) -> None:
    good = {
        "baseline": "nearest",
        "reference": None,
        "worlds": ["office"],
        "episodes": 1,
        "seed": 0,
        "methods": {"nearest": {"n": 1, "mean_time_s": 10.0, "ci95_s": [None, None]}},
        "outliers": {},
    }
    summary = ExperimentSummary.from_json(good)
    assert summary.methods["nearest"].mean_time_s == 10.0 and summary.methods["nearest"].p_holm is None
    ended = {"n": 1, "mean_time_s": 10.0, "end_reasons": {"explored": 1, "failed": 0}}
    typed = ExperimentSummary.from_json({**good, "methods": {"nearest": ended}}).methods["nearest"]
    assert typed.end_reasons == {EndReason.EXPLORED: 1, EndReason.FAILED: 0}
    assert all(type(reason) is EndReason for reason in typed.end_reasons or {})
    bad_cases = [
        ({**good, "episodes": "1"}, "episodes must be a whole number"),
        (
            {**good, "methods": {"nearest": {"n": 1, "mean_time_s": "fast", "ci95_s": [0, 1]}}},
            "mean_time_s must be a number",
        ),
        ({**good, "methods": {"nearest": {"n": 1}}}, "lacks mean_time_s"),
        ({**good, "outliers": {"soon": {"methods": {}}}}, "outlier threshold 'soon'"),
        (
            {**good, "methods": {"nearest": {"n": 1, "mean_time_s": 10.0, "end_reasons": {"lost": 1}}}},
            "end_reasons must be one of explored, unreachable, time_cap, failed, got 'lost'",
        ),
    ]
    for data, needle in bad_cases:
        with pytest.raises(ConfigError, match=needle):
            ExperimentSummary.from_json(data)
    (tmp_path / "summary.json").write_text("{not json")
    with pytest.raises(ConfigError, match="is not JSON"):
        ExperimentSummary.load(tmp_path)
    with pytest.raises(ConfigError, match="no experiment summary"):
        ExperimentSummary.load(tmp_path / "missing")


@pytest.mark.slow
def test_train_writes_a_model_that_learned_names(tmp_path: Path) -> None:
    config = frontier_rl.TrainConfig(
        model=4,
        timesteps=32,
        n_envs=1,
        eval_every=0,
        checkpoint_every=0,
        n_steps=8,
        max_decisions=16,
        sim=replace(SimConfig(), max_sim_time=60.0),
    )
    model = frontier_rl.train(config, tmp_path / "run")
    assert model == tmp_path / "run" / "model.zip" and model.is_file()
    result = frontier_rl.explore("office", f"learned:{model}", config=SHORT)
    assert result.decisions > 0
