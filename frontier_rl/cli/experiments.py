"""``frontier-rl evaluate`` (the paired experiment) and ``frontier-rl demo`` (the compact one on the
built-in worlds), with the summary they print."""

from __future__ import annotations

import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from frontier_rl.cli.options import (
    ResolutionOption,
    SimConfigOption,
    TrustModelOption,
    WorkersOption,
    checked_comm_range,
    checked_count,
    checked_run_arguments,
    sim_config,
)
from frontier_rl.cli.output import (
    comma_list,
    friendly_errors,
    int_list,
    policy_list,
    print_line,
    print_note,
    print_table,
    print_warning,
)
from frontier_rl.core.frontiers.thesis import THESIS_BASELINE
from frontier_rl.swarm import Failure, Strategy, parse_strategy

if TYPE_CHECKING:
    from frontier_rl.evaluation.results.summary import ExperimentSummary

_INTERRUPTED = "interrupted: finished episodes are saved in {out}/; rerun the same command to resume"
MaxTimeOption = Annotated[float | None, typer.Option(help="Sim-time cap of every episode (s).")]
ProgressOption = Annotated[bool, typer.Option(help="Show a progress bar.")]
RobotsOption = Annotated[
    str, typer.Option(help="Team sizes to run every method with, e.g. 1,2,4 (a method POLICY@N runs as given).")
]
StrategyOption = Annotated[
    str, typer.Option(help="Team strategies for sizes above 1: uncoordinated, coordinated, rendezvous (a list).")
]
CommRangeOption = Annotated[
    float | None, typer.Option(help="Teams' communication range (m); default unlimited, rendezvous 2 m.")
]
FailOption = Annotated[
    list[str] | None,
    typer.Option(help="ROBOT@SECONDS: a failure in every team episode that lasts until then (repeatable)."),
]
DEMO_WORLDS = ("office", "rooms", "cluttered")
SHIPPED_MODELS = (Path("models/model4.zip"), Path("models/model5.zip"), Path("models/model7.zip"))
"""Trained models in the repository; the demo runs them too when run from the checkout."""


@friendly_errors
def demo(
    out: Annotated[Path, typer.Option(help="Folder for the report and pictures (rewritten).")] = Path("demo_output"),
    seed: Annotated[int, typer.Option(help="Seed of the first episode.")] = 0,
    episodes: Annotated[int, typer.Option(help="Episodes per world.")] = 10,
    workers: WorkersOption = None,
    max_time: MaxTimeOption = None,
    progress: ProgressOption = True,
) -> None:
    """The compact experiment, on the built-in worlds.

    The shipped models against fixed:0.75, nearest, tour and the oracle, with a report in
    OUT/experiment, and a picture of each method's first episode on each world (plus an animation of
    one)."""
    import shutil

    checked_run_arguments(seed, out)
    from frontier_rl.config_files import dump_config
    from frontier_rl.evaluation.report.run_pictures import AnimatedRun
    from frontier_rl.evaluation.results.summary import ExperimentSummary
    from frontier_rl.evaluation.running.evaluate import DEFAULT_OUTLIERS_S, checked_run
    from frontier_rl.evaluation.running.evaluate import evaluate as run_evaluation
    from frontier_rl.evaluation.running.experiment import ExperimentConfig
    from frontier_rl.evaluation.running.methods import ORACLE
    from frontier_rl.run_folders import RunKind, refuse_other_runs

    learned = [f"learned:{path}" for path in SHIPPED_MODELS if path.is_file()]
    methods = (THESIS_BASELINE, "nearest", "tour", *learned, ORACLE)
    sim = sim_config(None, max_time)
    experiment = ExperimentConfig(methods=methods, worlds=DEMO_WORLDS, episodes=episodes, seed=seed, sim=sim)
    refuse_other_runs(out, RunKind.DEMO)
    _note_missing_models()
    checked_run(experiment, "process", workers, None)  # before the last demo's results are deleted
    results = out / "experiment"
    if results.exists():  # the demo starts afresh: a retrained model must not meet its old rows
        shutil.rmtree(results)
    command = _command_line("demo")
    report = run_evaluation(
        experiment,
        results,
        "process",
        workers,
        None,
        DEFAULT_OUTLIERS_S,
        progress,
        command,
        pictures=len(DEMO_WORLDS),
        animate=AnimatedRun("office", THESIS_BASELINE),
    )
    dump_config(experiment.sim, out / "config.yaml")  # once the folder is the demo's (its experiment/)
    title = f"{episodes} episode(s) per world on {', '.join(DEMO_WORLDS)}"
    _print_summary(ExperimentSummary.load(report.parent), title, experiment.baseline)
    print_line(f"report: {report.with_suffix('.html')} (and .md); pictures of seed {seed} in {results}/pictures/")


def _note_missing_models() -> None:
    """A line on standard error naming the shipped models the working folder lacks (outside a
    checkout of the repository, all of them), which the demo leaves out."""
    missing = [str(path) for path in SHIPPED_MODELS if not path.is_file()]
    if missing:
        note = f"note: {', '.join(missing)} not found in {Path.cwd()}: the demo runs without "
        note += "them (run it in a checkout of the repository to include the shipped models)"
        print_note(note)


def _print_summary(summary: ExperimentSummary, title: str, baseline: str) -> None:
    """The main numbers of the experiment's summary as a table on the terminal."""
    from rich.table import Table

    from frontier_rl.evaluation.report.conclusion import unfinished
    from frontier_rl.evaluation.report.table import short_labels

    methods = summary.methods
    labels = short_labels(methods)
    ends = unfinished({name: e.end_reasons or {} for name, e in methods.items()}, labels)
    table = Table(title=title, caption="not explored: " + "; ".join(ends) if ends else None, caption_justify="left")
    with_oracle = any(e.oracle_ratio is not None for e in methods.values())  # none without the oracle's run
    columns = ("method", "mean time (s)", "time vs baseline", "p Holm", *(("time / oracle",) if with_oracle else ()))
    for column in (*columns, "done"):
        table.add_column(column, justify="left" if column == "method" else "right", no_wrap=column == "method")
    for name, e in methods.items():
        if name == baseline:
            change = "baseline"
        elif e.reduction_pct is None:  # no episode to compare (every one a failed team's)
            change = "n/a"
        else:
            change = f"{0.0 - e.reduction_pct + 0.0:+.1f} %"  # + 0.0: no "-0.0"
        ratio = (f"{e.oracle_ratio:.2f}" if e.oracle_ratio is not None else "",) if with_oracle else ()
        p_holm = f"{e.p_holm:.2g}" if e.p_holm is not None else ""  # none for the baseline and the oracle
        mean = f"{e.mean_time_s:.1f}" if e.mean_time_s is not None else "n/a"  # every episode a failed team's
        episodes = sum((e.end_reasons or {}).values()) or e.n  # n: the episodes compared, a failed team's left out
        table.add_row(labels[name], mean, change, p_holm, *ratio, f"{e.episodes_done}/{episodes}")
    print_table(table)


def _method_names(methods: str, robots: str, strategy: str) -> list[str]:
    """``evaluate``'s methods, each run by every team size of ``robots`` under every strategy; a
    warning where ``--strategy`` is given but no team runs."""
    from frontier_rl.evaluation.running.methods import team_methods

    strategies = [parse_strategy(s) for s in comma_list(strategy)]
    sizes = int_list("--robots", robots)
    names = team_methods(policy_list(methods), sizes, strategies)
    if all(n == 1 for n in sizes) and strategies != [Strategy.UNCOORDINATED]:
        print_warning("--strategy acts between robots: with --robots 1 it is ignored (POLICY@N:STRATEGY names its own)")
    return names


@friendly_errors
def evaluate(
    methods: Annotated[str, typer.Option(help="Comma-separated policies, e.g. fixed:0.75,learned:models/model5.zip")],
    out: Annotated[Path, typer.Option(help="Results folder; rerunning with it resumes.")],
    worlds: Annotated[str, typer.Option(help="Comma-separated generators, files, folders, catalogue maps.")] = "office",
    episodes: Annotated[int, typer.Option(help="Episodes per world; episode i uses seed SEED + i.")] = 120,
    seed: Annotated[int, typer.Option(help="Seed of the first episode.")] = 0,
    baseline: Annotated[str, typer.Option(help="The method every other is compared with.")] = THESIS_BASELINE,
    oracle: Annotated[bool, typer.Option(help="Also run the full-knowledge oracle tour (reference).")] = True,
    workers: WorkersOption = None,
    backend: Annotated[str, typer.Option(help="serial, process or ray.")] = "process",
    ray_address: Annotated[str | None, typer.Option(help="Ray head host:port (default: a local Ray).")] = None,
    outliers: Annotated[str, typer.Option(help="Also compare without episodes above these times (s).")] = "1000,2000",
    config: SimConfigOption = None,
    max_time: MaxTimeOption = None,
    resolution: ResolutionOption = None,
    trust_model: TrustModelOption = False,
    progress: ProgressOption = True,
    robots: RobotsOption = "1",
    strategy: StrategyOption = "uncoordinated",
    comm_range: CommRangeOption = None,
    fail: FailOption = None,
    pictures: Annotated[int, typer.Option(help="Draw each method's first episode on this many worlds.")] = 3,
) -> None:
    """The paired experiment: every method on the same worlds.

    The same worlds, starts and noise for each method; statistics against the baseline, plots, and a
    Markdown and HTML report in --out. With --robots, teams of each size run each method, and the
    report adds exploration time against team size, overlap and per-robot coverage."""
    resolution = checked_run_arguments(seed, out, resolution)
    from frontier_rl import api
    from frontier_rl.evaluation.running.evaluate import parse_thresholds

    names = _method_names(methods, robots, strategy)
    with _resumable(out):
        summary = api.evaluate(
            names,
            [worlds],  # a comma list, as --worlds takes
            episodes,
            out=out,
            baseline=baseline,
            oracle=oracle,
            seed=seed,
            workers=workers,
            backend=backend,
            ray_address=ray_address,
            config=sim_config(config, max_time),
            resolution=resolution,
            trust_model=trust_model,
            comm_range=checked_comm_range(comm_range),
            failures=tuple(Failure.parse(text) for text in fail or []),
            outliers=parse_thresholds(outliers),
            pictures=checked_count("--pictures", pictures),
            progress=progress,
            command=_command_line("evaluate"),
        )
    _print_summary(summary, f"{episodes} episode(s) per world on {', '.join(summary.worlds)}", baseline)
    report = out / "report.md"
    print_line(f"report: {report} and {report.with_suffix('.html')}")


@contextmanager
def _resumable(out: Path) -> Iterator[None]:
    """Ctrl-C in the block ends the command (exit code 130) with a line saying how to resume it."""
    try:
        yield
    except KeyboardInterrupt:
        print_note(_INTERRUPTED.format(out=out))
        raise typer.Exit(130) from None


def _command_line(command: str) -> str:
    """The command as the user typed it, for the report."""
    return f"frontier-rl {command} " + " ".join(sys.argv[2:]) if len(sys.argv) > 2 else f"frontier-rl {command}"
