"""How good is the teacher that ``train --algo dagger`` imitates? Paired episodes per world of
``nearest``, the teacher's base policy (``greedy``, always the cheapest path, for model 5's teacher;
``tour`` for model 7's), the lookahead teacher (:func:`~frontier_rl.rl.teacher.teacher_slot`)
and the oracle.

The teacher sees the simulator's future, so it is a reference like the oracle, never a method; a
teacher much faster than ``nearest`` is what makes imitating it worth trying. Every method explores
the same world from the same start with the same sensor noise; each row gives every method's end
reason beside its time.

    .venv/bin/python experiments/lookahead_teacher.py --worlds office,dungeon/easy \\
        --episodes 4 --out results/lookahead_teacher.json
    .venv/bin/python experiments/lookahead_teacher.py --teacher tour --worlds dungeon/easy \\
        --episodes 6 --out results/tour_teacher.json    # model 7's: fresh noise, a 10 % margin
"""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

import numpy as np

from frontier_rl.atomic_write import write_text_atomic
from frontier_rl.core.sim.episode import run_episode
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.worlds import World
from frontier_rl.evaluation.running.experiment import expand_worlds
from frontier_rl.policies import make_policy
from frontier_rl.rl.teacher import GREEDY_TEACHER, TOUR_TEACHER, Teacher, take_slot, teacher_slot
from frontier_rl.world_spec import resolve_world

TOP_K = 16  # model 5's slots


def _simulator(world: World, seed: int) -> ExplorationSimulator:
    """The simulator ``run_episode(world, policy, seed=seed)`` builds: the same sensor-noise
    stream (the first of the two it spawns from ``seed``), so that every method is paired."""
    return ExplorationSimulator(world, rng=np.random.default_rng(seed).spawn(2)[0])


def episode_time(world: World, seed: int, choose: Callable[[ExplorationSimulator], int]) -> tuple[float, str | None]:
    """Sim time (s) and end reason of an episode in which ``choose(sim)`` names every decision's slot."""
    sim = _simulator(world, seed)
    while not sim.truncated and not sim.finished:
        take_slot(sim, choose(sim), TOP_K)
    reason = sim.end_reason()
    return sim.sim_time, None if reason is None else reason.value


def world_times(world: World, seed: int, teacher: Teacher) -> tuple[dict[str, float], dict[str, str | None]]:
    """Each method's time (s) and end reason on ``world``, from the same start and noise stream."""
    times: dict[str, float] = {}
    ends: dict[str, str | None] = {}
    for name in ("nearest", "oracle", "tour") if teacher.base == "tour" else ("nearest", "oracle"):
        result = run_episode(world, make_policy(name), seed=seed)
        times[name], ends[name] = result.sim_time_s, result.end_reason
    if teacher.base == "greedy":
        times["greedy"], ends["greedy"] = episode_time(world, seed, lambda sim: 0)
    times["teacher"], ends["teacher"] = episode_time(world, seed, lambda sim: teacher_slot(sim, TOP_K, teacher))
    return times, ends


def family_summary(rows: list[dict[str, float]]) -> dict[str, dict[str, float]]:
    """Per method: the mean time (s) over ``rows`` and how much less it is than ``nearest``'s (%)."""
    base = float(np.mean([r["nearest"] for r in rows]))
    methods = [m for m in ("nearest", "greedy", "tour", "teacher", "oracle") if m in rows[0]]
    means = {m: float(np.mean([r[m] for r in rows])) for m in methods}
    return {m: {"mean_s": v, "less_than_nearest_pct": 100 * (1 - v / base)} for m, v in means.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--worlds", required=True, help="comma-separated generators and folders of map files")
    parser.add_argument("--episodes", type=int, default=4, help="seeds 0.. per generator, first files per folder")
    parser.add_argument("--teacher", choices=("greedy", "tour"), default="greedy", help="model 5's or model 7's")
    parser.add_argument("--width", type=int, help="candidates the teacher tries (default: the teacher's)")
    parser.add_argument("--margin", type=float, help="share a candidate must save (default: the teacher's)")
    parser.add_argument("--own-noise", action="store_true", help="copies replay the episode's noise stream")
    parser.add_argument("--out", type=Path, required=True, help="JSON file of the results")
    args = parser.parse_args()
    teacher = GREEDY_TEACHER if args.teacher == "greedy" else TOUR_TEACHER
    if args.teacher == "greedy":
        teacher = replace(teacher, margin=0.0)  # the margin this experiment was first run with
    teacher = replace(
        teacher,
        width=teacher.width if args.width is None else args.width,
        margin=teacher.margin if args.margin is None else args.margin,
        fresh_noise=teacher.fresh_noise and not args.own_noise,
    )
    rows = []
    for entry in args.worlds.split(","):
        cases = [(f, 0) for f in expand_worlds(entry)[: args.episodes]] if "/" in entry else [
            (entry, k) for k in range(args.episodes)
        ]  # fmt: skip
        for spec, seed in cases:
            started = time.perf_counter()
            times, ends = world_times(resolve_world(spec, seed), seed, teacher)
            rows.append({"family": entry, "world": spec, "seed": seed, **times, "ends": ends})
            print(spec, seed, {k: round(v, 1) for k, v in times.items()}, ends,
                  f"{time.perf_counter() - started:.0f} s wall")  # fmt: skip
    summary = {family: family_summary([r for r in rows if r["family"] == family]) for family in dict.fromkeys(
        r["family"] for r in rows
    )}  # fmt: skip
    for family, methods in summary.items():
        print(family, {m: f"{v['mean_s']:.1f} s ({v['less_than_nearest_pct']:+.1f} %)" for m, v in methods.items()})
    write_text_atomic(args.out, json.dumps({"rows": rows, "summary": summary}, indent=1))


if __name__ == "__main__":
    main()
