"""Speed of the ROS 2 explorer: how long a decision takes, and how fast a team runs over DDS.

1. Decisions (no ROS): the explorer's planner ticks that choose a goal, timed while it explores the
   simulated robot in-process (:func:`~frontier_rl.robot.sim_robot.explore_in_process`), on office
   worlds and on ``nav2_warehouse``, per policy: median and 99th percentile (ms), decisions per second.
2. A team over ROS 2 (real rclpy and Fast DDS, in a loopback-only network namespace):
   ``ros2 sim --robots N --rate R`` and an explorer per robot, until every explorer ends, with the
   ranking service (``ros2 rank``) for the same robots asked ``--requests`` times a second per robot
   meanwhile; the wall time, the simulated time, the speed-up reached (simulated s per wall s,
   against ``--rate``), decisions per robot, the end reasons, and the requests sent, answered and
   their round trips (from publishing a request to receiving its status).

    .venv/bin/python benchmarks/ros2_explorer.py [--seeds 3] [--robots 4] [--rate 10] [--requests 10] [--json PATH]
"""

from __future__ import annotations

import argparse
import json
import math
import shlex
import statistics
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # bench this checkout, not an install

from frontier_rl import api
from frontier_rl.core.sim.episode import warm_up
from frontier_rl.policies.registry import make_policy
from frontier_rl.robot.explorer import FrontierExplorer
from frontier_rl.robot.explorer_decision import Goal
from frontier_rl.robot.explorer_params import ExplorerParams
from frontier_rl.robot.sim_robot import SimulatedRobot, explore_in_process
from frontier_rl.ros2.loopback import cli, loopback_problem, run_in_loopback

POLICIES = ("nearest", "fixed:0.75", "learned:models/model7.zip")


class _TimedExplorer(FrontierExplorer):
    """An explorer that times its ticks that chose a goal (s; a goal sent again with its path
    renewed is no choice)."""

    decision_times: list[float]

    def tick(self, *args: Any, **kwargs: Any) -> Any:
        started, decisions = time.perf_counter(), self.decisions
        decision = super().tick(*args, **kwargs)
        if isinstance(decision, Goal) and self.decisions > decisions:
            self.decision_times.append(time.perf_counter() - started)
        return decision


def decision_speed(world_name: str, seeds: int, policy: str) -> dict[str, Any]:
    """The explorer's decision times over ``seeds`` episodes of ``world_name`` with ``policy``."""
    times: list[float] = []
    for seed in range(seeds):
        world = api.load_world(world_name, seed)
        robot = SimulatedRobot(world, seed=seed)
        explorer = _TimedExplorer(make_policy(policy), ExplorerParams(time_cap=robot.sim.max_sim_time))
        explorer.decision_times = []
        explore_in_process(robot, explorer)
        times += explorer.decision_times
    ms = np.array(times) * 1e3
    median = float(np.median(ms))
    return {
        "world": world_name,
        "policy": policy,
        "decisions": len(times),
        "median_ms": round(median, 2),
        "p99_ms": round(float(np.percentile(ms, 99)), 2),
        "decisions_per_s": round(1e3 / median, 1),
    }


def team_over_ros2(world: str, seed: int, robots: int, rate: float, requests: float, home: Path) -> dict[str, Any]:
    """A team of ``robots`` on ``world`` at ``rate`` over ROS 2, an explorer per robot, until all
    end, with the ranking service asked ``requests`` times a second per robot meanwhile."""
    frontier_rl = shlex.quote(cli())
    names = ",".join(f"tb3_{i}" for i in range(robots))
    client = f"{shlex.quote(sys.executable)} {shlex.quote(str(Path(__file__).with_name('ranking_client.py')))}"
    explorers = " ".join(
        f"timeout --preserve-status -s INT 1200 {frontier_rl} ros2 explore --json --use-sim-time "
        f"--namespace tb3_{i} --seed {seed + i} > explore{i}.log 2> explore{i}.err & e{i}=$!;"
        for i in range(robots)
    )
    waits = " ".join(f"wait $e{i};" for i in range(robots))
    script = (
        f"{frontier_rl} ros2 sim --world {world} --seed {seed} --rate {rate:g} --robots {robots} > sim.log 2>&1 & "
        f"sim=$!; {frontier_rl} ros2 rank --robots {names} > rank.log 2>&1 & rank=$!; "
        f"{client} {names} --rate {requests:g} --until-file done > client.log 2> client.err & client=$!; "
        f"{explorers} {waits} touch done; wait $client; stop $rank $sim"
    )
    started = time.perf_counter()
    done = run_in_loopback(script, home, 1300)
    wall = time.perf_counter() - started
    statuses = []
    for i in range(robots):
        lines = (home / f"explore{i}.log").read_text().strip().splitlines()
        statuses.append(json.loads(lines[-1]) if lines else {"state": "no status", "time_s": 0.0, "goals": 0})
    sim_time = max(float(s["time_s"]) for s in statuses)
    load = json.loads((home / "client.log").read_text() or "{}")
    trips = np.array(load.get("round_trips_s") or [math.nan]) * 1e3
    answered = load.get("statuses", [])
    return {
        "world": world,
        "robots": robots,
        "rate": rate,
        "exit": done.returncode,
        "wall_s": round(wall, 1),
        "sim_s": round(sim_time, 1),
        "speed_up": round(sim_time / wall, 2),
        "decisions_per_robot": [s["goals"] for s in statuses],
        "reasons": [s.get("reason") or s["state"] for s in statuses],
        "requests_per_robot_s": requests,
        "requests_sent": load.get("sent", 0),
        "answered": len(answered),
        "answered_with_frontiers": sum(1 for a in answered if a["frontiers"]),
        "round_trip_median_ms": round(float(np.median(trips)), 2),
        "round_trip_p99_ms": round(float(np.percentile(trips, 99)), 2),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=3, help="episodes per world and policy")
    parser.add_argument("--robots", type=int, default=4, help="robots of the team over ROS 2 (0: none)")
    parser.add_argument("--rate", type=float, default=10.0, help="the team's simulated s per wall s")
    parser.add_argument("--requests", type=float, default=10.0, help="ranking requests per robot per second")
    parser.add_argument("--json", type=Path, help="write the rows here too")
    args = parser.parse_args()
    warm_up(make_policy("nearest"))
    rows: list[dict[str, Any]] = []
    print("| world | policy | decisions | median (ms) | p99 (ms) | decisions/s |\n|---|---|---:|---:|---:|---:|")
    for world in ("office", "nav2_warehouse"):
        for policy in POLICIES:
            row = decision_speed(world, args.seeds if world == "office" else 1, policy)
            rows.append(row)
            print(
                f"| {world} | {policy} | {row['decisions']} | {row['median_ms']} | {row['p99_ms']} | "
                f"{row['decisions_per_s']} |",
                flush=True,
            )
    if args.robots:
        problem = loopback_problem()
        if problem is not None:
            print(f"team over ROS 2 not run: {problem}")
        else:
            import tempfile

            with tempfile.TemporaryDirectory() as home:
                team = team_over_ros2("office", 3, args.robots, args.rate, args.requests, Path(home))
            rows.append(team)
            print(json.dumps(team))
    if args.json is not None:
        args.json.write_text(json.dumps(rows, indent=1) + "\n")
    print(f"median of medians: {statistics.median(r['median_ms'] for r in rows if 'median_ms' in r)} ms")


if __name__ == "__main__":
    main()
