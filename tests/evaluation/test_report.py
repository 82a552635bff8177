"""The report's reading aids: the generated conclusion (best method, saving, CI, p and Holm's p,
oracle ratio, how episodes ended), the methods table, outlier tables only where an episode was
left out, and a page that is one self-contained file."""

from __future__ import annotations

import base64
import io
import json
import re
from pathlib import Path

import pytest
from PIL import Image

from frontier_rl.core.mapping.mapper import MapperConfig
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.evaluation.report.conclusion import conclude
from frontier_rl.evaluation.report.method_notes import describe_method
from frontier_rl.evaluation.report.plots import coverage_plot
from frontier_rl.evaluation.report.table import short_labels
from frontier_rl.evaluation.report.tables import outlier_note, outlier_tables, time_tables
from frontier_rl.evaluation.results.episode_record import EpisodeTrace
from frontier_rl.evaluation.results.summary import ExperimentSummary
from frontier_rl.evaluation.running.evaluate import evaluate
from frontier_rl.evaluation.running.experiment import ExperimentConfig
from frontier_rl.evaluation.statistics.analysis import summarise
from frontier_rl.policies import POLICY_NAMES
from frontier_rl.rl.config import TrainConfig
from tests.evaluation.test_completion import _row

METHODS = ("fixed:0.75", "nearest", "largest", "oracle")


def _summary(
    times: dict[str, list[float]],
    ends: dict[str, list[str]] | None = None,
    outliers: tuple[float, ...] = (1000.0, 2000.0),
    worlds: tuple[str, ...] = ("office",),
) -> tuple[ExperimentSummary, ExperimentConfig]:
    episodes = len(times["fixed:0.75"]) // len(worlds)
    config = ExperimentConfig(methods=tuple(times), worlds=worlds, episodes=episodes)
    rows = {}
    for method, values in times.items():
        for i, value in enumerate(values):  # in the order of paired_times: by episode, then world
            reason = (ends or {}).get(method, ["explored"] * len(values))[i]
            episode, world = divmod(i, len(worlds))
            rows[(method, worlds[world], episode)] = _row(method, episode, reason, 1.0, sim_time_s=value)
    return summarise(rows, config, outliers), config


BASE = [400.0, 420.0, 450.0, 500.0, 380.0, 410.0]


def test_the_conclusion_names_the_fastest_method_with_its_statistics() -> None:
    times = {
        "fixed:0.75": BASE,
        "nearest": [t - 30 + 3 * i for i, t in enumerate(BASE)],
        "largest": [t + 40 for t in BASE],
        "oracle": [t - 80 for t in BASE],
    }
    summary, config = _summary(times)
    best = summary.methods["nearest"]
    conclusion = conclude(summary, short_labels(config.methods))
    assert conclusion.best == "nearest"
    low, high = best.ci95_s
    assert conclusion.headline == (
        f"nearest explored fastest: {best.mean_time_s:.1f} s on average against {sum(BASE) / 6:.1f} s for the "
        f"baseline fixed:0.75, {best.reduction_pct:.1f} % less time (mean saving {best.mean_diff_s:.1f} s, "
        f"95 % CI {low:.1f} to {high:.1f} s; one-tailed paired t-test p = {best.p_one_tailed:.2g}, p Holm = "
        f"{best.p_holm:.2g}; significant at the 5 % level), {best.oracle_ratio:.2f} × the time of the oracle "
        "that knows the map."
    )
    # two methods tested (the oracle is a reference): Holm doubles the smaller p, keeps the larger
    assert best.p_holm == pytest.approx(min(1.0, 2 * best.p_one_tailed))
    assert summary.methods["oracle"].p_holm is None and summary.methods["fixed:0.75"].p_holm is None
    assert any("2 methods were tested" in d for d in conclusion.details)
    assert conclusion.details[-1] == "All 24 episodes ended with the map explored."


def test_a_method_as_fast_as_the_baseline_in_every_episode_counts_in_holms_family() -> None:
    # "largest" has no defined p (no difference at all), but it was tested: Holm's m is 2
    times = {"fixed:0.75": BASE, "nearest": [t - 30 + 3 * i for i, t in enumerate(BASE)], "largest": BASE}
    summary, _ = _summary(times)
    nearest, largest = summary.methods["nearest"], summary.methods["largest"]
    assert largest.p_one_tailed is None and largest.p_holm is None
    assert nearest.p_holm == pytest.approx(min(1.0, 2 * nearest.p_one_tailed))
    assert summary.methods["largest"].std_time_s == pytest.approx(summary.methods["fixed:0.75"].std_time_s)


def test_the_conclusion_says_when_nothing_beat_the_baseline_and_names_unfinished_episodes() -> None:
    times = {"fixed:0.75": BASE, "largest": [t + 5 for t in BASE]}
    ends = {"fixed:0.75": ["explored"] * 6, "largest": ["explored"] * 4 + ["time_cap", "unreachable"]}
    summary, config = _summary(times, ends)
    conclusion = conclude(summary, short_labels(config.methods))
    assert conclusion.headline.startswith("No method was faster than the baseline fixed:0.75 (")
    assert "the fastest, largest, took" in conclusion.headline and "% more time" in conclusion.headline
    assert not any("tested against" in d for d in conclusion.details)  # one method: no multiple comparisons
    assert conclusion.details[-1] == (
        "10 of 12 episodes ended with the map explored; the others: largest 1 unreachable, 1 time cap (time cap: cut "
        "at the sim-time cap, with the cap as its time (the default cap is about three times what the fastest method "
        "takes on large floors: a policy that meets it wanders); unreachable: frontiers were left, none of them "
        "reachable for a robot of this size or each given up after its tries)."
    )


def test_the_summary_file_reads_back_as_the_summary_it_was_written_from() -> None:
    """``to_json`` and ``from_json`` are one codec: every field of every part survives, per world,
    outlier cuts, team points and undefined values (the oracle's Holm p, a p of equal times)."""
    times = {
        "fixed:0.75": BASE,
        "nearest": [t - 30 + 3 * i for i, t in enumerate(BASE)],
        "largest": BASE,
        "nearest@2": [t / 2 for t in BASE],
        "nearest@3:coordinated": [t / 3 for t in BASE],
        "oracle": [t - 80 for t in BASE],
    }
    summary, _ = _summary(times, outliers=(1000.0, 430.0), worlds=("office", "rooms"))
    assert summary.per_world and summary.teams and len(summary.outliers) == 2
    assert [(p.policy, p.strategy, p.robots) for p in summary.teams] == [
        ("nearest", "uncoordinated", 1),
        ("nearest", "uncoordinated", 2),
        ("nearest", "coordinated", 1),
        ("nearest", "coordinated", 3),
    ]
    text = json.dumps(summary.to_json(), indent=1)
    assert ExperimentSummary.from_json(json.loads(text)) == summary


def test_outlier_tables_only_when_an_episode_was_left_out() -> None:
    summary, config = _summary({"fixed:0.75": BASE, "nearest": [*BASE[:5], 1500.0]})
    labels = short_labels(config.methods)
    tables = outlier_tables(summary, config, labels)
    assert [t.title for t in tables] == ["Without episodes above 1000 s"]  # 2000 s left nothing out
    assert tables[0].rows[1][-1] == "1"
    assert outlier_note(summary).startswith("No episode took longer than 2000 s ")
    clean, _ = _summary({"fixed:0.75": BASE, "nearest": BASE})
    assert outlier_tables(clean, config, labels) == []
    assert "1000 s or 2000 s (the thesis's outlier thresholds)" in outlier_note(clean)
    own, _ = _summary({"fixed:0.75": BASE, "nearest": BASE}, outliers=(900.0,))
    assert outlier_note(own).startswith("No episode took longer than 900 s, so")  # a user's threshold, not the thesis's
    assert [t.title for t in time_tables(clean, config)] == ["Exploration time, all episodes"]


def test_the_main_table_gives_sd_and_holm_beside_the_raw_values() -> None:
    summary, config = _summary({"fixed:0.75": BASE, "nearest": BASE[::-1], "largest": [t + 1 for t in BASE]})
    main = time_tables(summary, config)[0]
    header = list(main.header)
    assert header[header.index("variance (s²)") + 1] == "sd (s)"
    assert header[header.index("p one-tailed") + 1] == "p Holm"
    row = main.rows[2]  # largest
    assert row[header.index("sd (s)")] == f"{summary.methods['largest'].std_time_s:.1f}"


@pytest.mark.parametrize(
    ("method", "parts"),
    [
        ("fixed:0.75", ["eq. 3.1", "w = 0.75 (the thesis's baseline)"]),
        ("fixed:0.9", ["w = 0.9"]),
        ("nearest", ["nearest frontier"]),
        ("oracle", ["Knows the true map"]),
        ("nearest@3:coordinated", ["A team of 3 robots", "strategy = coordinated"]),
        (
            "learned:models/model5.zip",
            ["Model 5 (map + per-frontier", "sha256 ", "--model 5 --worlds office --timesteps 60000"],
        ),
        ("learned:README.md", ["could not be read", "not a frontier_rl model"]),
        ("tour", ["shortest open tour", "10 stops"]),
        ("tour:13", ["Held-Karp", "13 stops"]),
        ("learned:models/model7.zip", ["Model 7", "--model 7 --worlds office --timesteps 60000"]),
    ],
)
def test_every_method_is_described(method: str, parts: list[str]) -> None:
    note = describe_method(method, Path(__file__).parents[2])
    text = f"{note.description} {note.parameters}"
    for part in parts:
        assert part in text, text


@pytest.mark.parametrize("name", [name for name in POLICY_NAMES if not name.startswith(("fixed", "learned"))])
def test_every_policy_name_has_its_own_description(name: str) -> None:
    assert describe_method(name.replace(":N", ":4")).description != describe_method("no-such-policy").description


def test_the_training_command_lists_what_differs_from_the_defaults() -> None:
    config = TrainConfig(model=5, worlds="office,rooms", timesteps=5000, algo="ppo", gamma=0.9, seed=3, vf_coef=0.4)
    assert config.command() == (
        "frontier-rl train --model 5 --worlds office,rooms --timesteps 5000 --algo ppo --gamma 0.9 --seed 3"
        " (also vf_coef=0.4)"
    )


def test_the_training_command_names_each_simulator_setting_that_differs() -> None:
    sim = SimConfig(mapper=MapperConfig(hit=0.85, miss=-0.5), max_sim_time=600.0)
    assert TrainConfig(model=7, sim=sim).command() == (
        "frontier-rl train --model 7 --worlds office --timesteps 100000"
        " (also sim.mapper.hit=0.85, sim.mapper.miss=-0.5, sim.max_sim_time=600.0)"
    )


def test_the_command_options_are_the_train_commands() -> None:
    import inspect

    from frontier_rl.cli.train import train
    from frontier_rl.rl.config import _CLI_OPTIONS

    parameters = inspect.signature(train).parameters
    assert set(_CLI_OPTIONS) == set(parameters) - {"out", "resume", "progress", "config"}
    for name in _CLI_OPTIONS:  # the same defaults, so a default left out of the command is the command's
        assert parameters[name].default == getattr(TrainConfig(), name), name


@pytest.fixture(scope="module")
def small_report(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("report") / "exp"
    config = ExperimentConfig(methods=("fixed:0.75", "nearest", "oracle"), worlds=("office", "rooms"), episodes=2,
                              sim=SimConfig(max_sim_time=120.0))  # fmt: skip
    evaluate(config, out, backend="serial", progress=False, command="test", pictures=1)
    return out


def test_the_page_is_one_self_contained_file(small_report: Path) -> None:
    page = (small_report / "report.html").read_text()
    assert '<meta name="viewport" content="width=device-width, initial-scale=1">' in page
    for forbidden in ("<script", "<link", "@import", "url(", "<iframe", "<object"):
        assert forbidden not in page.lower(), forbidden
    sources = re.findall(r'src="([^"]*)"', page)
    assert len(sources) == 3 + 3  # three charts, and the first office episode of each method
    for source in sources:
        kind, data = re.fullmatch(r"data:image/(png|gif);base64,([A-Za-z0-9+/=]+)", source).groups()  # type: ignore[union-attr]
        with Image.open(io.BytesIO(base64.b64decode(data))) as image:
            image.load()
            assert image.format.lower() == kind and image.width > 0  # type: ignore[union-attr]
    assert not re.search(r"(href|src)=\"(https?:|//)", page)
    assert 'id="conclusion"' in page and "<h2>Methods</h2>" in page and "<h2>Runs</h2>" in page


def test_the_runs_drawn_are_the_episodes_of_the_rows(small_report: Path) -> None:
    import csv

    with (small_report / "episodes.csv").open() as handle:
        rows = {(r["method"], r["world"], r["episode"]): r for r in csv.DictReader(handle)}
    page = (small_report / "report.html").read_text()
    for method in ("fixed:0.75", "nearest", "oracle"):
        row = rows[(method, "office", "0")]
        assert (small_report / "pictures" / f"office_{method.replace(':', '_')}.png").is_file()
        assert f"office / {method}.</b> Episode 0 (seed 0): {float(row['sim_time_s']):.1f} s" in page
    assert not list((small_report / "pictures").glob("rooms_*"))  # --pictures 1: the first world only
    markdown = (small_report / "report.md").read_text()
    assert "![office / nearest](pictures/office_nearest.png)" in markdown


def test_a_coverage_plot_of_episodes_that_ended_at_once_draws_without_a_warning(tmp_path: Path) -> None:
    """``--max-time 1e-9``: every trace ends at t = 0 (matplotlib warned of a singular x range)."""
    traces = {"nearest": [EpisodeTrace("nearest", "office", 0, coverage_t=(0.0,), coverage=(0.07,))]}
    assert coverage_plot(traces, tmp_path / "coverage.png").exists()  # warnings are errors here


def test_a_policy_of_yours_that_reports_its_weight_has_a_weight_plot(tmp_path: Path) -> None:
    """Only learned models had one, though the guide says ``weight`` is for the reports' weight plots."""
    policy = tmp_path / "mine.py"
    policy.write_text(
        "from frontier_rl import Ranking\n"
        "from frontier_rl.core.frontiers.ranking import rank, weighted_cost\n"
        "class Adaptive:\n"
        "    name = 'adaptive'\n"
        "    def rank(self, context, rng):\n"
        "        weight = 0.9 if len(context.frontiers) > 3 else 0.5\n"
        "        return Ranking(rank(weighted_cost(context.frontiers, weight)), weight)\n"
    )
    out = tmp_path / "exp"
    config = ExperimentConfig(methods=(f"{policy}:Adaptive", "fixed:0.75"), worlds=("office",), episodes=1,
                              baseline="fixed:0.75", sim=SimConfig(max_sim_time=60.0))  # fmt: skip
    evaluate(config, out, backend="serial", progress=False, command="test")
    assert (out / "weights.png").is_file()
    assert "Weight chosen over time" in (out / "report.md").read_text()
