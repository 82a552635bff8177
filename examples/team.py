"""A team of robots exploring one world: each coordination strategy against a robot alone.

    python examples/team.py --robots 3 --world office --fail 1@120

Each robot has its own map, merged with a teammate's within the communication range. Uncoordinated
robots each rank the frontiers of their own map; coordinated ones lower the utility of a frontier a
teammate heads for (Burgard et al. 2000); rendezvous is the thesis's commander and explorers, who
explore alone and meet to merge maps. ``--fail ROBOT@SECONDS`` stops a robot for good: what it had not
shared is lost, and the others must still finish the map.
"""

from __future__ import annotations

import argparse
import sys
from typing import NoReturn

import frontier_rl
from frontier_rl import Failure, SimConfig, Strategy, TeamConfig


class OneLineErrors(argparse.ArgumentParser):
    """Bad arguments end the script as bad values do: one ``error:`` line, exit code 2 (as frontier-rl)."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"error: {message}\n")


def main() -> None:
    parser = OneLineErrors(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--robots", type=int, default=3, help="team size, 1 to 8")
    parser.add_argument("--world", default="office", help="a generator, catalogue map or map file")
    parser.add_argument("--policy", default="nearest", help="every robot's policy, as for frontier-rl explore")
    parser.add_argument("--seed", type=int, default=0, help="seeds the world, the starts and the sensor noise")
    parser.add_argument("--comm-range", type=float, default=None, help="robots this close (m) share maps")
    parser.add_argument("--fail", action="append", default=[], help="ROBOT@SECONDS: a robot that stops")
    parser.add_argument("--max-time", type=float, default=None, help="sim-time cap (s)")
    args = parser.parse_args()

    config = SimConfig() if args.max_time is None else SimConfig(max_sim_time=args.max_time)
    failures = tuple(Failure.parse(text) for text in args.fail)
    teams = [TeamConfig(args.robots, s, comm_range=args.comm_range, failures=failures) for s in Strategy]
    world = frontier_rl.load_world(args.world, args.seed)  # the same world, start and noise for every run
    alone = frontier_rl.explore(world, args.policy, seed=args.seed, config=config)
    print(f"{'one robot':>14}: {alone.sim_time_s:7.1f} s, {alone.path_length_m:6.1f} m driven, {alone.end_reason}")

    for team in teams:
        result = frontier_rl.explore(world, args.policy, seed=args.seed, config=config, team=team)
        # A TeamResult: the team's time, distance and coverage, and each robot's share of the work.
        shares = " ".join(f"{share:.0%}" for share in result.robot_coverage)
        failed = sum(t is not None for t in result.failed_at_s)
        speedup = alone.sim_time_s / result.sim_time_s
        print(
            f"{team.strategy.value:>14}: {result.sim_time_s:7.1f} s (speed-up {speedup:.2f}×), "
            f"{result.path_length_m:6.1f} m driven, overlap {result.overlap:.0%}, each robot saw {shares}, "
            f"{failed} failed, {result.end_reason}"
        )


if __name__ == "__main__":
    try:
        main()
    except frontier_rl.FrontierRLError as exc:  # a bad world, team or failure: one line, no traceback
        print(f"error: {exc}", file=sys.stderr)
        sys.exit(2)
