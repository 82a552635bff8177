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
import time
from pathlib import Path

CHECKOUT = Path(__file__).resolve().parents[1]
HELP_TARGET_S = 0.3
SMALL_EXPLORE_TARGET_S = 0.8
SMALL_MAP = "lse_arena"  # the smallest catalogue map (9.9 m x 9.4 m); its episode takes milliseconds


def process_seconds(args: list[str], repeats: int) -> list[float]:
    """Wall time (s) of ``repeats`` runs of ``python -m frontier_rl.cli ARGS`` on this checkout, after
    one untimed run that fills the caches (numba's kernels, Python's bytecode, the disk's)."""
    command = [sys.executable, "-m", "frontier_rl.cli", *args]
    environment = os.environ | {"PYTHONPATH": str(CHECKOUT)}

    def run() -> float:
        start = time.perf_counter()
        subprocess.run(command, env=environment, check=True, stdout=subprocess.DEVNULL, timeout=120)
        return time.perf_counter() - start

    run()
    return [run() for _ in range(repeats)]


def bench_startup(repeats: int) -> list[tuple[str, float, float]]:
    """(metric, median seconds, target seconds) of ``--help`` and of one explore on the small map."""
    explore = ["explore", "--world", SMALL_MAP, "--policy", "nearest", "--seed", "0", "--json"]
    return [
        (f"`frontier-rl --help` as a process (median of {repeats})",
         statistics.median(process_seconds(["--help"], repeats)), HELP_TARGET_S),
        (f"`frontier-rl explore --world {SMALL_MAP}` as a process (median of {repeats})",
         statistics.median(process_seconds(explore, repeats)), SMALL_EXPLORE_TARGET_S),
    ]  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--repeats", type=int, default=5)
    for metric, seconds, target in bench_startup(parser.parse_args().repeats):
        print(f"{metric}: {seconds:.3f} s (target {target} s)")


if __name__ == "__main__":
    main()
