"""Write an exploration policy in a few lines and compare it with the shipped ones.

The policy below drives to the frontier with the most unknown border per metre of the way there.
It is compared with the nearest frontier (the baseline) and the shipped model 7 in a paired
experiment: every method meets the same worlds, start poses and sensor noise, and the summary gives
each method's mean exploration time, its saving against the baseline with a 95 % confidence interval,
and the one-tailed paired t-test's p-value (Holm-adjusted over the methods tested).

    python examples/custom_policy.py --episodes 20 --worlds office,rooms

The experiment's report (report.md / report.html, with plots) is written to --out; rerunning the same
command resumes it. The same class runs on the command line as ``examples/custom_policy.py:SizePerMetre``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import NoReturn

import numpy as np

import frontier_rl
from frontier_rl import DecisionContext, ExperimentSummary, Ranking, SimConfig


class SizePerMetre:
    """The most frontier cells per metre to drive: size / (1 m + distance)."""

    name = "size-per-metre"

    def rank(self, context: DecisionContext, rng: np.random.Generator) -> Ranking:
        frontiers = context.frontiers  # the candidates: sizes (cells), distances (m), centres, ...
        score = frontiers.sizes / (1.0 + frontiers.distances)
        return Ranking(np.argsort(-score, kind="stable"))  # frontier indices, best first


# Experiments run episodes in worker processes, which load a policy by its spec, FILE.py:CLASS:
# this very file (the workers import it, so the code below runs only as a script). The spec is the
# method's name in the results: the absolute path keeps it the same from any working folder, so a
# rerun with the same --out resumes instead of adding a method.
POLICY = f"{Path(__file__).resolve()}:SizePerMetre"
MODEL_7 = Path(__file__).resolve().parent.parent / "models" / "model7.zip"


class OneLineErrors(argparse.ArgumentParser):
    """Bad arguments end the script as bad values do: one ``error:`` line, exit code 2 (as frontier-rl)."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"error: {message}\n")


def main() -> None:
    parser = OneLineErrors(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--episodes", type=int, default=20, help="episodes per world")
    parser.add_argument("--worlds", default="office,rooms", help="generators, catalogue maps or map files")
    parser.add_argument("--out", type=Path, default=Path("results/custom_policy"), help="results folder")
    parser.add_argument("--model", type=Path, default=None, help="a model file to compare with (default: model 7)")
    parser.add_argument("--max-time", type=float, default=None, help="sim-time cap of an episode (s)")
    parser.add_argument(
        "--workers", type=int, default=None, help="episodes at once (default: every core; 1: in this process)"
    )
    parser.add_argument(
        "--oracle", action=argparse.BooleanOptionalAction, default=True, help="also run the full-knowledge oracle"
    )
    args = parser.parse_args()

    model = compared_model(args.model)
    methods = [POLICY] if model is None else [POLICY, f"learned:{model}"]
    config = SimConfig() if args.max_time is None else SimConfig(max_sim_time=args.max_time)
    summary = frontier_rl.evaluate(
        methods,
        args.worlds.split(","),
        args.episodes,
        out=args.out,
        baseline="nearest",
        oracle=args.oracle,
        workers=args.workers,
        backend="serial" if args.workers == 1 else "process",  # one at a time: no worker process to start
        config=config,
    )
    labels = {POLICY: SizePerMetre.name} | ({f"learned:{model}": model.stem} if model else {})
    print_summary(summary, labels)
    print(f"report: {args.out / 'report.md'}")


def compared_model(model: Path | None) -> Path | None:
    """The model file to compare with: ``model``, which must exist, or model 7, left out (with a
    line saying so) where this file is not in a clone that has it."""
    if model is not None:
        if not model.is_file():
            raise frontier_rl.ConfigError(f"--model {str(model)!r} is not a file")
        return model
    if MODEL_7.is_file():
        return MODEL_7
    print(f"model 7 left out: no {MODEL_7} (--model names another model file)", file=sys.stderr)
    return None


def print_summary(summary: ExperimentSummary, labels: dict[str, str]) -> None:
    """One line per method from the typed summary (the fields of summary.json)."""
    print(f"{summary.episodes} episode(s) on {', '.join(summary.worlds)}; baseline {summary.baseline}")
    for name, method in summary.methods.items():
        line = f"{labels.get(name, name):>15}: {_number(method.mean_time_s)} s"
        if name == summary.baseline:
            line += "  (baseline)"
        elif name != summary.reference:
            low, high = method.ci95_s  # of the mean saving (s); a negative saving is a loss
            line += f"  saves {_number(method.mean_diff_s)} s, {_number(method.reduction_pct)} %"
            line += f" (95 % CI {_number(low)} to {_number(high)} s)"
            line += f", p = {_number(method.p_one_tailed, '.2g')} (Holm: {_number(method.p_holm, '.2g')})"
        if method.oracle_ratio is not None:
            line += f", {method.oracle_ratio:.2f} × the oracle's time"
        print(line + f", {method.episodes_done}/{method.n} explored")


def _number(value: float | None, spec: str = ".1f") -> str:
    return "n/a" if value is None else format(value, spec)


if __name__ == "__main__":
    try:
        main()
    except frontier_rl.FrontierRLError as exc:  # bad worlds or settings: one line, no traceback
        print(f"error: {exc}", file=sys.stderr)
        sys.exit(2)
