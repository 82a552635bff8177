"""``frontier-rl explore``: one world, one policy (or a team of robots), one episode."""

from __future__ import annotations

import json
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from frontier_rl.cli.options import (
    MAX_SEED,
    POLICY_HELP,
    WORLD_HELP,
    ResolutionOption,
    SimConfigOption,
    TrustModelOption,
    checked_comm_range,
    output_file,
    sim_config,
)
from frontier_rl.cli.output import friendly_errors, print_table, print_warning
from frontier_rl.core.frontiers.thesis import THESIS_BASELINE
from frontier_rl.core.world.robot import parse_pose
from frontier_rl.core.world.scale import checked_resolution
from frontier_rl.errors import ConfigError
from frontier_rl.policies.spec import PolicySpec
from frontier_rl.seeds import checked_seed
from frontier_rl.swarm.config import Failure, TeamConfig, parse_strategy

if TYPE_CHECKING:
    from frontier_rl.core.sim.config import SimConfig
    from frontier_rl.core.sim.episode import ExplorationPolicy
    from frontier_rl.core.sim.metrics import EpisodeResult
    from frontier_rl.core.world.worlds import World
    from frontier_rl.recording import EpisodeRecorder


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
    """Explore one world with one policy, or a team of robots.

    Reports the time, distance and coverage of the episode."""
    # Every option is checked before the episode runs (outputs included); the metrics are printed
    # before the pictures are written, so a picture that cannot be written loses no result.
    checked_seed(seed, "--seed")
    team = _team_config(robots, strategy, comm_range, fail or [])
    if gif is not None and team is not None:
        raise ConfigError("--gif records one robot's decisions; use --png for a team")
    resolution = checked_resolution(resolution)
    pose = parse_pose(start) if start is not None else None
    spec = PolicySpec.parse(policy)  # a malformed name, before the engine loads
    from frontier_rl import api  # the engine: after every check of the arguments
    from frontier_rl.core.world.catalog import WORLD_GENERATORS
    from frontier_rl.policies.registry import make_policy
    from frontier_rl.recording import EpisodeRecorder

    settings = sim_config(config, max_time)
    if png is not None:
        output_file(png, ".png", "--png")
    if gif is not None:
        output_file(gif, ".gif", "--gif")
    chosen = make_policy(spec, trust_model=trust_model)
    the_world = api.load_world(world, seed, start=pose, resolution=resolution)
    if resolution is not None and world in WORLD_GENERATORS:
        print_warning(f"--resolution is for map files: the generated world {world!r} is drawn on cells of its own")
    recorder = EpisodeRecorder(the_world, frames=gif is not None) if team is None and (png or gif) else None
    result = _episode(the_world, spec, chosen, seed, settings, team, recorder)
    _print_episode(the_world.name, seed, chosen.name, result, as_json)
    _save_pictures(png, gif, the_world, result, f"{the_world.name} / {chosen.name}", recorder)


def _save_pictures(
    png: Path | None,
    gif: Path | None,
    world: World,
    result: EpisodeResult,
    title: str,
    recorder: EpisodeRecorder | None,
) -> None:
    """The picture and the animation asked for: a single robot's from its ``recorder``, a team's
    picture from its result (a team's episode has no recorder and no animation)."""
    if recorder is not None:
        if png is not None:
            recorder.save_png(png, result, title)
        if gif is not None:
            recorder.save_gif(gif, result, title)
    elif png is not None:
        from frontier_rl.recording import save_team_png
        from frontier_rl.swarm.result import TeamResult

        assert isinstance(result, TeamResult)
        save_team_png(png, world, result, title)


def _episode(
    world: World,
    spec: PolicySpec,
    policy: ExplorationPolicy,
    seed: int,
    settings: SimConfig,
    team: TeamConfig | None,
    recorder: EpisodeRecorder | None,
) -> EpisodeResult:
    """The episode of ``policy`` (named ``spec``) on ``world`` (:func:`frontier_rl.api.explore`); an
    exception the user's own policy code raises becomes one line naming the spec, the exception
    and the user's file and line."""
    from frontier_rl import api
    from frontier_rl.policies.user_failures import user_code_failure

    try:
        if team is not None:
            return api.explore(world, policy, seed=seed, config=settings, team=team)
        return api.explore(world, policy, seed=seed, config=settings, on_decision=recorder)
    except (Exception, SystemExit) as exc:  # sys.exit() in a policy's rank() too
        failure = user_code_failure(spec, policy, exc)
        if failure is None:
            raise
        raise failure from None


def _print_episode(world: str, seed: int, policy: str, result: EpisodeResult, as_json: bool) -> None:
    """An episode's metrics on standard output: one JSON object, or a table."""
    summary = {"world": world, "seed": seed, "policy": policy, **result.summary().to_json()}
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
    from rich.table import Table  # the table's only: JSON output needs no rich

    table = Table(title=f"{world}, seed {seed}, {policy}")
    table.add_column("metric")
    table.add_column("value", justify="right")
    for key, value in summary.items():
        table.add_row(key, _table_value(value))
    print_table(table)


def _table_value(value: object) -> str:
    """A metric as the table shows it: ``-`` for none (a robot that never failed, a coverage never
    reached), one value per robot separated by commas, a count per kind (aborts by cause) as
    "kind n" for each kind that has any ("none" when none has), anything else as itself."""
    if value is None:
        return "-"
    if isinstance(value, Mapping):
        return ", ".join(f"{kind} {count}" for kind, count in value.items() if count) or "none"
    if isinstance(value, (list, tuple)):
        return ", ".join(_table_value(item) for item in value)
    return str(value)


def _team_config(robots: int, strategy: str, comm_range: float | None, fail: list[str]) -> TeamConfig | None:
    """The team of ``explore``'s options; None for a single robot that is not to fail (the options
    that act between robots are ignored then, with a warning)."""
    failures = tuple(Failure.parse(text) for text in fail)
    team = TeamConfig(robots, parse_strategy(strategy), checked_comm_range(comm_range), failures)
    between = [name for name, given in (("--strategy", team.strategy != TeamConfig().strategy),
                                        ("--comm-range", comm_range is not None)) if given]  # fmt: skip
    if robots == 1 and between:
        verb, subject = ("acts", "it is") if len(between) == 1 else ("act", "they are")
        print_warning(f"{' and '.join(between)} {verb} between robots: with one robot {subject} ignored (--robots N)")
    return None if robots == 1 and not failures else team
