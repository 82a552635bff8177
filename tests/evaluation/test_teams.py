"""``evaluate`` with teams: method syntax, validation, rows, and the report's team figures."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from frontier_rl.cli import app
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.errors import ConfigError
from frontier_rl.evaluation.running.evaluate import evaluate
from frontier_rl.evaluation.running.experiment import ExperimentConfig
from frontier_rl.evaluation.running.fingerprints import identity
from frontier_rl.evaluation.running.methods import team_methods
from frontier_rl.evaluation.statistics.analysis import team_scaling
from frontier_rl.swarm import Failure, Strategy, TeamMethod
from frontier_rl.swarm.config import one_robot_methods

pytestmark = pytest.mark.slow  # team experiments

SHORT = SimConfig(max_sim_time=120.0)
runner = CliRunner()


def _config(methods: tuple[str, ...], **kw: object) -> ExperimentConfig:
    return ExperimentConfig(methods=methods, worlds=("office",), episodes=2, sim=SHORT, **kw)  # type: ignore[arg-type]


def test_the_same_failures_in_another_order_are_the_same_experiment() -> None:
    """A resume refused the folder of ``--fail 0@5 --fail 1@5`` when given ``--fail 1@5 --fail 0@5``."""
    given = (Failure(2, 5.0), Failure(None, None), Failure(0, 7.0), Failure(None, 3.0))
    configs = [_config(("fixed:0.75", "nearest@4"), failures=order) for order in (given, given[::-1])]
    assert configs[0] == configs[1]
    assert [str(f) for f in configs[0].failures] == ["0@7", "2@5", "random@3", "random@random"]


def test_each_method_is_parsed_once_and_its_jobs_carry_it(monkeypatch: pytest.MonkeyPatch) -> None:
    parsed: list[str] = []
    parse = TeamMethod.parse.__func__  # type: ignore[attr-defined]

    def counting(cls: type[TeamMethod], method: str) -> TeamMethod:
        parsed.append(method)
        return parse(cls, method)  # type: ignore[no-any-return]

    monkeypatch.setattr(TeamMethod, "parse", classmethod(counting))
    config = _config(("fixed:0.75", "nearest@2:coordinated"))
    jobs, _ = config.jobs(), identity(config)
    assert {config.team_for(m) is not None for m in config.methods} == {False, True}
    assert sorted(parsed) == ["fixed:0.75", "nearest@2:coordinated"]
    assert {job.method: job.team_method for job in jobs} == {
        "fixed:0.75": TeamMethod.parse("fixed:0.75"),
        "nearest@2:coordinated": TeamMethod(TeamMethod.parse("nearest").policy, 2, Strategy.COORDINATED),
    }


def test_team_methods_expand_every_size_and_strategy() -> None:
    out = team_methods(["fixed:0.75", "nearest@3"], [1, 2], [Strategy.UNCOORDINATED, Strategy.COORDINATED])
    assert out == ["fixed:0.75", "fixed:0.75@2", "fixed:0.75@2:coordinated", "nearest@3"]
    assert str(TeamMethod.parse("nearest@2:uncoordinated")) == "nearest@2"
    assert str(TeamMethod.parse("nearest@2:Rendezvous")) == "nearest@2:rendezvous"  # as --strategy takes it
    with pytest.raises(ConfigError, match="'nearest@2@3' names two team sizes"):  # not "unknown policy 'nearest@2'"
        TeamMethod.parse("nearest@2@3")
    assert str(TeamMethod.parse("learned:runs/a@2.zip@3").policy) == "learned:runs/a@2.zip"  # an @ in a path


@pytest.mark.parametrize(
    ("methods", "kw", "needle"),
    [
        (("fixed:0.75", "fixed:0.75@9"), {}, "1 to 8"),
        (("fixed:0.75", "oracle@2"), {}, "oracle"),
        (("fixed:0.75", "nearest"), {"failures": (Failure(0, 10.0),)}, "team methods"),
        (("fixed:0.75", "nearest@2"), {"failures": (Failure(2, 10.0),)}, "robot 2"),
        (("fixed:0.75", "nearest@2", "nearest@2:uncoordinated"), {}, "twice"),
        (("fixed:0.75", "nearest@2:swarm"), {}, "swarm"),
    ],
)
def test_bad_team_experiments_are_refused(methods: tuple[str, ...], kw: dict[str, object], needle: str) -> None:
    with pytest.raises(ConfigError, match=needle):
        _config(methods, **kw)


def test_a_team_is_compared_with_its_policy_alone_however_the_policy_is_written() -> None:
    """``fixed:0.50@2`` and ``fixed:0.5@4`` are teams of ``fixed:0.5``: one line, which the one
    robot starts (the line had no one-robot point when the texts differed)."""
    methods = ("fixed:0.5", "fixed:0.50@2", "fixed:0.5@4")
    times = {"fixed:0.5": [100.0, 120.0], "fixed:0.50@2": [60.0, 70.0], "fixed:0.5@4": [40.0, 50.0]}
    points = team_scaling(times, methods)
    assert [(p.policy, p.robots, p.method, p.mean_time_s) for p in points] == [
        ("fixed:0.5", 1, "fixed:0.5", 110.0),
        ("fixed:0.5", 2, "fixed:0.50@2", 65.0),
        ("fixed:0.5", 4, "fixed:0.5@4", 45.0),
    ]
    assert one_robot_methods(("nearest@2", "fixed:0.750", "tour")) == {"fixed:0.75": "fixed:0.750", "tour:10": "tour"}


def test_team_settings_are_part_of_the_identity() -> None:
    plain = identity(_config(("fixed:0.75", "nearest@2")))
    assert plain.team is None and "team" not in plain.to_json()  # results folders of single robots keep matching
    failing = identity(_config(("fixed:0.75", "nearest@2"), failures=(Failure(1, 30.0),), comm_range=3.0))
    assert failing.to_json()["team"] == {"comm_range": 3.0, "failures": ["1@30"]}


def test_a_team_experiment_reports_time_against_team_size(tmp_path: Path) -> None:
    config = _config(("fixed:0.75", "fixed:0.75@2:coordinated", "fixed:0.75@3:coordinated"),
                     failures=(Failure(1, 30.0),))  # fmt: skip
    report = evaluate(config, tmp_path, backend="serial", progress=False)
    with (tmp_path / "episodes.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    assert {(r["method"], r["robots"]) for r in rows} == {
        ("fixed:0.75", "1"), ("fixed:0.75@2:coordinated", "2"), ("fixed:0.75@3:coordinated", "3")
    }  # fmt: skip
    assert all(0.0 <= float(r["overlap"]) <= 1.0 for r in rows)
    traces = [json.loads(line) for line in (tmp_path / "traces.jsonl").read_text().splitlines()]
    teams = [t for t in traces if "@" in t["method"]]
    assert all(len(t["robot_coverage"]) == TeamMethod.parse(t["method"]).robots for t in teams)
    assert all(t["failed_at_s"][1] is not None and t["failed_at_s"][1] >= 30.0 for t in teams)
    summary = json.loads((tmp_path / "summary.json").read_text())
    line = summary["teams"]["fixed:0.75"]["coordinated"]
    assert list(line) == ["1", "2", "3"] and line["2"]["method"] == "fixed:0.75@2:coordinated"
    assert summary["methods"]["fixed:0.75@3:coordinated"]["robots"] == 3
    text = report.read_text()
    assert "fixed:0.75 ×3 coordinated" in text and "speed-up over 1 robot" in text and "teams.png" in text
    assert (tmp_path / "teams.png").stat().st_size > 0


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["--robots", "1,x"], "1,x"),
        (["--robots", "9"], "9"),
        (["--robots", "2", "--strategy", "swarm"], "swarm"),
        (["--robots", "2", "--comm-range", "-2"], "-2"),
        (["--robots", "2", "--fail", "3@10"], "robot 3"),
        (["--robots", "1,2", "--strategy", ""], "--strategy"),  # ran uncoordinated teams, unasked
    ],
)
def test_bad_team_options_are_one_line(tmp_path: Path, args: list[str], needle: str) -> None:
    result = runner.invoke(app, ["evaluate", "--methods", "nearest", "--out", str(tmp_path / "r"), *args])
    assert result.exit_code == 2
    lines = [line for line in result.output.splitlines() if line.strip()]
    assert len(lines) == 1 and needle in lines[0], result.output
    assert not (tmp_path / "r").exists()


def test_a_rerun_with_fewer_episodes_reports_its_own_team_episodes(tmp_path: Path) -> None:
    """The folder keeps the traces of a first run's second episode; the report of a rerun with one
    episode counts only that one (the Teams table's robots failed and coverage per robot)."""
    methods = ("fixed:0.75", "fixed:0.75@2")
    evaluate(_config(methods), tmp_path, backend="serial", progress=False)
    report = evaluate(
        ExperimentConfig(methods=methods, worlds=("office",), episodes=1, sim=SHORT),
        tmp_path,
        backend="serial",
        progress=False,
    )
    team_row = "| fixed:0.75 ×2 uncoordinated | 2 |"
    row = next(line for line in report.read_text().splitlines() if line.startswith(team_row))
    assert row.endswith("| 0 in 1 episodes |"), row
