"""Start-up benchmark: the wall time of whole ``frontier-rl`` processes, where the import of the
package and the loading of numba's cached kernels count, not only the episode.

Run by ``benchmarks/run.py`` (``make bench``); alone as ``python benchmarks/startup.py [--repeats N]``.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

CHECKOUT = Path(__file__).resolve().parents[1]
HELP_TARGET_S = 0.3
SMALL_EXPLORE_TARGET_S = 0.8
SMALL_MAP = "lse_arena"  # the smallest catalogue map (9.9 m x 9.4 m); its episode takes milliseconds
FLOOR_KERNEL = """
import numba
import numpy as np
from scipy import ndimage


@numba.njit(cache=True)
def total(values):
    sum_ = 0.0
    for value in values:
        sum_ += value
    return sum_
"""
"""The floor under any process of the engine: a module that imports what every episode needs (NumPy,
SciPy's ndimage, numba) and one cached kernel; numba sets up its compiler target at the first call."""

FLOOR_CLI = """
import typer

app = typer.Typer()


@app.command()
def explore(world: str = "office", seed: int = 0) -> None:
    \"\"\"Explore one world.\"\"\"


@app.command()
def evaluate(seeds: int = 10) -> None:
    \"\"\"Evaluate policies.\"\"\"


app()
"""
"""The floor under ``--help``: a typer command line of two commands, its help laid out by rich as
typer does when rich is installed."""


def process_seconds(args: list[str], repeats: int, path: Path = CHECKOUT) -> list[float]:
    """Wall time (s) of ``repeats`` runs of ``python ARGS`` with ``path`` on the module path (this
    checkout), after one untimed run that fills the caches (numba's kernels, Python's bytecode, the
    disk's). Python writes its bytecode even where the caller's environment says not to
    (``PYTHONDONTWRITEBYTECODE``, set on some CI and container images): a user's installed package
    has it, and compiling the package's source again in every process cost the small explore
    0.1-0.3 s here."""
    command = [sys.executable, *args]
    environment = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    environment["PYTHONPATH"] = str(path)

    def run() -> float:
        start = time.perf_counter()
        subprocess.run(command, env=environment, check=True, stdout=subprocess.DEVNULL, timeout=120)
        return time.perf_counter() - start

    run()
    return [run() for _ in range(repeats)]


def floor_seconds(repeats: int) -> list[float]:
    """Wall time (s) of ``repeats`` processes that import :data:`FLOOR_KERNEL`'s module and call its
    kernel once: what no command that runs an episode can go below."""
    with tempfile.TemporaryDirectory() as folder:
        (Path(folder) / "floor_kernel.py").write_text(FLOOR_KERNEL)
        script = "import numpy as np, floor_kernel; floor_kernel.total(np.ones(3))"
        return process_seconds(["-c", script], repeats, Path(folder))


def help_floor_seconds(repeats: int) -> list[float]:
    """Wall time (s) of ``repeats`` processes printing :data:`FLOOR_CLI`'s ``--help``: what no
    typer command line's help goes below."""
    with tempfile.TemporaryDirectory() as folder:
        (Path(folder) / "floor_cli.py").write_text(FLOOR_CLI)
        return process_seconds(["-m", "floor_cli", "--help"], repeats, Path(folder))


def bench_startup(repeats: int) -> list[tuple[str, float, float | None]]:
    """(metric, median seconds, target seconds or None) of ``--help`` and of the floor under it
    (:func:`help_floor_seconds`), of one explore on the small map and of the floor under it
    (:func:`floor_seconds`)."""
    cli = ["-m", "frontier_rl.cli"]
    explore = [*cli, "explore", "--world", SMALL_MAP, "--policy", "nearest", "--seed", "0", "--json"]
    return [
        (f"`frontier-rl --help` as a process (median of {repeats})",
         statistics.median(process_seconds([*cli, "--help"], repeats)), HELP_TARGET_S),
        (f"floor: a typer command line of two commands, its --help (median of {repeats})",
         statistics.median(help_floor_seconds(repeats)), None),
        (f"`frontier-rl explore --world {SMALL_MAP}` as a process (median of {repeats})",
         statistics.median(process_seconds(explore, repeats)), SMALL_EXPLORE_TARGET_S),
        (f"floor: a process importing NumPy, SciPy's ndimage and numba, one cached kernel (median of {repeats})",
         statistics.median(floor_seconds(repeats)), None),
    ]  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--repeats", type=int, default=5)
    for metric, seconds, target in bench_startup(parser.parse_args().repeats):
        print(f"{metric}: {seconds:.3f} s" + ("" if target is None else f" (target {target} s)"))


if __name__ == "__main__":
    main()
