"""Paired speed comparison of two or more checkouts of this project on the same office episodes.

Run as ``python benchmarks/compare.py BASELINE OTHER [OTHER ...] [--rounds R] [--seeds N]``, each
argument a checkout (a ``git worktree`` of another commit, say). One worker process per checkout,
pinned to the same core, warms up, then every office seed is run by every checkout back to back
(the order alternating from seed to seed), R times over. The machine's speed drifts by tens of
percent from minute to minute; a ratio of two runs a second apart does not, so the result is the
median over all episodes of each checkout's wall time divided by the baseline's on the same
episode. Each checkout runs its own code: the workers import ``frontier_rl`` from the checkout.

An episode's wall time here is that of the whole ``run_episode`` call: the loop and the result's
account of what is left (the frontiers left and their audit), which the episode's own
``wall_time_s`` leaves out (its loop only). Comparisons before 2026-12-01 timed the loop only.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

WORKER = r"""
import json, os, sys, time
os.environ.update(dict.fromkeys(("NUMBA_NUM_THREADS", "OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS"), "1"))
sys.path.insert(0, os.getcwd())
try:
    from frontier_rl.core.sim.episode import run_episode
    try:
        from frontier_rl.core.world.catalog import generate_world
    except ImportError:  # before the named worlds had a module of their own
        from frontier_rl.core.world.worlds import generate_world
except ImportError:  # a checkout from before core/ had its stage sub-packages
    from frontier_rl.core.episode import run_episode
    from frontier_rl.core.worlds import generate_world
from frontier_rl.policies import make_policy
run_episode(generate_world("office", 10_000), make_policy("fixed:0.75"), seed=10_000)  # compile
print("ready", flush=True)
for line in sys.stdin:
    seed = int(line)
    world, policy = generate_world("office", seed), make_policy("fixed:0.75")
    started = time.perf_counter()
    result = run_episode(world, policy, seed=seed)
    print(json.dumps([time.perf_counter() - started, result.sim_time_s]), flush=True)
"""


def episode_wall_time(worker: subprocess.Popen[str], seed: int) -> float:
    """The wall time (s) of office episode ``seed`` run by ``worker``."""
    if worker.stdin is None or worker.stdout is None:
        raise SystemExit("a worker has no pipes")
    worker.stdin.write(f"{seed}\n")
    worker.stdin.flush()
    return float(json.loads(worker.stdout.readline())[0])


def main(argv: list[str] | None = None) -> int:
    """Compare the checkouts; prints one line per checkout."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("checkouts", nargs="+", type=Path, help="the baseline first, then the others")
    parser.add_argument("--rounds", type=int, default=3, help="times each seed is run (default 3)")
    parser.add_argument("--seeds", type=int, default=20, help="office seeds 0..N-1 (default 20)")
    args = parser.parse_args(argv)
    missing = [str(c) for c in args.checkouts if not (c / "frontier_rl").is_dir()]
    if len(args.checkouts) < 2 or missing or args.rounds < 1 or args.seeds < 1:
        parser.error(f"need two or more checkouts, rounds >= 1 and seeds >= 1 (not checkouts: {missing})")
    core = str(min(os.sched_getaffinity(0))) if hasattr(os, "sched_getaffinity") else None
    prefix = ["taskset", "-c", core] if core is not None and sys.platform == "linux" else []
    command = [*prefix, sys.executable, "-c", WORKER]
    workers = [
        subprocess.Popen(command, cwd=c, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        for c in args.checkouts
    ]
    try:
        for w in workers:
            if w.stdout is None or w.stdout.readline().strip() != "ready":
                raise SystemExit(f"a worker failed to start (exit code {w.poll()})")
        walls: list[list[float]] = [[] for _ in workers]
        for round_ in range(args.rounds):
            for seed in range(args.seeds):
                order = list(range(len(workers)))
                if (seed + round_) % 2:
                    order.reverse()
                for i in order:
                    walls[i].append(episode_wall_time(workers[i], seed))
    finally:
        for w in workers:
            if w.stdin is not None:
                w.stdin.close()
            w.wait()
    n = args.rounds * args.seeds
    print(f"{n} office episodes per checkout (fixed:0.75, seeds 0-{args.seeds - 1}, {args.rounds} rounds)")
    for checkout, times in zip(args.checkouts, walls, strict=True):
        ratio = statistics.median(t / b for t, b in zip(times, walls[0], strict=True))
        print(f"{checkout}: median wall {statistics.median(times):.3f} s, median ratio to the baseline {ratio:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
