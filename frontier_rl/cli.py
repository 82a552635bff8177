"""The ``frontier-rl`` command line: ``explore`` one episode, ``demo`` the built-in worlds, ``train`` a model."""

from __future__ import annotations

import dataclasses
import json
import os
import sys
from pathlib import Path
from typing import Annotated, Any, NoReturn

import typer
from rich.table import Table
from rich.text import Text

from frontier_rl.cli_benchmark import benchmark_app
from frontier_rl.cli_maps import maps_command
from frontier_rl.cli_output import (
    OneLineGroup,
    comma_list,
    err_console,
    friendly_errors,
    int_list,
    one_line,
    policy_list,
    stdout_console,
)
from frontier_rl.config import dump_config, load_sim_config
from frontier_rl.core.frontiers.ranking import THESIS_BASELINE
from frontier_rl.core.navigation.tours import MAX_STOPS
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import run_episode, warm_up
from frontier_rl.core.sim.metrics import EpisodeResult
from frontier_rl.core.world.catalog import WORLD_GENERATORS
from frontier_rl.core.world.worlds import resolution_bounds
from frontier_rl.errors import ConfigError, short_path, short_repr
from frontier_rl.policies import ENTRY_POINT_GROUP, POLICY_NAMES, make_policy
from frontier_rl.recording import EpisodeRecorder, save_team_png
from frontier_rl.render import check_output_file
from frontier_rl.swarm import Failure, TeamConfig, parse_strategy, run_team_episode
from frontier_rl.world_spec import checked_resolution, parse_pose, resolve_world

#: Largest seed a command accepts (0 to 2**32 - 1: NumPy's legacy seeding, which SB3 uses, takes no more).
MAX_SEED = 2**32 - 1
WORLD_HELP = f"{' | '.join(WORLD_GENERATORS)} | a map file (ROS .yaml, Dungeon .png, HouseExpo .json) | a catalogue map"
POLICY_HELP = (
    f"One of: {', '.join(POLICY_NAMES)} (W in [0, 1], N stops 1 to {MAX_STOPS}); or your own: FILE.py:CLASS, "
    f"MODULE:CLASS (on PYTHONPATH) or a name an installed package registers under {ENTRY_POINT_GROUP}."
)

app = typer.Typer(
    add_completion=False, no_args_is_help=True, help="Frontier exploration for search and rescue.", cls=OneLineGroup
)
app.add_typer(benchmark_app, name="benchmark")
app.command("maps")(maps_command)

_RES_LO, _RES_HI = resolution_bounds()

# Options that several commands share
ResolutionOption = Annotated[
    float | None,
    typer.Option(
        help=f"Cell size (m) for map files, {_RES_LO:.2g} to {_RES_HI:.3g} (the robot's radius); "
        "below 0.04 m the robot maps on 0.05 m cells."
    ),
]
TrustModelOption = Annotated[
    bool, typer.Option(help="Allow learned:PATH to be an SB3 zip from elsewhere (unpickles it: runs its code).")
]
SimConfigOption = Annotated[Path | None, typer.Option(help="SimConfig YAML (any subset of its fields).")]

_INTERRUPTED = "interrupted: finished episodes are saved in {out}/; rerun the same command to resume"
DEMO_WORLDS = ("office", "rooms", "cluttered")
SHIPPED_MODELS = (Path("models/model4.zip"), Path("models/model5.zip"), Path("models/model7.zip"))
"""Trained models in the repository; the demo runs them too when run from the checkout."""


def _fail(message: str) -> NoReturn:
    raise ConfigError(message)


def _seed(value: int, option: str = "--seed") -> int:
    """A seed option, checked: a whole number from 0 to :data:`MAX_SEED`."""
    if not 0 <= value <= MAX_SEED:
        _fail(f"{option} must be a whole number from 0 to {MAX_SEED}, got {short_repr(value)}")
    return value


def _count(option: str, value: int) -> int:
    """A count option, checked: a whole number of at least 0."""
    if value < 0:
        _fail(f"{option} must be 0 or more, got {short_repr(value)}")
    return value


def _output_folder(path: Path, option: str = "--out") -> Path:
    """A results folder option, checked before any work: an existing folder, or a path whose
    nearest existing ancestor is a writable folder (the command creates the rest)."""
    if path.exists() and not path.is_dir():
        _fail(f"{option} {short_path(path)} is a file, not a folder")
    ancestor = path
    while not ancestor.exists() and ancestor != ancestor.parent:
        ancestor = ancestor.parent
    if not ancestor.is_dir():
        _fail(f"{option} {short_path(path)}: {short_path(ancestor)} is a file, not a folder")
    if not os.access(ancestor, os.W_OK | os.X_OK):
        _fail(f"{option} {short_path(path)}: folder {short_path(ancestor)} is not writable")
    return path


def _team_config(robots: int, strategy: str, comm_range: float | None, fail: list[str]) -> TeamConfig | None:
    """The team of ``explore``'s options; None for a single robot with no team option."""
    failures = tuple(Failure.parse(text) for text in fail)
    team = TeamConfig(robots, parse_strategy(strategy), _comm_range(comm_range), failures)
    return None if team == TeamConfig() else team


def _comm_range(value: float | None) -> float | None:
    """``--comm-range``, checked (m; None: the strategy's default)."""
    if value is not None and not value >= 0:
        raise ConfigError(f"--comm-range must be >= 0 m, got {value!r}")
    return value


def _sim_config(config: Path | None, max_time: float | None) -> SimConfig:
    cfg = load_sim_config(config) if config is not None else SimConfig()
    if max_time is not None:
        if not max_time > 0:
            raise ConfigError(f"--max-time must be a positive number of seconds, got {max_time!r}")
        cfg = dataclasses.replace(cfg, max_sim_time=max_time)
    return cfg


@app.command()
@friendly_errors
def explore(
    world: Annotated[str, typer.Option(help=WORLD_HELP)] = "office",
    seed: Annotated[int, typer.Option(help=f"Seeds the world, the start and the sensor noise (0 to {MAX_SEED}).")] = 0,
    policy: Annotated[str, typer.Option(help=POLICY_HELP)] = THESIS_BASELINE,
    png: Annotated[Path | None, typer.Option(help="Write a picture of the episode to this .png file.")] = None,
    gif: Annotated[
        Path | None, typer.Option(help="Write an animation, one frame per decision, to this .gif file.")
    ] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print the metrics as one JSON object.")] = False,
    start: Annotated[str | None, typer.Option(help="Start pose 'x,y[,theta]' (m, rad; |theta| <= 1e6).")] = None,
    resolution: ResolutionOption = None,
    config: SimConfigOption = None,
    max_time: Annotated[float | None, typer.Option(help="Sim-time cap of the episode (s).")] = None,
    trust_model: TrustModelOption = False,
    robots: Annotated[int, typer.Option(help="Team size, 1 to 8; robot 0 starts on the start pose.")] = 1,
    strategy: Annotated[
        str, typer.Option(help="Team coordination: uncoordinated | coordinated | rendezvous.")
    ] = "uncoordinated",
    comm_range: Annotated[
        float | None,
        typer.Option(help="Robots this close (m) merge maps and share goals (default: unlimited; rendezvous: 2 m)."),
    ] = None,
    fail: Annotated[
        list[str] | None,
        typer.Option(help="ROBOT@SECONDS: that robot stops for good then (either may be 'random'); repeatable."),
    ] = None,
) -> None:
    """Explore one world with one policy (or a team of robots) and report time, distance and coverage."""
    # Every option is checked before the episode runs (outputs included); the metrics are printed
    # before the pictures are written, so a picture that cannot be written loses no result.
    _seed(seed)
    sim_config = _sim_config(config, max_time)
    team = _team_config(robots, strategy, comm_range, fail or [])
    if gif is not None and team is not None:
        raise ConfigError("--gif records one robot's decisions; use --png for a team")
    if png is not None:
        check_output_file(png, ".png", "--png")
    if gif is not None:
        check_output_file(gif, ".gif", "--gif")
    resolution = checked_resolution(resolution)
    pose = parse_pose(start) if start is not None else None
    chosen = make_policy(policy, trust_model=trust_model)
    the_world = resolve_world(world, seed, pose, resolution)
    warm_up()
    recorder = None
    if team is not None:
        result: EpisodeResult = run_team_episode(the_world, chosen, sim_config, team, seed)
    else:
        recorder = EpisodeRecorder(the_world, frames=gif is not None) if (png or gif) else None
        result = run_episode(the_world, chosen, sim_config, seed, on_decision=recorder)
    _print_episode(the_world.name, seed, chosen.name, result, as_json)
    title = f"{the_world.name} / {chosen.name}"
    if team is not None and png is not None:
        save_team_png(png, the_world, result, title)  # type: ignore[arg-type]
    if recorder is not None and png is not None:
        recorder.save_png(png, result, title)
    if recorder is not None and gif is not None:
        recorder.save_gif(gif, result, title)


def _print_episode(world: str, seed: int, policy: str, result: EpisodeResult, as_json: bool) -> None:
    """An episode's metrics on standard output: one JSON object, or a table."""
    summary = {"world": world, "seed": seed, "policy": policy, **result.summary()}
    weights = [d.weight for d in result.decision_log if d.weight is not None]
    if weights and as_json:
        summary["weights"] = weights  # the weight of every decision, in order
    elif weights:
        summary["mean_weight"] = round(float(sum(weights) / len(weights)), 3)
    if as_json:
        summary["frontiers_left"] = [f.summary() for f in result.frontiers_left]
        typer.echo(json.dumps(summary))
        return
    summary["frontiers_left"] = len(result.frontiers_left)
    table = Table(title=f"{world}, seed {seed}, {policy}")
    table.add_column("metric")
    table.add_column("value", justify="right")
    for key, value in summary.items():
        table.add_row(key, str(value))
    stdout_console().print(table)


@app.command()
@friendly_errors
def demo(
    out: Annotated[Path, typer.Option(help="Folder for the report and pictures (rewritten).")] = Path("demo_output"),
    seed: Annotated[int, typer.Option(help="Seed of the first episode.")] = 0,
    episodes: Annotated[int, typer.Option(help="Episodes per world.")] = 10,
    workers: Annotated[int | None, typer.Option(help="Episodes run at once (default: every core).")] = None,
    max_time: Annotated[float | None, typer.Option(help="Sim-time cap of every episode (s).")] = None,
    progress: Annotated[bool, typer.Option(help="Show a progress bar.")] = True,
) -> None:
    """The compact experiment: the shipped models against fixed:0.75, nearest, tour and the oracle
    on the built-in worlds, with a report in OUT/experiment, and a picture of each method's first
    episode on each world (plus an animation of one)."""
    import shutil

    from frontier_rl.evaluation.evaluate import DEFAULT_OUTLIERS_S
    from frontier_rl.evaluation.evaluate import evaluate as run_evaluation
    from frontier_rl.evaluation.experiment import ORACLE, ExperimentConfig

    _seed(seed)
    _output_folder(out)
    learned = (f"learned:{path}" for path in SHIPPED_MODELS if path.exists())
    methods = (THESIS_BASELINE, "nearest", "tour", *learned, ORACLE)
    sim = _sim_config(None, max_time)
    experiment = ExperimentConfig(methods=methods, worlds=DEMO_WORLDS, episodes=episodes, seed=seed, sim=sim)
    out.mkdir(parents=True, exist_ok=True)
    results = out / "experiment"
    if results.exists():  # the demo starts afresh: a retrained model must not meet its old rows
        shutil.rmtree(results)
    dump_config(experiment.sim, out / "config.yaml")
    command = "frontier-rl demo " + " ".join(sys.argv[2:]) if len(sys.argv) > 2 else "frontier-rl demo"
    report = run_evaluation(experiment, results, "process", workers, None, DEFAULT_OUTLIERS_S, progress, command,
                            pictures=len(DEMO_WORLDS), animate=("office", THESIS_BASELINE))  # fmt: skip
    _print_summary(report, f"{episodes} episode(s) per world on {', '.join(DEMO_WORLDS)}", experiment.baseline)
    stdout_console().print(
        f"report: {report.with_suffix('.html')} (and .md); pictures of seed {seed} in {results}/pictures/"
    )


def _print_summary(report: Path, title: str, baseline: str) -> None:
    """The main numbers of an experiment's ``summary.json`` as a table on the terminal."""
    from frontier_rl.evaluation.tables import short_labels

    summary = json.loads((report.parent / "summary.json").read_text())
    labels = short_labels(summary["methods"])
    table = Table(title=title, caption=_not_explored(summary["methods"], labels), caption_justify="left")
    for column in ("method", "mean time (s)", "vs baseline", "p one-tailed", "time / oracle", "done"):
        table.add_column(column, justify="left" if column == "method" else "right", no_wrap=column == "method")
    for name, e in summary["methods"].items():
        compared = name != baseline and e["reduction_pct"] is not None
        change = f"{0.0 - e['reduction_pct'] + 0.0:+.1f} %" if compared else "baseline"  # + 0.0: no "-0.0"
        table.add_row(
            labels[name], f"{e['mean_time_s']:.1f}", change,
            f"{e['p_one_tailed']:.2g}" if compared and e["p_one_tailed"] is not None else "",
            f"{e['oracle_ratio']:.2f}" if e["oracle_ratio"] is not None else "", f"{e['episodes_done']}/{e['n']}",
        )  # fmt: skip
    stdout_console().print(table)


def _not_explored(methods: dict[str, dict[str, Any]], labels: dict[str, str]) -> str | None:
    """The episodes each method ended otherwise than explored, by reason ("not explored: nearest
    1 unreachable, 2 time_cap; ..."); None if every episode was explored."""
    from frontier_rl.evaluation.conclusion import unfinished

    parts = unfinished(methods, labels)
    return "not explored: " + "; ".join(parts) if parts else None


@app.command()
@friendly_errors
def evaluate(
    methods: Annotated[str, typer.Option(help="Comma-separated policies, e.g. fixed:0.75,learned:models/model5.zip")],
    out: Annotated[Path, typer.Option(help="Results folder; rerunning with it resumes.")],
    worlds: Annotated[str, typer.Option(help="Comma-separated generators, files, folders, catalogue maps.")] = "office",
    episodes: Annotated[int, typer.Option(help="Episodes per world; episode i uses seed SEED + i.")] = 120,
    seed: Annotated[int, typer.Option(help="Seed of the first episode.")] = 0,
    baseline: Annotated[str, typer.Option(help="The method every other is compared with.")] = THESIS_BASELINE,
    oracle: Annotated[bool, typer.Option(help="Also run the full-knowledge oracle tour (reference).")] = True,
    workers: Annotated[int | None, typer.Option(help="Episodes run at once (default: every core).")] = None,
    backend: Annotated[str, typer.Option(help="serial, process or ray.")] = "process",
    ray_address: Annotated[str | None, typer.Option(help="Ray head host:port (default: a local Ray).")] = None,
    outliers: Annotated[str, typer.Option(help="Also compare without episodes above these times (s).")] = "1000,2000",
    config: SimConfigOption = None,
    max_time: Annotated[float | None, typer.Option(help="Sim-time cap of every episode (s).")] = None,
    resolution: ResolutionOption = None,
    trust_model: TrustModelOption = False,
    progress: Annotated[bool, typer.Option(help="Show a progress bar.")] = True,
    robots: Annotated[
        str, typer.Option(help="Team sizes to run every method with, e.g. 1,2,4 (a method POLICY@N runs as given).")
    ] = "1",
    strategy: Annotated[
        str, typer.Option(help="Team strategies for sizes above 1: uncoordinated, coordinated, rendezvous (a list).")
    ] = "uncoordinated",
    comm_range: Annotated[
        float | None, typer.Option(help="Teams' communication range (m); default unlimited, rendezvous 2 m.")
    ] = None,
    fail: Annotated[
        list[str] | None, typer.Option(help="ROBOT@SECONDS: a failure in every team episode (repeatable).")
    ] = None,
    pictures: Annotated[int, typer.Option(help="Draw each method's first episode on this many worlds.")] = 3,
) -> None:
    """The paired experiment: every method on the same worlds, starts and noise; statistics against the
    baseline, plots, and a Markdown and HTML report in --out. With --robots, teams of each size run each
    method, and the report adds exploration time against team size, overlap and per-robot coverage."""
    from frontier_rl.evaluation.evaluate import evaluate as run_evaluation
    from frontier_rl.evaluation.evaluate import parse_thresholds
    from frontier_rl.evaluation.experiment import ORACLE, ExperimentConfig, expand_worlds, team_methods

    _seed(seed)
    _output_folder(out)
    resolution = checked_resolution(resolution)
    names = team_methods(
        policy_list(methods), int_list("--robots", robots), [parse_strategy(s) for s in comma_list(strategy)]
    )
    ordered = list(dict.fromkeys([baseline, *names, *([ORACLE] if oracle else [])]))
    experiment = ExperimentConfig(
        methods=tuple(ordered), worlds=expand_worlds(worlds), episodes=episodes, seed=seed, baseline=baseline,
        sim=_sim_config(config, max_time), resolution=resolution, trust_model=trust_model,
        comm_range=_comm_range(comm_range),
        failures=tuple(Failure.parse(text) for text in fail or []),
    )  # fmt: skip
    command = "frontier-rl evaluate " + " ".join(sys.argv[2:]) if len(sys.argv) > 2 else "frontier-rl evaluate"
    try:
        report = run_evaluation(experiment, out, backend, workers, ray_address, parse_thresholds(outliers), progress,
                                command, pictures=_count("--pictures", pictures))  # fmt: skip
    except KeyboardInterrupt:
        err_console.print(Text(one_line(_INTERRUPTED.format(out=out))))
        raise typer.Exit(130) from None
    _print_summary(report, f"{episodes} episode(s) per world on {', '.join(experiment.worlds)}", baseline)
    stdout_console().print(f"report: {report} and {report.with_suffix('.html')}")


@app.command()
@friendly_errors
def train(
    out: Annotated[Path, typer.Option(help="Run directory: config, checkpoints, logs, model.zip, learning curve.")],
    model: Annotated[int, typer.Option(help="Model: 1, 2 (point), 3, 4, 6 (weight), 5, 7 (frontier).")] = 4,
    worlds: Annotated[str, typer.Option(help="Generators, files, folders, catalogue maps, each [=WEIGHT].")] = "office",
    timesteps: Annotated[int, typer.Option(help="Decisions to train for.")] = 100_000,
    n_envs: Annotated[int, typer.Option(help="Parallel environments (subprocesses).")] = 2,
    algo: Annotated[str, typer.Option(help="a2c (the thesis), ppo or dagger (models 5 and 7).")] = "a2c",
    observation_size: Annotated[int, typer.Option(help="Map image edge: 64 or 250 pixels.")] = 64,
    reward: Annotated[str, typer.Option(help="Reward preset: normalised or thesis.")] = "normalised",
    learning_rate: Annotated[float, typer.Option(help="Optimizer step size.")] = 7e-4,
    n_steps: Annotated[int, typer.Option(help="Decisions per env between updates.")] = 8,
    gamma: Annotated[float, typer.Option(help="Discount per decision, in (0, 1].")] = 0.99,
    ent_coef: Annotated[float, typer.Option(help="Entropy bonus: keeps the policy trying other actions.")] = 0.001,
    seed: Annotated[int, typer.Option(help="Seeds the envs and the network.")] = 0,
    eval_every: Annotated[int, typer.Option(help="Decisions between validations (0: none).")] = 10_000,
    checkpoint_every: Annotated[int, typer.Option(help="Decisions between checkpoints (0: none).")] = 10_000,
    init: Annotated[str, typer.Option(help="Model file whose weights start the run (same model).")] = "",
    privileged_critic: Annotated[
        bool, typer.Option(help="Models 5 and 7: the critic also reads the true map's unseen share (training only).")
    ] = False,
    privileged_map: Annotated[
        bool, typer.Option(help="With --privileged-critic: it also sees the true map's unseen space as an image.")
    ] = False,
    config: SimConfigOption = None,
    resume: Annotated[bool, typer.Option(help="Continue the run in --out from its last checkpoint.")] = False,
    progress: Annotated[bool, typer.Option(help="Show a progress bar.")] = True,
) -> None:
    """Train a model (1-4 the thesis's, 5-7 ours) with Stable-Baselines3 (A2C as in the thesis, or PPO)."""
    _seed(seed)
    _output_folder(out)
    from frontier_rl.rl.config import TrainConfig
    from frontier_rl.rl.train import interruption_note
    from frontier_rl.rl.train import train as run_training

    settings = TrainConfig(
        model=model, worlds=worlds, timesteps=timesteps, n_envs=n_envs, algo=algo,
        observation_size=observation_size, reward=reward, learning_rate=learning_rate, n_steps=n_steps,
        gamma=gamma, ent_coef=ent_coef, seed=seed, eval_every=eval_every, checkpoint_every=checkpoint_every, init=init,
        privileged_critic=privileged_critic, privileged_map=privileged_map, sim=_sim_config(config, None),
    )  # fmt: skip
    try:
        final = run_training(settings, out, resume=resume, progress=progress)
    except KeyboardInterrupt:
        err_console.print(Text(one_line(interruption_note(settings, out))))
        raise typer.Exit(130) from None
    stdout_console().print(f"model: {final}   learning curve: {out / 'learning_curve.png'}")


if __name__ == "__main__":
    app()
