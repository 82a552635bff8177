"""The ROS 2 explorer's decisions on the harder survey's maps, in-process (no ROS): its
:class:`~frontier_rl.robot.explorer.FrontierExplorer` drives the simulated robot as Nav2 would
(:func:`~frontier_rl.robot.sim_robot.explore_in_process`: a planner tick every
``1 / planner_frequency`` s of simulated time, goals found on the narrow-passage recovery's levels
followed as paths), one episode per map and seed, the time cap the simulator's. Prints a row per
episode (end reason, coverage of the explorable space, simulated time, decisions, goals given up)
and the totals the ROS 2 guide's "Real buildings, in-process" quotes; with ``--out``, the rows as
JSON lines, written as they come (a rerun skips the episodes the file has).

    .venv/bin/python experiments/explorer_survey.py --seeds 1,2 --workers 2 --out results/explorer_survey.jsonl
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from frontier_rl.api import load_world
from frontier_rl.policies.registry import make_policy
from frontier_rl.robot.explorer import FrontierExplorer, check_robot_policy
from frontier_rl.robot.explorer_params import ExplorerParams
from frontier_rl.robot.sim_robot import SimulatedRobot, explore_in_process


def _survey_maps() -> tuple[str, ...]:
    """The harder survey's maps (``experiments/harder_survey.py``'s ``MAPS``)."""
    spec = importlib.util.spec_from_file_location("harder_survey", Path(__file__).with_name("harder_survey.py"))
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look their module up
    spec.loader.exec_module(module)
    return tuple(module.MAPS)


@dataclass(frozen=True)
class ExplorerEpisode:
    """One in-process episode of the explorer.

    Attributes:
        map, seed, policy: what was explored, from which start, ranked how.
        end_reason: how the explorer ended (``explored``, ``unreachable``, ``time_cap``).
        coverage: the share of the map's explorable space mapped (the simulator's measure).
        sim_time_s: simulated time (s); wall_time_s: the episode's wall time (s).
        decisions: goals chosen; goals_given_up: of them given up (aborted, no progress, reached in vain).
    """

    map: str
    seed: int
    policy: str
    end_reason: str
    coverage: float
    sim_time_s: float
    decisions: int
    goals_given_up: int
    wall_time_s: float


def run_one(world: str, seed: int, policy: str) -> ExplorerEpisode:
    """The explorer with ``policy`` on ``world`` from ``seed``'s start, until it ends."""
    started = time.perf_counter()
    robot = SimulatedRobot(load_world(world, seed), seed=seed)
    _, policy_rng = np.random.default_rng(seed).spawn(2)  # as `frontier-rl ros2 explore --seed` seeds it
    ranking = make_policy(policy)
    check_robot_policy(ranking, policy)
    explorer = FrontierExplorer(ranking, ExplorerParams(time_cap=robot.sim.max_sim_time), rng=policy_rng)
    finished = explore_in_process(robot, explorer)
    result = robot.result()
    return ExplorerEpisode(
        world,
        seed,
        policy,
        finished.reason.value,
        round(result.coverage, 6),
        round(result.sim_time_s, 2),
        explorer.decisions,
        explorer.goals_given_up,
        round(time.perf_counter() - started, 1),
    )


def totals(episodes: list[ExplorerEpisode]) -> str:
    """One line: how many reached 99 %, the mean coverage, the goals given up and the simulated time."""
    at_99 = sum(e.coverage >= 0.99 for e in episodes)
    mean = 100 * sum(e.coverage for e in episodes) / len(episodes)
    given_up, sim_time = sum(e.goals_given_up for e in episodes), sum(e.sim_time_s for e in episodes)
    return (
        f"{len(episodes)} episodes: {at_99} at 99 % or more, mean coverage {mean:.3f} %, "
        f"{given_up:,} goals given up, {sim_time:,.0f} s simulated"
    )


def _read_rows(path: Path) -> list[ExplorerEpisode]:
    """The episodes a former run wrote to ``path`` (JSON lines); exits with one line on a damaged one."""
    rows = []
    for number, line in enumerate(path.read_text().splitlines(), start=1):
        if not line.strip():
            continue
        try:
            rows.append(ExplorerEpisode(**json.loads(line)))
        except (ValueError, TypeError) as error:
            sys.exit(f"error: {path}:{number} is no episode of this script ({error})")
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--maps", default=",".join(_survey_maps()), help="comma-separated catalogue maps or map files")
    parser.add_argument("--seeds", default="1,2", help="comma-separated starts (seeds)")
    parser.add_argument("--policy", default="nearest", help="the policy spec the explorer ranks with")
    parser.add_argument("--workers", type=int, default=1, help="episodes run at once (processes)")
    parser.add_argument("--out", type=Path, help="JSON lines, one per episode, appended as they come")
    args = parser.parse_args()
    wanted = [(world.strip(), int(seed)) for seed in args.seeds.split(",") for world in args.maps.split(",")]
    had = _read_rows(args.out) if args.out is not None and args.out.exists() else []
    done = [e for e in had if e.policy == args.policy and (e.map, e.seed) in wanted]
    jobs = [job for job in wanted if job not in {(e.map, e.seed) for e in done}]
    with ProcessPoolExecutor(max(args.workers, 1)) as pool:
        futures = {pool.submit(run_one, world, seed, args.policy): (world, seed) for world, seed in jobs}
        for future in as_completed(futures):
            try:
                episode = future.result()
            except Exception as error:  # one map that fails (a bad file) ends none of the others
                print(f"{futures[future][0]} seed {futures[future][1]}: failed: {error}", file=sys.stderr)
                continue
            done.append(episode)
            print(
                f"{episode.map:<18} {episode.seed:>4} {episode.end_reason:<11} {100 * episode.coverage:7.2f} % "
                f"{episode.sim_time_s:>10,.0f} s {episode.decisions:>6} decisions {episode.goals_given_up:>5} given up",
                flush=True,
            )
            if args.out is not None:
                args.out.parent.mkdir(parents=True, exist_ok=True)
                with args.out.open("a") as out:
                    out.write(json.dumps(asdict(episode)) + "\n")
    if done:
        print(totals(done))


if __name__ == "__main__":
    main()
