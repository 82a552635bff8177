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
import threading
import time
from dataclasses import dataclass
from pathlib import Path

CHECKOUT = Path(__file__).resolve().parents[1]
HELP_TARGET_S = 0.3
SMALL_EXPLORE_TARGET_S = 0.8
LIMIT_S = 120.0
"""A timed process still running after this long (s) is killed, and the benchmark fails."""
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

app = typer.Typer(rich_markup_mode=None)


@app.command()
def explore(world: str = "office", seed: int = 0) -> None:
    \"\"\"Explore one world.\"\"\"


@app.command()
def evaluate(seeds: int = 10) -> None:
    \"\"\"Evaluate policies.\"\"\"


app()
"""
"""The floor under ``--help``: a typer command line of two commands, its help laid out by click as
plain text, as ``frontier-rl``'s is."""


@dataclass(frozen=True)
class Process:
    """A Python process the benchmark times: ``python ARGS`` with ``path`` on the module path."""

    args: tuple[str, ...]
    path: Path = CHECKOUT


def interleaved_seconds(processes: list[Process], repeats: int) -> list[list[float]]:
    """Wall time (s) of ``repeats`` runs of each process, run in turn (one of each, then again), so
    that a machine slowing down for a while slows all of them alike; after one untimed run of each
    that fills the caches (numba's kernels, Python's bytecode, the disk's). Python writes its bytecode
    even where the caller's environment says not to (``PYTHONDONTWRITEBYTECODE``, set on some CI and
    container images): a user's installed package has it, and compiling the package's source again
    in every process cost the small explore 0.1-0.3 s here."""
    environment = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}

    def run(process: Process) -> float:
        return exact_wall_seconds([sys.executable, *process.args], environment | {"PYTHONPATH": str(process.path)})

    for process in processes:
        run(process)
    rounds = [[run(process) for process in processes] for _ in range(repeats)]
    return [list(times) for times in zip(*rounds, strict=True)]


def exact_wall_seconds(command: list[str], environment: dict[str, str], limit_s: float = LIMIT_S) -> float:
    """The wall time (s) of ``command``, run to its end. ``Popen.wait(timeout)`` polls, sleeping up
    to 50 ms between looks, which rounded every time measured here up to the next step of 50 ms
    (a process of 0.12 s read 0.165 s); a plain ``wait()`` blocks until the process ends, and a timer
    kills a process still running after ``limit_s``.

    Raises:
        subprocess.CalledProcessError: the command failed (or was killed).
    """
    start = time.perf_counter()
    with subprocess.Popen(command, env=environment, stdout=subprocess.DEVNULL) as child:
        watchdog = threading.Timer(limit_s, child.kill)
        watchdog.start()
        try:
            code = child.wait()
        finally:
            watchdog.cancel()
    seconds = time.perf_counter() - start
    if code != 0:
        raise subprocess.CalledProcessError(code, command)
    return seconds


def bench_startup(repeats: int) -> list[tuple[str, float, str, float | None]]:
    """(metric, value, unit, target or None): the median seconds of ``--help``, of the floor under it
    (:data:`FLOOR_CLI`), of one explore on the small map and of the floor under that
    (:data:`FLOOR_KERNEL`), and each command's median ratio to its floor over the rounds."""
    cli = ("-m", "frontier_rl.cli")
    explore = (*cli, "explore", "--world", SMALL_MAP, "--policy", "nearest", "--seed", "0", "--json")
    with tempfile.TemporaryDirectory() as folder:
        floors = Path(folder)
        (floors / "floor_kernel.py").write_text(FLOOR_KERNEL)
        (floors / "floor_cli.py").write_text(FLOOR_CLI)
        kernel = ("-c", "import numpy as np, floor_kernel; floor_kernel.total(np.ones(3))")
        help_floor = ("-m", "floor_cli", "--help")
        processes = [Process((*cli, "--help")), Process(help_floor, floors), Process(explore), Process(kernel, floors)]
        help_s, help_floor_s, explore_s, floor_s = interleaved_seconds(processes, repeats)

    def ratio(command: list[float], floor: list[float]) -> float:
        return statistics.median(c / f for c, f in zip(command, floor, strict=True))

    help_name, explore_name = "`frontier-rl --help`", f"`frontier-rl explore --world {SMALL_MAP}`"
    median, of = statistics.median, f"median of {repeats}"
    return [
        (f"{help_name} as a process ({of})", median(help_s), "s", HELP_TARGET_S),
        (f"floor: a typer command line of two commands, its --help ({of})", median(help_floor_s), "s", None),
        (f"{help_name} over its floor ({of} rounds)", ratio(help_s, help_floor_s), "×", None),
        (f"{explore_name} as a process ({of})", median(explore_s), "s", SMALL_EXPLORE_TARGET_S),
        (
            f"floor: a process importing NumPy, SciPy's ndimage and numba, one cached kernel ({of})",
            median(floor_s),
            "s",
            None,
        ),
        (f"{explore_name} over its floor ({of} rounds)", ratio(explore_s, floor_s), "×", None),
    ]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--repeats", type=int, default=5)
    for metric, value, unit, target in bench_startup(parser.parse_args().repeats):
        print(f"{metric}: {value:.3f} {unit}" + ("" if target is None else f" (target {target} {unit})"))


if __name__ == "__main__":
    main()
