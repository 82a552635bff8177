"""Does 'done' mean the building is explored? The real-map completion experiment of issue 13.

Runs ``frontier-rl evaluate`` on every ROS, Stage and HouseExpo map of ``--maps`` (default: the
maps the package ships, named in the results by their catalogue names; random starts) and on the
first ``--dungeon`` DungeonMaps of easy, medium and complex (their own starts), then prints per map
family: episodes, end reasons, episodes that ended with a frontier the robot could still have
tried, coverage, mean time and mean time to 99 % of the free space.

    .venv/bin/python experiments/real_maps.py --methods nearest,fixed:0.75 \\
        --episodes 5 --dungeon 20 --out results/real_maps
"""

from __future__ import annotations

import argparse
import csv
import subprocess
import sys
from collections import defaultdict
from pathlib import Path

from frontier_rl.atomic_write import write_text_atomic
from frontier_rl.io.catalogue import MAPS_DIR, catalogue

FAMILIES = {"ros": ("turtlebot3_world", "aws_small_house", "nav2_depot", "nav2_warehouse", "lse_arena")}


def map_files(maps: Path, dungeon: int) -> dict[str, list[Path]]:
    """The map files of each family."""
    ros = [p for name in FAMILIES["ros"] for p in sorted((maps / name).glob("*.yaml"))]
    stage = sorted((maps / "stage").glob("*.yaml"))
    houseexpo = sorted((maps / "houseexpo").glob("*.json"))
    dungeons = {
        f"dungeon_{level}": sorted((maps / "dungeon" / level).glob("img_*.png"), key=lambda p: int(p.stem[4:]))[
            :dungeon
        ]
        for level in ("easy", "medium", "complex")
    }
    return {"ros": ros, "stage": stage, "houseexpo": houseexpo, **dungeons}


def time_to_99(group: list[dict[str, str]]) -> str:
    """The mean sim time (s) at which the episodes of ``group`` first covered 99 % of the free
    space; over those that did, said with their count when some never did ("—" if none did)."""
    reached = [float(r["t99_s"]) for r in group if r["t99_s"] not in ("", "None", "nan")]
    if not reached:
        return "—"
    mean = f"{sum(reached) / len(reached):.0f}"
    return mean if len(reached) == len(group) else f"{mean} ({len(reached)} of {len(group)})"


def family_table(rows: list[dict[str, str]], family_of: dict[str, str]) -> str:
    """A Markdown table per (family, method): completion, end reasons, coverage, time to the end
    and to 99 % of the free space."""
    groups: dict[tuple[str, str], list[dict[str, str]]] = defaultdict(list)
    for row in rows:
        groups[(family_of[row["world"]], row["method"])].append(row)
    lines = [
        "| family | method | episodes | explored | unreachable | time cap | coverage mean / min | "
        "capped-free ≥ 99 % | unseen free left (m², mean) | mean time (s) | mean time to 99 % (s) |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for (family, method), group in sorted(groups.items()):
        reasons = [r["end_reason"] for r in group]
        cov = [float(r["coverage"]) for r in group]
        uncapped = [c for c, r in zip(cov, reasons, strict=True) if r != "time_cap"]
        full = sum(c >= 0.99 for c in uncapped)
        left = sum(float(r["unknown_left_m2"]) for r in group) / len(group)
        time_s = sum(float(r["sim_time_s"]) for r in group) / len(group)
        lines.append(
            f"| {family} | {method} | {len(group)} | {reasons.count('explored')} | {reasons.count('unreachable')} | "
            f"{reasons.count('time_cap')} | {sum(cov) / len(cov):.3f} / {min(cov):.3f} | {full} / {len(uncapped)} | "
            f"{left:.2f} | {time_s:.0f} | {time_to_99(group)} |"
        )
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--maps", type=Path, default=MAPS_DIR, help="the maps folder (default: the package's)")
    parser.add_argument("--methods", default="nearest,fixed:0.75,explore-lite,info-gain")
    parser.add_argument("--episodes", type=int, default=5, help="random starts per ROS/Stage/HouseExpo map")
    parser.add_argument("--dungeon", type=int, default=20, help="DungeonMaps per difficulty (their own start)")
    parser.add_argument("--skip", default="", help="comma-separated map stems to leave out (e.g. warehouse)")
    parser.add_argument("--workers", type=int, default=None, help="episodes run at once (default: every core)")
    parser.add_argument("--config", type=Path, default=None, help="SimConfig YAML (default: the defaults)")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    skip = set(filter(None, args.skip.split(",")))
    families = {k: [p for p in v if p.stem not in skip] for k, v in map_files(args.maps, args.dungeon).items()}
    names = {m.path.resolve(): m.name for m in catalogue().maps}  # the shipped maps by their catalogue names
    frl = Path(sys.executable).with_name("frontier-rl")
    family_of: dict[str, str] = {}
    for family, files in families.items():
        if not files:
            continue
        episodes = 1 if family.startswith("dungeon") else args.episodes
        out = args.out / family
        baseline = args.methods.split(",")[0]
        worlds = ",".join(names.get(p.resolve(), str(p)) for p in files)
        cmd = [str(frl), "evaluate", "--methods", args.methods, "--worlds", worlds,
               "--episodes", str(episodes), "--no-oracle", "--baseline", baseline, "--out", str(out)]  # fmt: skip
        if args.workers is not None:
            cmd += ["--workers", str(args.workers)]
        if args.config is not None:
            cmd += ["--config", str(args.config)]
        subprocess.run(cmd, check=True)
        with (out / "episodes.csv").open() as handle:
            for row in csv.DictReader(handle):
                family_of[row["world"]] = family
    rows = []
    for family in families:
        path = args.out / family / "episodes.csv"
        if path.exists():
            with path.open() as handle:
                rows += list(csv.DictReader(handle))
    table = family_table(rows, family_of)
    write_text_atomic(args.out / "completion.md", table + "\n")
    print(table)


if __name__ == "__main__":
    main()
