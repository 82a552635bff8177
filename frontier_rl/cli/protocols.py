"""``frontier-rl benchmark PROTOCOL``: a published evaluation protocol, with its metric beside ours
(:mod:`frontier_rl.evaluation.protocols.published`)."""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import asdict
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from frontier_rl.atomic_write import write_text_atomic
from frontier_rl.cli.options import WorkersOption, output_file
from frontier_rl.cli.output import OneLineGroup, friendly_errors, int_list, policy_list, print_line, print_table
from frontier_rl.errors import ConfigError, short_repr
from frontier_rl.swarm.config import MAX_ROBOTS

if TYPE_CHECKING:
    from rich.table import Table

    from frontier_rl.evaluation.protocols.explore_bench import ExploreBenchSummary
    from frontier_rl.evaluation.protocols.published import AriadneSummary

benchmark_app = typer.Typer(
    no_args_is_help=True, cls=OneLineGroup, help="Run a published evaluation protocol, its metric beside ours."
)
DEFAULT_DUNGEON_TESTS = "dungeon/complex"
"""ARiADNE's hardest test set, a catalogue collection (``frontier-rl maps dungeon/complex``)."""


@benchmark_app.command()
@friendly_errors
def ariadne(
    methods: Annotated[
        str, typer.Option(help="Comma-separated policies (as for explore --policy).")
    ] = "nearest,oracle",
    maps: Annotated[
        str, typer.Option(help="A folder of DungeonMaps test PNGs, or a catalogue collection (dungeon/easy, ...).")
    ] = DEFAULT_DUNGEON_TESTS,
    limit: Annotated[int, typer.Option(help="Run only the first N maps in ARiADNE's order (0: all).")] = 0,
    workers: WorkersOption = None,
    json_out: Annotated[Path | None, typer.Option("--json", help="Also write every run and the summary here.")] = None,
) -> None:
    """ARiADNE's test protocol, beside our time to explore.

    An 80 px sensor; a run ends at <= 250 unseen free px; distance in px."""
    from frontier_rl.evaluation.protocols.published import ariadne_maps, run_protocol, summary_rows

    names = policy_list(methods)
    _check_json(json_out)
    if limit < 0:
        raise ConfigError(f"--limit must be >= 0, got {limit}")
    files = ariadne_maps(_folder(maps), limit or None)
    runs, failures = run_protocol(names, files, workers)
    _some_finished(runs, failures)
    rows = summary_rows(runs, names)
    print_table(_ariadne_table(rows, f"ARiADNE protocol on {maps} ({len(files)} maps)"))
    for row in rows:  # as ARiADNE's test driver prints them, one line each (a log is grepped for them)
        print_line(
            f"{row.method}: |#Total test: {row.tests} |#Average length: {row.average_length_px:.2f} "
            f"|#Length std: {row.length_std_px:.2f}"
        )
    _finish(json_out, {"protocol": "ariadne", "maps": maps}, rows, runs, failures)


DEFAULT_BLUEPRINTS = "turtlebot3_world,aws_small_house,nav2_depot"
"""Explore-Bench's blueprints here: three ROS maps of the catalogue."""


@benchmark_app.command("explore-bench")
@friendly_errors
def explore_bench(
    methods: Annotated[str, typer.Option(help="Comma-separated policies (as for explore --policy).")] = "nearest",
    maps: Annotated[
        str, typer.Option(help="ROS maps (YAML or catalogue names) or folders of them: the blueprints.")
    ] = DEFAULT_BLUEPRINTS,
    robots: Annotated[str, typer.Option(help="Team sizes, e.g. 1,2 (Explore-Bench runs one and two).")] = "1,2",
    seeds: Annotated[int, typer.Option(help="Starts per map and team size: seeds 0..N-1.")] = 5,
    workers: WorkersOption = None,
    json_out: Annotated[Path | None, typer.Option("--json", help="Also write every run and the summary here.")] = None,
) -> None:
    """Explore-Bench's metrics on ROS maps, beside our time.

    T_90, T_total at a 0.99 exploration rate and the path; for teams the coverage std and the
    overlap rate."""
    from frontier_rl.evaluation.protocols import explore_bench as bench

    names = policy_list(methods)
    _check_json(json_out)
    sizes = list(dict.fromkeys(int_list("--robots", robots)))  # a size given twice runs once
    if not all(1 <= n <= MAX_ROBOTS for n in sizes):
        raise ConfigError(f"--robots takes team sizes 1 to {MAX_ROBOTS}, got {short_repr(robots)}")
    if not 1 <= seeds <= 10_000:
        raise ConfigError(f"--seeds must be in 1..10000, got {seeds}")
    from frontier_rl.world_spec import world_entries

    blueprints = [m for entry in world_entries(maps) for m in bench.explore_bench_maps(_located(entry))]
    runs, failures = bench.run_explore_bench_all(names, blueprints, seeds, sizes, workers)
    _some_finished(runs, failures)
    rows = bench.explore_bench_rows(runs)
    print_table(_explore_bench_table(rows, seeds))
    _finish(json_out, {"protocol": "explore-bench", "maps": maps}, rows, runs, failures)


def _ariadne_table(rows: list[AriadneSummary], title: str) -> Table:
    """The ARiADNE protocol's summary rows as a table, its metric beside ours."""
    from rich.table import Table

    table = Table(title=title)
    for column in (
        "method",
        "tests",
        "average length (px)",
        "length std (px)",
        "rule met",
        "ours: time (s)",
        "ours: path (m)",
        "ours: explored",
    ):
        table.add_column(column, justify="left" if column == "method" else "right")
    for row in rows:
        n = row.tests
        table.add_row(
            row.method,
            str(n),
            f"{row.average_length_px:.1f}",
            f"{row.length_std_px:.1f}",
            f"{row.rule_met}/{n}",
            f"{row.mean_time_s:.1f}",
            f"{row.mean_path_m:.1f}",
            f"{row.explored}/{n}",
        )
    return table


def _explore_bench_table(rows: list[ExploreBenchSummary], seeds: int) -> Table:
    """Explore-Bench's summary rows as a table, its metrics beside our time."""
    from rich.table import Table

    table = Table(title=f"Explore-Bench metrics, {seeds} start(s) per map and team size")
    for column in (
        "method",
        "robots",
        "map",
        "ended / runs",
        "T_90 (s)",
        "T_total (s)",
        "path (m)",
        "coverage std",
        "overlap rate",
        "final rate",
        "ours: time (s)",
    ):
        table.add_column(column, justify="left" if column in ("method", "map") else "right")
    for row in rows:
        figures = (row.t90_s, row.t_total_s, row.path_m, row.coverage_std, row.overlap_rate, row.final_rate)
        table.add_row(
            row.method,
            str(row.robots),
            row.map,
            f"{row.ended} / {row.runs}",
            *(_shown(value) for value in (*figures, row.ours_time_s)),
        )
    return table


def _located(entry: str) -> str:
    """The file or folder a ``--maps`` entry names (a path, or a catalogue map or collection); a
    generator's name as it is (the protocol refuses it)."""
    from frontier_rl.world_spec import world_path

    path = world_path(entry)
    return entry if path is None else str(path)


def _folder(entry: str) -> Path:
    """The folder of ARiADNE test maps that ``--maps`` names (a path or a catalogue collection)."""
    path = Path(_located(entry))
    if not path.is_dir():
        raise ConfigError(f"--maps {short_repr(entry)} is not a folder or a collection of maps")
    return path


def _check_json(json_out: Path | None) -> None:
    """Refuse a ``--json`` path no file can be written to before the runs, not after them."""
    if json_out is not None:
        output_file(json_out, ".json", "--json")


def _no_nan(value: Any) -> Any:
    """``value`` with every float that is not finite (a mean over no run) as None: JSON has no NaN."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: _no_nan(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_no_nan(v) for v in value]
    return value


def _shown(value: float) -> str:
    """A table cell: 3 significant digits, a dash where there is no value (NaN)."""
    return "—" if math.isnan(value) else f"{value:.3g}"


def _some_finished(runs: Sequence[object], failures: list[str]) -> None:
    """Stop with one line when every run failed, before an empty table (or one of NaN) is printed."""
    from frontier_rl.evaluation.running.backends import EpisodeFailedError

    if failures and not runs:
        raise EpisodeFailedError(f"every one of the {len(failures)} run(s) failed: {'; '.join(failures[:3])}")


def _finish(
    json_out: Path | None, head: dict[str, str], summary: Sequence[Any], runs: Sequence[Any], failures: list[str]
) -> None:
    """Write ``head``, the summary lines, the runs (dataclasses, as their fields) and the failures
    to ``json_out`` (if given), then fail if any run did: the table and the file keep the runs that
    finished."""
    from frontier_rl.evaluation.running.backends import EpisodeFailedError

    if json_out is not None:
        payload = head | {"summary": [asdict(s) for s in summary], "runs": [asdict(r) for r in runs]}
        text = json.dumps(_no_nan(payload | {"failures": failures}), indent=2, allow_nan=False)
        json_out.parent.mkdir(parents=True, exist_ok=True)  # a folder the check let it make
        write_text_atomic(json_out, text + "\n")
    if failures:
        raise EpisodeFailedError(
            f"{len(failures)} run(s) failed (the table leaves them out): {'; '.join(failures[:3])}"
        )
