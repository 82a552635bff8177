"""Does a learned policy hold in buildings it never saw? One paired experiment per family of worlds
against ``nearest``, with the oracle as the reference.

Families: the generators' held-out seeds (``office``, ``rooms``, ``cluttered``, ``building``,
``cave``: seeds from 0 up; training draws seeds from 10⁶ up, and no shipped model saw a cave)
and the DungeonMaps test sets ``dungeon/easy``, ``dungeon/medium`` and ``dungeon/complex`` of the
map catalogue, or the folders ``easy``, ``medium`` and ``complex`` of ``--dungeon`` (never trained
on: training reads ``dungeon/train`` only), the first ``--maps`` maps of each by file name, one
episode each from a random start. Each family's results go to ``OUT/FAMILY`` (a ``frontier-rl evaluate`` folder:
rerunning continues it); the table printed and written to ``OUT/generalisation.json`` holds, per
family and method, the mean time, the reduction against ``nearest`` with its one-tailed paired
t-test, and the time over the oracle's.

    .venv/bin/python experiments/generalisation.py --methods learned:models/model5.zip \
        --episodes 30 --maps 30 --out results/generalisation
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from frontier_rl.atomic_write import write_text_atomic
from frontier_rl.config_files import load_sim_config
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.evaluation.running.evaluate import evaluate
from frontier_rl.evaluation.running.experiment import ExperimentConfig, expand_worlds
from frontier_rl.evaluation.running.methods import ORACLE

GENERATORS = ("office", "rooms", "cluttered", "building", "cave")
DUNGEON_TESTS = ("easy", "medium", "complex")
BASELINE = "nearest"


def families(dungeon: Path | None, maps: int, only: set[str] | None) -> dict[str, tuple[str, ...]]:
    """Family name -> the worlds of its experiment (the DungeonMaps by catalogue name where
    ``dungeon`` is None)."""
    out: dict[str, tuple[str, ...]] = {name: (name,) for name in GENERATORS}
    for level in DUNGEON_TESTS:
        if dungeon is None:
            out[f"dungeon-{level}"] = expand_worlds(f"dungeon/{level}")[:maps]
        elif (dungeon / level).is_dir():
            out[f"dungeon-{level}"] = expand_worlds(str(dungeon / level))[:maps]
        else:
            print(f"- {dungeon / level} not found: dungeon-{level} skipped")
    return {k: v for k, v in out.items() if only is None or k in only}


def family_rows(summary: dict[str, Any], methods: list[str]) -> list[dict[str, Any]]:
    """The table rows of one family's ``summary.json``."""
    table = summary["methods"]
    rows = []
    for method in methods:
        entry = table[method]
        rows.append({
            "method": method, "n": entry["n"], "mean_time_s": entry["mean_time_s"],
            "reduction_vs_nearest_pct": entry["reduction_pct"], "p_one_tailed": entry["p_one_tailed"],
            "oracle_ratio": entry["oracle_ratio"], "explored": entry["end_reasons"]["explored"],
        })  # fmt: skip
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--methods", required=True, help="comma-separated policies to test against nearest")
    parser.add_argument("--episodes", type=int, default=30, help="episodes (seeds 0..N-1) per generator")
    parser.add_argument("--building-episodes", type=int, default=10, help="episodes of the large buildings")
    parser.add_argument("--maps", type=int, default=30, help="DungeonMaps test maps per level (first by name)")
    parser.add_argument(
        "--dungeon", type=Path, default=None, help="a folder of easy/, medium/, complex/ (default: the catalogue's)"
    )
    parser.add_argument("--families", default="", help="comma-separated subset of the families")
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--config", type=Path, default=None, help="SimConfig YAML (default: the defaults)")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()

    tested = [m.strip() for m in args.methods.split(",") if m.strip()]
    methods = [BASELINE, *tested, ORACLE]
    only = {f.strip() for f in args.families.split(",") if f.strip()} or None
    sim = load_sim_config(args.config) if args.config is not None else SimConfig()
    results: dict[str, list[dict[str, Any]]] = {}
    for family, worlds in families(args.dungeon, args.maps, only).items():
        episodes = 1 if family.startswith("dungeon") else args.episodes
        episodes = args.building_episodes if family == "building" else episodes
        config = ExperimentConfig(methods=tuple(methods), worlds=worlds, episodes=episodes, baseline=BASELINE, sim=sim)
        out = args.out / family
        evaluate(config, out, workers=args.workers, command=f"experiments/generalisation.py ({family})")
        results[family] = family_rows(json.loads((out / "summary.json").read_text()), methods)
        for row in results[family]:
            shown = {k: "—" if v is None else f"{v:.3g}" for k, v in row.items() if isinstance(v, float | None)}
            print(f"{family:16s} {row['method']:40s} n={row['n']:3d} {shown['mean_time_s']:>8s} s "
                  f"{shown['reduction_vs_nearest_pct']:>6s} % p={shown['p_one_tailed']:8s} "
                  f"×oracle {shown['oracle_ratio']} explored {row['explored']}/{row['n']}")  # fmt: skip
    write_text_atomic(args.out / "generalisation.json", json.dumps(results, indent=1) + "\n")


if __name__ == "__main__":
    main()
