"""The weight-sweep script behind the README's analysis of model 4."""

from __future__ import annotations

import copy
import importlib.util
import json
import shutil
import subprocess
import sys
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import run_episode
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.catalog import generate_world
from frontier_rl.policies import make_policy

pytestmark = pytest.mark.slow  # the experiment scripts, run whole

SCRIPT = Path(__file__).resolve().parents[1] / "experiments" / "weight_sweep.py"


def test_sweep_analysis_matches_the_rows(tmp_path: Path) -> None:
    out = tmp_path / "sweep"
    args = [sys.executable, str(SCRIPT), "--methods", "nearest", "--episodes", "2", "--seed", "5", "--max-time", "60",
            "--workers", "2", "--out", str(out)]  # fmt: skip
    subprocess.run(args, capture_output=True, text=True, check=True, timeout=300)
    summary = json.loads((out / "summary.json").read_text())
    assert len(summary["methods"]) == 23  # fixed:0.75 first, nearest, the other 20 weights, the oracle
    sweep = summary["sweep"]
    best = f"{sweep['best_weight']:.2f}"
    assert sweep["best_mean_time_s"] == summary["methods"][f"fixed:{best}"]["mean_time_s"]
    assert sum(sweep["per_world_best_weight_counts"].values()) == 2
    assert sweep["per_world_oracle_mean_time_s"] <= sweep["best_mean_time_s"]
    assert (out / "report.html").exists()


GENERALISATION = SCRIPT.parent / "generalisation.py"


def test_generalisation_table_per_family(tmp_path: Path) -> None:
    """Two families, two episodes: one evaluate folder each, on the ``--config`` settings, and a
    table row per method."""
    out = tmp_path / "gen"
    sim = tmp_path / "sim.yaml"
    sim.write_text("mapper:\n  hit: 0.75\n  miss: -0.5\n")
    args = [sys.executable, str(GENERALISATION), "--methods", "fixed:0.75", "--episodes", "2", "--families",
            "office,rooms", "--workers", "2", "--config", str(sim), "--out", str(out)]  # fmt: skip
    run = subprocess.run(args, capture_output=True, text=True, check=True, timeout=300)
    table = json.loads((out / "generalisation.json").read_text())
    assert set(table) == {"office", "rooms"}
    for family, rows in table.items():
        assert [r["method"] for r in rows] == ["nearest", "fixed:0.75", "oracle"]
        assert rows[0]["reduction_vs_nearest_pct"] == 0.0 and rows[0]["n"] == 2
        summary = json.loads((out / family / "summary.json").read_text())
        assert rows[1]["mean_time_s"] == summary["methods"]["fixed:0.75"]["mean_time_s"]
        mapper = json.loads((out / family / "experiment.json").read_text())["sim"]["mapper"]
        assert (mapper["hit"], mapper["miss"]) == (0.75, -0.5)
        assert family in run.stdout


def test_the_real_map_experiment_runs_on_the_config_it_is_given(tmp_path: Path, real_maps: Path) -> None:
    """``experiments/real_maps.py --config``: every family's evaluation runs on those settings."""
    maps = tmp_path / "maps"
    shutil.copytree(real_maps / "lse_arena", maps / "lse_arena")
    sim = tmp_path / "sim.yaml"
    sim.write_text("mapper:\n  hit: 0.75\n  miss: -0.5\n")
    args = [sys.executable, str(SCRIPT.parent / "real_maps.py"), "--maps", str(maps), "--methods", "nearest",
            "--episodes", "1", "--dungeon", "0", "--workers", "1", "--config", str(sim),
            "--out", str(tmp_path / "out")]  # fmt: skip
    subprocess.run(args, capture_output=True, text=True, check=True, timeout=300)
    mapper = json.loads((tmp_path / "out" / "ros" / "experiment.json").read_text())["sim"]["mapper"]
    assert (mapper["hit"], mapper["miss"]) == (0.75, -0.5)
    assert "ros" in (tmp_path / "out" / "completion.md").read_text()


@pytest.mark.parametrize(("t99", "shown"), [(["100", "200"], "150"), (["100", ""], "100 (1 of 2)"), (["", ""], "—")])
def test_the_real_map_table_gives_the_time_to_99_percent_of_those_that_reached_it(t99: list[str], shown: str) -> None:
    real_maps = _script("real_maps")
    rows = [{"world": "w", "method": "nearest", "end_reason": "explored", "coverage": "1.0", "unknown_left_m2": "0",
             "sim_time_s": "300", "t99_s": t} for t in t99]  # fmt: skip
    header, _, line = real_maps.family_table(rows, {"w": "ros"}).splitlines()
    assert header.endswith("| mean time (s) | mean time to 99 % (s) |")
    assert line == f"| ros | nearest | 2 | 2 | 0 | 0 | 1.000 / 1.000 | 2 / 2 | 0.00 | 300 | {shown} |"


def _script(name: str) -> Any:
    spec = importlib.util.spec_from_file_location(name, SCRIPT.parent / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # its dataclasses look their module up there
    spec.loader.exec_module(module)
    return module


def test_a_copied_simulator_replays_the_episode_exactly() -> None:
    """The headroom probe rests on this: a deep copy explores on exactly as the original would."""
    headroom = _script("weight_headroom")
    sim = ExplorationSimulator(generate_world("office", 3), rng=np.random.default_rng(3))
    for _ in range(5):
        headroom._take(sim, 0.95)
    twin = copy.deepcopy(sim)
    assert headroom.finish(twin, 0.95) == headroom.finish(sim, 0.95)
    assert np.array_equal(twin.map().data, sim.map().data)


def test_headroom_summary_counts_savings() -> None:
    headroom = _script("weight_headroom")
    probes = [
        {"end_times_s": {"0.50": 90.0, "0.95": 100.0}},
        {"end_times_s": {"0.50": 120.0, "0.95": 100.0}},
        {"end_times_s": {"0.50": 100.0, "0.95": 100.0}},
    ]
    summary = headroom.summarise(probes, 0.95)
    assert summary["share_where_another_weight_saves_time"] == 1 / 3
    assert summary["mean_saving_s"] == 10.0 / 3 and summary["max_saving_s"] == 10.0
    assert summary["best_weight_counts"] == {"0.50": 1, "0.95": 2}  # a tie goes to the constant


def test_headroom_counts_a_saving_only_beyond_the_noise() -> None:
    headroom = _script("weight_headroom")
    probes = [
        {
            "end_times_s": {},
            "repeat_end_times_s": {"0.50": [90.0, 93.0, 88.0, 91.0], "0.95": [100.0, 102.0, 99.0, 100.0]},
        },
        {"end_times_s": {}, "repeat_end_times_s": {"0.50": [90.0, 90.0, 110.0, 110.0], "0.95": [100.0] * 4}},
    ]
    for probe in probes:
        probe["end_times_s"] = {w: float(np.mean(t)) for w, t in probe["repeat_end_times_s"].items()}
    summary = headroom.summarise(probes, 0.95)
    assert summary["share_where_another_weight_saves_time"] == 0.5  # the second probe ties in the mean
    assert summary["share_with_a_saving_beyond_2_standard_errors"] == 0.5
    assert summary["mean_saving_beyond_2_standard_errors_s"] == pytest.approx(9.75 / 2)
    assert summary["noise_repeats"] == 4
    assert summary["other_decisions_tested"] == 2
    assert summary["other_decisions_faster_beyond_2_standard_errors"] == 1
    # picking by rollouts 1-2 and judging by 3-4, and back: the first probe picks 0.50 both ways
    # (10 and 9.5 s saved); the second picks 0.50 on 1-2 and loses 10 s, and the constant on 3-4
    assert summary["held_out_saving_s"] == pytest.approx((9.75 + (-10.0 + 0.0) / 2) / 2)
    assert summary["held_out_saving_standard_error_s"] == pytest.approx(abs(9.75 - -5.0) / 2)  # sd / sqrt(2)
    assert summary["expected_so_by_chance"] == pytest.approx(2 * 0.0697, abs=1e-3)  # P(t3 > 2) per decision
    assert summary["other_decisions_slower_beyond_2_standard_errors"] == 0
    one = headroom.summarise(probes[:1], 0.95)
    assert one["held_out_saving_standard_error_s"] is None  # one probe: no spread to give


def test_headroom_paired_differences_without_spread_are_no_test() -> None:
    headroom = _script("weight_headroom")
    probe = {"repeat_end_times_s": {"0.50": [90.0, 92.0], "0.75": [95.0, 97.0], "0.95": [100.0, 102.0]}}
    assert headroom._paired_t_values(probe, "0.95") == []  # differences of exactly 10 and 5: no t
    assert headroom._significant_saving(probe, "0.95") == 0.0


def test_headroom_rollouts_share_noise_streams_across_weights() -> None:
    headroom = _script("weight_headroom")
    sim = ExplorationSimulator(generate_world("office", 2), rng=np.random.default_rng(2))
    for _ in range(3):
        headroom._take(sim, 0.95)
    times = headroom._noisy_end_times(sim, 0.95, [0.9, 0.95, 0.0], 2, (2, 3))
    assert set(times) == {"0.00", "0.90", "0.95"} and all(len(t) == 2 for t in times.values())
    assert times["0.95"][0] != times["0.95"][1]  # fresh noise per repeat
    again = headroom._noisy_end_times(sim, 0.95, [0.95], 2, (2, 3))
    assert again["0.95"] == times["0.95"]  # the same streams for the same key


def test_headroom_rollouts_of_every_weight_draw_the_same_seeds(monkeypatch: pytest.MonkeyPatch) -> None:
    headroom = _script("weight_headroom")
    sim = ExplorationSimulator(generate_world("office", 2), rng=np.random.default_rng(2))
    for _ in range(3):
        headroom._take(sim, 0.95)
    seeds: dict[float, list[object]] = {}
    take = headroom._take

    def recording_take(twin: ExplorationSimulator, weight: float) -> ExplorationSimulator:
        seeds.setdefault(weight, []).append(twin.rng.bit_generator.seed_seq.entropy)
        return take(twin, weight)

    monkeypatch.setattr(headroom, "_take", recording_take)
    monkeypatch.setattr(headroom, "finish", lambda twin, constant: 0.0)  # the first decision is enough
    headroom._noisy_end_times(sim, 0.95, [0.0, 0.95], 3, (2, 3))
    assert set(seeds) == {0.0, 0.95}  # here w = 0 takes another decision, rolled out on its own
    assert seeds[0.0] == seeds[0.95] and len({str(s) for s in seeds[0.95]}) == 3  # paired, fresh per repeat


def test_teacher_summary_is_relative_to_nearest() -> None:
    teacher = _script("lookahead_teacher")
    rows = [
        {"nearest": 400.0, "greedy": 380.0, "teacher": 300.0, "oracle": 320.0},
        {"nearest": 200.0, "greedy": 220.0, "teacher": 150.0, "oracle": 160.0},
    ]
    summary = teacher.family_summary(rows)
    assert summary["nearest"] == {"mean_s": 300.0, "less_than_nearest_pct": 0.0}
    assert summary["teacher"]["mean_s"] == 225.0 and summary["teacher"]["less_than_nearest_pct"] == 25.0
    assert summary["greedy"]["less_than_nearest_pct"] == 0.0


def test_teacher_experiment_pairs_its_noise_with_run_episode() -> None:
    """Greedy and the teacher run on the sensor-noise stream that ``run_episode`` gives the
    simulator of the same seed: the first scan's map and the stream's next state are the same."""
    teacher = _script("lookahead_teacher")
    world = generate_world("rooms", 2)
    seen: list[tuple[object, ...]] = []

    def first(sim: ExplorationSimulator, *_: object) -> None:
        if not seen:
            seen.append((sim.rng.bit_generator.state, sim.map().data.tobytes()))

    run_episode(world, make_policy("nearest"), SimConfig(max_sim_time=30.0), seed=7, on_decision=first)
    ours = teacher._simulator(world, 7)
    assert seen == [(ours.rng.bit_generator.state, ours.map().data.tobytes())]
    assert teacher._simulator(world, 8).rng.bit_generator.state != seen[0][0]


def test_the_harder_survey_tabulates_causes_and_draws_the_worst(tmp_path: Path, real_maps: Path) -> None:
    """On a map given as a file (in a folder of another name): the survey calls it by its stem."""
    shutil.copytree(real_maps / "lse_arena", tmp_path / "maps" / "arena")
    out = tmp_path / "survey"
    args = [sys.executable, str(SCRIPT.parent / "harder_survey.py"), "--maps",
            str(tmp_path / "maps" / "arena" / "lse_arena.yaml"), "--methods", "nearest,tour",
            "--episodes", "2", "--workers", "1", "--out", str(out)]  # fmt: skip
    subprocess.run(args, capture_output=True, text=True, check=True, timeout=300)
    assert (out / "lse_arena" / "episodes.csv").is_file()
    survey = json.loads((out / "survey.json").read_text())
    assert [(row["map"], row["method"], row["episodes"]) for row in survey["rows"]] == [
        ("lse_arena", "nearest", 2),
        ("lse_arena", "tour", 2),
    ]
    for row in survey["rows"]:
        assert row["explored"] + row["unreachable"] + row["time_cap"] == 2
        assert set(row["aborts"]) == {"not_planned", "no_progress", "detour", "no_path"}
        assert row["explorable_left_m2"] >= 0 and 0.99 <= row["min_coverage"] <= 1
        for part in ("unreachable_with_a_path_to_space", "unreachable_with_a_path_on_map"):
            assert 0 <= row[part] <= row["unreachable_with_a_path"] <= row["unreachable"]
        assert 0.0 <= row["explorable_given_up_m2_max"] <= max(row["explorable_left_m2"], 0.0) * 2 + 0.01
    assert min(row["time_over_fastest"] for row in survey["rows"]) == 1.0
    worst = survey["worst"]
    assert len(worst) == 4 and sorted((out / w["picture"]) for w in worst) == sorted((out / "worst").glob("*.png"))
    assert [w["coverage"] for w in worst] == sorted(w["coverage"] for w in worst)
    for w in worst:
        assert sum(p["area_m2"] for p in w["unseen"]) <= w["explorable_left_m2"] + 0.01
        assert all(p["area_m2"] >= 0.25 and p["path_within_m"] > 0 for p in w["unseen"])
    assert 0.9 < survey["explorable_shares"]["lse_arena"] <= 1  # a walled arena: nearly all of it in sight
    assert "against its explorable share of" in (out / "survey.md").read_text()
    assert "episodes gave up explorable space with a path" in (out / "survey.md").read_text()
    # an episode that runs again otherwise than surveyed (the engine changed since) is not drawn
    survey_script = _script("harder_survey")
    episodes = survey_script.read_episodes(out / "lse_arena")
    changed = [replace(e, world="lse_arena", coverage=e.coverage - 0.001) for e in episodes]
    maps = {"lse_arena": str(tmp_path / "maps" / "arena" / "lse_arena.yaml")}
    with pytest.raises(SystemExit, match=r"ran again to .* not as surveyed .* run the survey again"):
        survey_script.draw_worst(changed, maps, tmp_path / "again")
    assert not list((tmp_path / "again" / "worst").glob("*.png"))


def test_the_harder_survey_names_maps_by_their_worlds_names(tmp_path: Path, real_maps: Path) -> None:
    named_maps = _script("harder_survey").named_maps
    copy = tmp_path / "lse_arena.yaml"
    for part in ("lse_arena.yaml", "lse_arena.pgm"):
        shutil.copy(real_maps / "lse_arena" / part, tmp_path / part)
    assert named_maps(["office", str(copy)]) == {"office": "office", "lse_arena": str(copy)}
    with pytest.raises(SystemExit, match="are both called 'lse_arena'"):
        named_maps(["lse_arena", str(copy)])


EXPLORER_SURVEY = SCRIPT.parent / "explorer_survey.py"


def test_explorer_survey_rows_totals_and_a_rerun_that_skips_what_it_has(tmp_path: Path) -> None:
    out = tmp_path / "explorer.jsonl"
    args = [sys.executable, str(EXPLORER_SURVEY), "--maps", "aws_small_house", "--seeds", "1", "--out", str(out)]
    run = subprocess.run(args, capture_output=True, text=True, check=True, timeout=300)
    (row,) = [json.loads(line) for line in out.read_text().splitlines()]
    assert row["map"] == "aws_small_house" and row["seed"] == 1 and row["policy"] == "nearest"
    assert row["coverage"] >= 0.99 and row["decisions"] > 10 and row["end_reason"] in ("explored", "unreachable")
    assert "1 episodes: 1 at 99 % or more" in run.stdout
    again = subprocess.run(args, capture_output=True, text=True, check=True, timeout=300)
    assert len(out.read_text().splitlines()) == 1 and "1 episodes: 1 at 99 % or more" in again.stdout
    out.write_text(out.read_text() + "{not json\n")
    damaged = subprocess.run(args, capture_output=True, text=True, timeout=300)
    assert damaged.returncode == 1 and damaged.stderr.startswith(f"error: {out}:2 is no episode"), damaged.stderr
