"""How episodes ended: the rows' end reason and coverage columns, their counts in ``summary.json``
and the report's Completion table."""

from __future__ import annotations

import csv
import json
from dataclasses import replace
from pathlib import Path
from typing import Any

import pytest

from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.metrics import EndReason
from frontier_rl.errors import ConfigError
from frontier_rl.evaluation.report.conclusion import conclude
from frontier_rl.evaluation.report.table import completion_table
from frontier_rl.evaluation.report.tables import report_tables
from frontier_rl.evaluation.results.episode_record import ROW_COLUMNS, EpisodeRow, EpisodeTrace
from frontier_rl.evaluation.results.summary import MethodSummary
from frontier_rl.evaluation.running.evaluate import evaluate
from frontier_rl.evaluation.running.experiment import ExperimentConfig
from frontier_rl.evaluation.statistics.analysis import end_reasons, summarise
from tests.evaluation.maps import write_slit_map

SHORT = SimConfig(max_sim_time=80.0)
METHODS = ("fixed:0.75", "nearest")


def _row(method: str, episode: int, end_reason: str | None, coverage: float, **kw: Any) -> EpisodeRow:
    """A row as ``run_job`` writes it, typed as read back."""
    row = EpisodeRow(
        method=method,
        world="office",
        episode=episode,
        seed=episode,
        start_x_m=0.0,
        start_y_m=0.0,
        start_theta_rad=0.0,
        sim_time_s=100.0 + 10 * episode,
        path_length_m=0.0,
        coverage=coverage,
        t90_s=None,
        t99_s=None,
        decisions=3,
        aborts=0,
        done=end_reason == "explored",
        truncated=end_reason == "time_cap",
        end_reason=end_reason,
        free_coverage=0.9 * coverage,
        unknown_left_m2=0.0,
        mean_weight=None,
        robots=1,
        overlap=0.0,
        wall_time_s=0.0,
    )
    return EpisodeRow.from_csv_line(replace(row, **kw).csv_line())


def test_rows_carry_the_end_reason_and_coverages_typed() -> None:
    row = _row("nearest", 0, "unreachable", 0.75, unknown_left_m2=1.25)
    assert row.end_reason == "unreachable"
    assert row.free_coverage == 0.675 and isinstance(row.free_coverage, float)
    assert row.unknown_left_m2 == 1.25 and isinstance(row.unknown_left_m2, float)
    assert _row("nearest", 0, None, 0.5).end_reason is None  # an empty field
    line = _row("nearest", 0, "time_cap", 0.5).csv_line()
    assert line.split(",")[ROW_COLUMNS.index("end_reason")] == "time_cap"
    with pytest.raises(ConfigError, match="free_coverage 'most' is not valid"):
        EpisodeRow.from_csv_line(line.replace(",0.45,", ",most,", 1))
    # an empty field only where a column may be undefined
    with pytest.raises(ConfigError, match="coverage '' is not valid"):
        EpisodeRow.from_csv_line(line.replace(",0.5,", ",,", 1))
    with pytest.raises(ConfigError, match=r"decisions '3\.5' is not valid \(expected an integer"):
        EpisodeRow.from_csv_line(line.replace(",3,", ",3.5,", 1))
    assert _row("nearest", 0, "failed", 0.5).end_reason is EndReason.FAILED
    with pytest.raises(
        ConfigError, match="end_reason must be one of explored, unreachable, time_cap, failed, got 'lost'"
    ):
        EpisodeRow.from_csv_line(line.replace(",time_cap,", ",lost,", 1))


def test_a_trace_reads_back_as_it_was_written_and_refuses_what_the_report_cannot_draw() -> None:
    trace = EpisodeTrace(
        "nearest@2",
        "office",
        1,
        (0.0, 5.0),
        (0.1, 0.9),
        aborts_by_cause={"no_path": 2},
        explorable_left_m2=0.5,
        frontiers_with_path_left=2,
        frontiers_with_path_to_space_left=1,
        explorable_given_up_m2=0.25,
        frontiers_unrevealable_left=1,
        robot_path_lengths_m=(3.0, 4.0),
        robot_coverage=(0.5, 0.6),
        failed_at_s=(None, 4.5),
    )
    assert EpisodeTrace.from_json(json.loads(json.dumps(trace.to_json()))) == trace
    assert "robot_coverage" not in EpisodeTrace("nearest", "office", 0, (0.0,), (1.0,)).to_json()
    for change, needle in (
        ({"coverage": []}, "must be lists of one length, not empty"),
        ({"weight_t": [1.0]}, "weight_t and weight must be lists of one length"),
        ({"coverage": [0.1, float("inf")]}, "must hold finite numbers"),
        ({"episode": 1.0}, "episode must be a whole number"),
        ({"robot_coverage": [0.5, None]}, "robot_coverage must be a list of finite numbers"),
        ({"aborts_by_cause": {"no_path": "2"}}, "aborts_by_cause must map causes to whole numbers"),
        ({"aborts_by_cause": {"stuck": 2}}, "a cause of aborts_by_cause must be one of not_planned, no_progress"),
    ):
        with pytest.raises(ConfigError, match=needle):
            EpisodeTrace.from_json(trace.to_json() | change)


def test_end_reasons_count_every_reason() -> None:
    rows = [_row("nearest", i, r, 1.0) for i, r in enumerate(["explored", "time_cap", "failed", "explored", None])]
    assert end_reasons(rows) == {"explored": 2, "unreachable": 0, "time_cap": 1, "failed": 1}
    assert list(end_reasons([])) == ["explored", "unreachable", "time_cap"]


def test_summary_counts_end_reasons_and_coverage_per_method() -> None:
    config = ExperimentConfig(methods=METHODS, worlds=("office",), episodes=3, sim=SHORT)
    ends = {"fixed:0.75": ("explored", "unreachable", "time_cap"), "nearest": ("explored", "explored", "unreachable")}
    rows = {}
    for method, reasons in ends.items():
        for episode, reason in enumerate(reasons):
            coverage = 1.0 if reason == "explored" else 0.5 + 0.1 * episode
            left = 0.0 if reason == "explored" else 2.0 + episode
            rows[(method, "office", episode)] = _row(method, episode, reason, coverage, unknown_left_m2=left)
    summary = summarise(rows, config)
    methods = summary.methods
    fixed, nearest = methods["fixed:0.75"], methods["nearest"]
    assert fixed.end_reasons == {"explored": 1, "unreachable": 1, "time_cap": 1}
    assert nearest.end_reasons == {"explored": 2, "unreachable": 1, "time_cap": 0}
    assert fixed.episodes_done == 1 and nearest.episodes_done == 2
    assert fixed.mean_coverage == pytest.approx((1.0 + 0.6 + 0.7) / 3)
    assert fixed.min_coverage == pytest.approx(0.6) and nearest.min_coverage == pytest.approx(0.7)
    assert fixed.mean_free_coverage == pytest.approx(0.9 * (1.0 + 0.6 + 0.7) / 3)
    assert fixed.mean_unknown_left_m2 == pytest.approx((3.0 + 4.0) / 3)
    assert nearest.mean_unknown_left_m2 == pytest.approx(4.0 / 3)
    tables = {t.title: t for t in report_tables(summary, config)}
    assert tables["Completion"].rows[1][:5] == ["nearest", "3", "2", "1", "0"]
    # only the episode cut at the cap is named as such, not the unreachable one
    assert tables["Exploration time, all episodes"].note.endswith("(their time counts as the cap): fixed:0.75 1.")


def test_a_team_whose_robots_all_failed_has_no_time_to_compare() -> None:
    """Its time (when the last robot stopped, 60 s) counted as its time to explore: the report named a
    team whose robots all failed the fastest method, "86 % less time, significant"."""
    methods = ("nearest", "nearest@2:coordinated", "nearest@3:coordinated")
    config = ExperimentConfig(methods=methods, worlds=("office",), episodes=3, baseline="nearest", sim=SHORT)
    rows = {}
    for episode in range(3):
        rows[("nearest", "office", episode)] = _row("nearest", episode, "explored", 1.0, sim_time_s=400.0 + episode)
        for method in methods[1:]:
            failed = method.endswith("@2:coordinated") or episode == 0
            end, time = ("failed", 60.0) if failed else ("explored", 300.0 + 7 * episode)
            rows[(method, "office", episode)] = _row(method, episode, end, 0.5 if failed else 1.0, sim_time_s=time)
    summary = summarise(rows, config)
    all_failed, one_failed = summary.methods["nearest@2:coordinated"], summary.methods["nearest@3:coordinated"]
    assert all_failed.n == 0 and all_failed.mean_time_s is None and all_failed.end_reasons["failed"] == 3
    assert one_failed.n == 2 and one_failed.mean_time_s == pytest.approx((307.0 + 314.0) / 2)
    assert one_failed.mean_diff_s == pytest.approx((401.0 - 307.0 + 402.0 - 314.0) / 2)  # the pairs it has
    assert one_failed.median_time_s == pytest.approx(310.5)
    assert [p.robots for p in summary.teams] == [1, 3]  # no point for a team size with no time
    labels = {m: m for m in methods}
    assert conclude(summary, labels).best == "nearest@3:coordinated"
    only_failed = ExperimentConfig(methods=methods[:2], worlds=("office",), episodes=3, baseline="nearest", sim=SHORT)
    alone = summarise({k: v for k, v in rows.items() if k[0] in methods[:2]}, only_failed)
    assert conclude(alone, labels).headline.startswith("No method has an exploration time to compare")


def test_the_completion_table_lays_out_the_counts() -> None:
    entry = MethodSummary(
        4, 300.0, mean_coverage=0.8125, min_coverage=0.5, mean_free_coverage=0.75, mean_unknown_left_m2=1.5
    )
    entries = {
        "fixed:0.75@2": replace(entry, end_reasons=dict(zip(EndReason, (1, 1, 1, 1), strict=True))),
        "nearest": replace(entry, end_reasons=dict(zip(EndReason, (3, 0, 1), strict=False))),
    }
    table = completion_table(entries, {"fixed:0.75@2": "fixed:0.75 ×2", "nearest": "nearest"})
    assert table.title == "Completion"
    assert table.header == ("method", "episodes", "explored", "unreachable", "time cap", "failed", "mean coverage",
                            "min coverage", "free coverage", "unknown left (m²)")  # fmt: skip
    assert table.rows == [
        ["fixed:0.75 ×2", "4", "1", "1", "1", "1", "81.25 %", "50.00 %", "75.00 %", "1.50"],
        ["nearest", "4", "3", "0", "1", "0", "81.25 %", "50.00 %", "75.00 %", "1.50"],
    ]


@pytest.fixture(scope="module")
def mixed_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Two methods on a map they cannot map whole (a slit too narrow for the robot: its episodes end
    before the cap) and on the office, cut at 80 s."""
    folder = tmp_path_factory.mktemp("mixed")
    config = ExperimentConfig(METHODS, (str(write_slit_map(folder)), "office"), episodes=2, sim=SHORT)
    evaluate(config, folder / "exp", backend="serial", progress=False, command="test")
    return folder / "exp"


def test_an_experiment_counts_how_its_episodes_ended(mixed_run: Path) -> None:
    with (mixed_run / "episodes.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    slit = [r for r in rows if r["world"].endswith("slit.yaml")]
    office = [r for r in rows if r["world"] == "office"]
    assert len(slit) == len(office) == 4
    assert all(r["end_reason"] in ("explored", "unreachable") and r["truncated"] == "False" for r in slit)
    assert all(float(r["free_coverage"]) < float(r["coverage"]) for r in slit)  # the room behind the slit
    assert all(r["end_reason"] == "time_cap" and r["truncated"] == "True" for r in office)
    assert all(r["done"] == str(r["end_reason"] == "explored") for r in rows)
    summary = json.loads((mixed_run / "summary.json").read_text())
    for method in METHODS:
        entry = summary["methods"][method]
        own = [r for r in rows if r["method"] == method]
        counted = {reason: sum(r["end_reason"] == reason for r in own) for reason in ("explored", "unreachable")}
        assert entry["end_reasons"] == counted | {"time_cap": 2}
        assert entry["episodes_done"] == counted["explored"]
        assert entry["min_coverage"] == min(float(r["coverage"]) for r in own)
        assert entry["mean_unknown_left_m2"] == pytest.approx(sum(float(r["unknown_left_m2"]) for r in own) / 4)
        office_entry = summary["per_world"]["office"]["methods"][method]
        assert office_entry["end_reasons"] == {"explored": 0, "unreachable": 0, "time_cap": 2}


def test_the_report_shows_the_completion_table(mixed_run: Path) -> None:
    summary = json.loads((mixed_run / "summary.json").read_text())
    markdown = (mixed_run / "report.md").read_text()
    completion = markdown.split("**Completion**", 1)[1]
    for method in METHODS:
        e = summary["methods"][method]
        counts = " | ".join(str(e["end_reasons"][r]) for r in ("explored", "unreachable", "time_cap"))
        cells = f"| {method} | 4 | {counts} | {100 * e['mean_coverage']:.2f} % | {100 * e['min_coverage']:.2f} % |"
        assert cells in completion
    # episodes not done need not be capped: only the capped ones are named as cut at the cap
    assert "(their time counts as the cap): fixed:0.75 2, nearest 2." in markdown
    assert "<caption>Completion</caption>" in (mixed_run / "report.html").read_text()


def test_results_of_another_version_are_refused(mixed_run: Path, tmp_path: Path) -> None:
    out = tmp_path / "old"
    out.mkdir()
    for name in ("experiment.json", "traces.jsonl"):
        (out / name).write_bytes((mixed_run / name).read_bytes())
    old_header = ",".join(c for c in ROW_COLUMNS if c not in ("end_reason", "free_coverage", "unknown_left_m2"))
    (out / "episodes.csv").write_text(old_header + "\n")
    config = ExperimentConfig(METHODS, tuple(json.loads((mixed_run / "summary.json").read_text())["worlds"]),
                              episodes=2, sim=SHORT)  # fmt: skip
    with pytest.raises(ConfigError, match="columns of another version"):
        evaluate(config, out, backend="serial", progress=False)
