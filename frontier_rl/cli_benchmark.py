"""``frontier-rl benchmark PROTOCOL``: a published evaluation protocol, with its metric beside ours
(:mod:`frontier_rl.evaluation.protocols`)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer
from rich.table import Table

from frontier_rl.atomic_write import write_text_atomic
from frontier_rl.cli_output import OneLineGroup, comma_list, friendly_errors, stdout_console
from frontier_rl.errors import ConfigError, short_repr

benchmark_app = typer.Typer(
    no_args_is_help=True, cls=OneLineGroup, help="Run a published evaluation protocol, its metric beside ours."
)
DEFAULT_DUNGEON_TESTS = Path("../shared/maps/dungeon/complex")


@benchmark_app.command()
@friendly_errors
def ariadne(
    methods: Annotated[
        str, typer.Option(help="Comma-separated policies (as for explore --policy).")
    ] = "nearest,oracle",
    maps: Annotated[Path, typer.Option(help="A folder of DungeonMaps test PNGs.")] = DEFAULT_DUNGEON_TESTS,
    limit: Annotated[int, typer.Option(help="Run only the first N maps in ARiADNE's order (0: all).")] = 0,
    workers: Annotated[int, typer.Option(help="Processes (0: every core).")] = 0,
    json_out: Annotated[Path | None, typer.Option("--json", help="Also write every run and the summary here.")] = None,
) -> None:
    """ARiADNE's test protocol (80 px sensor, a run ends at <= 250 unseen free px, distance in px)."""
    from frontier_rl.evaluation.backends import EpisodeFailedError
    from frontier_rl.evaluation.protocols import ariadne_maps, run_protocol, summary_rows

    names = comma_list(methods)
    if not names:
        raise ConfigError(f"--methods names no policy: {short_repr(methods)}")
    if limit < 0 or workers < 0:
        raise ConfigError(f"--limit and --workers must be >= 0, got {limit} and {workers}")
    files = ariadne_maps(maps, limit or None)
    runs, failures = run_protocol(names, files, workers or None)
    rows = summary_rows(runs, names)
    table = Table(title=f"ARiADNE protocol on {maps} ({len(files)} maps)")
    for column in ("method", "tests", "average length (px)", "length std (px)", "rule met", "ours: time (s)",
                   "ours: path (m)", "ours: explored"):  # fmt: skip
        table.add_column(column, justify="left" if column == "method" else "right")
    for row in rows:
        n = row["tests"]
        table.add_row(str(row["method"]), str(n), f"{row['average_length_px']:.1f}", f"{row['length_std_px']:.1f}",
                      f"{row['rule_met']}/{n}", f"{row['mean_time_s']:.1f}", f"{row['mean_path_m']:.1f}",
                      f"{row['explored']}/{n}")  # fmt: skip
    console = stdout_console()
    console.print(table)
    for row in rows:  # as ARiADNE's test driver prints them
        console.print(f"{row['method']}: |#Total test: {row['tests']} |#Average length: {row['average_length_px']:.2f} "
                      f"|#Length std: {row['length_std_px']:.2f}")  # fmt: skip
    if json_out is not None:
        payload = {"protocol": "ariadne", "maps": str(maps), "summary": rows, "runs": [vars(r) for r in runs],
                   "failures": failures}  # fmt: skip
        write_text_atomic(json_out, json.dumps(payload, indent=2) + "\n")
    if failures:
        raise EpisodeFailedError(
            f"{len(failures)} run(s) failed (the table leaves them out): {'; '.join(failures[:3])}"
        )
