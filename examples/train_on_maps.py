"""Train a frontier-ranking model on a folder of maps, then compare it with the nearest frontier on
maps it never saw.

    python examples/train_on_maps.py --maps dungeon/train --test-maps dungeon/easy --timesteps 60000

``--maps`` and ``--test-maps`` take catalogue names (``frontier-rl maps`` lists them), folders of map
files and single maps, comma-separated. Training keeps one map in ten of the training folder for
validation, writes checkpoints and a learning curve into OUT/training, and the final model,
OUT/training/model.zip, is a policy every command takes as ``learned:OUT/training/model.zip``.
Training loads torch; the first run compiles the simulator's kernels.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import NoReturn

import frontier_rl
from frontier_rl import SimConfig, TrainConfig


class OneLineErrors(argparse.ArgumentParser):
    """Bad arguments end the script as bad values do: one ``error:`` line, exit code 2 (as frontier-rl)."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"error: {message}\n")


def main() -> None:
    parser = OneLineErrors(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--maps", default="dungeon/train", help="maps to train on")
    parser.add_argument("--test-maps", default="dungeon/easy", help="maps to evaluate on, never trained on")
    parser.add_argument("--model", type=int, default=7, help="model 1-7 (7: frontier choice with tour costs)")
    parser.add_argument("--timesteps", type=int, default=60_000, help="decisions to train for")
    parser.add_argument("--n-envs", type=int, default=2, help="environments (processes) trained in parallel")
    parser.add_argument("--episodes", type=int, default=1, help="evaluation episodes per test map")
    parser.add_argument(
        "--workers", type=int, default=None, help="test episodes at once (default: every core; 1: in this process)"
    )
    parser.add_argument("--max-time", type=float, default=None, help="sim-time cap of an episode (s)")
    parser.add_argument("--out", type=Path, default=Path("runs/train_on_maps"), help="run folder")
    args = parser.parse_args()

    sim = SimConfig() if args.max_time is None else SimConfig(max_sim_time=args.max_time)
    # Every training setting has the thesis's or our tested default; these are the ones to change first.
    config = TrainConfig(model=args.model, worlds=args.maps, timesteps=args.timesteps, n_envs=args.n_envs, sim=sim)
    model = frontier_rl.train(config, args.out / "training", progress=True)
    print(f"model: {model}")

    # The paired comparison on the test maps: the same starts and sensor noise for both methods.
    learned = f"learned:{model}"
    summary = frontier_rl.evaluate(
        [learned],
        args.test_maps.split(","),
        args.episodes,
        out=args.out / "evaluation",
        baseline="nearest",
        oracle=False,
        workers=args.workers,
        backend="serial" if args.workers == 1 else "process",  # one at a time: no worker process to start
        config=sim,
        pictures=1,
    )
    result = summary.methods[learned]
    low, high = result.ci95_s
    print(f"{len(summary.worlds)} test map(s), {result.n} paired episodes")
    nearest = summary.methods["nearest"]
    print(f"nearest: {_number(nearest.mean_time_s)} s; model {args.model}: {_number(result.mean_time_s)} s")
    print(
        f"saving: {_number(result.mean_diff_s)} s, {_number(result.reduction_pct)} % "
        f"(95 % CI of the saving {_number(low)} to {_number(high)} s), "
        f"p one-tailed {_number(result.p_one_tailed, '.2g')}"
    )
    print(f"report: {args.out / 'evaluation' / 'report.md'}")


def _number(value: float | None, spec: str = ".1f") -> str:
    return "n/a" if value is None else format(value, spec)


if __name__ == "__main__":
    try:
        main()
    except frontier_rl.FrontierRLError as exc:  # bad maps or settings: one line, no traceback
        print(f"error: {exc}", file=sys.stderr)
        sys.exit(2)
