"""The harder survey of real buildings: SLAM maps with radial streaks, glass, clutter, narrow doors
and floors of up to 100 m, each explored from several random starts by each method.

Runs ``frontier-rl evaluate`` once per map into ``OUT/MAP`` (rerunning resumes), then writes
``OUT/survey.md`` and ``OUT/survey.json``: per map and method the end reasons, the goals given up
by cause, the explorable area left (m², what the robot could have seen on the true map and did not),
the lowest coverage, and the mean time against the map's fastest method; the mean coverage of
the maps' free space against its explorable share (about what an episode can map); and the five worst
episodes (lowest coverage, a time cap first), each run again and drawn into ``OUT/worst/`` (the
picture of ``frontier-rl explore --png``: the explorable space left unseen in amber), with where
that space lies and how near the robot's path came to it.

    .venv/bin/python experiments/harder_survey.py --episodes 5 --out results/harder_survey
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
from collections import Counter, defaultdict
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from statistics import mean

import numpy as np

from frontier_rl.api import explore, load_world
from frontier_rl.atomic_write import write_text_atomic
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.leg_result import AbortCause
from frontier_rl.core.world.grid import CellState
from frontier_rl.evaluation.results.episode_record import EpisodeRow, EpisodeTrace
from frontier_rl.recording import EpisodeRecorder, UnseenPlace
from frontier_rl.world_spec import world_name

MAPS = (
    "aws_bookstore",
    "willow_full",
    "willow_2010",
    "gdc_3ne",
    "gdc_3",
    "stata_basement",
    "ipa_office",
    "ipa_plant",
    "adblab",
    "brsu_c069",
    "nav2_depot",
    "aws_small_house",
    "uom_floor3",
    "elsabot_home",
    "slam_building",
)
"""Catalogue maps with what real SLAM maps have (``nav2_depot`` and ``aws_small_house`` from the first
survey, for reference; ``uom_floor3`` and ``elsabot_home`` saved by Nav2), and the ``slam_building``
generator: a building floor with a SLAM map's streaks, specks and rough walls, a new one for every
start."""
METHODS = "nearest,fixed:0.75,tour,learned:models/model7.zip"
WORST = 5


@dataclass(frozen=True)
class Episode:
    """One episode of the survey, from its row and trace."""

    world: str
    method: str
    seed: int
    end_reason: str
    coverage: float
    sim_time_s: float
    explorable_left_m2: float
    aborts: Counter[str]
    with_path_left: int
    with_path_to_space_left: int | None  # None in traces from before the count
    explorable_given_up_m2: float | None  # None in traces from before the audit on the true map
    with_path_on_map_left: int | None  # None in traces from before the count
    unrevealable_left: int
    free_coverage: float


def run_map(frontier_rl: Path, world: str, methods: str, episodes: int, out: Path, workers: int | None) -> None:
    """``evaluate`` on one map (no oracle: the survey asks how episodes end, not how far from optimal)
    into the folder ``out``."""
    command = [
        str(frontier_rl),
        "evaluate",
        "--methods",
        methods,
        "--worlds",
        world,
        "--episodes",
        str(episodes),
        "--no-oracle",
        "--baseline",
        methods.split(",")[0],
        "--pictures",
        "0",
        "--out",
        str(out),
    ]
    if workers is not None:
        command += ["--workers", str(workers)]
    subprocess.run(command, check=True)


def named_maps(worlds: list[str]) -> dict[str, str]:
    """Each of ``worlds`` (catalogue names or map files) by its world's name (a map file's stem),
    which names its results folder and its rows of the survey. Two maps of one name exit with an
    error."""
    named: dict[str, str] = {}
    for world in worlds:
        name = world_name(world)
        if name in named:
            sys.exit(f"error: maps {named[name]!r} and {world!r} are both called {name!r}; rename one")
        named[name] = world
    return named


def read_episodes(folder: Path) -> list[Episode]:
    """The episodes of one map's results folder (its rows and traces, read by their codecs)."""
    traces = {}
    for line in (folder / "traces.jsonl").read_text().splitlines():
        trace = EpisodeTrace.from_json(json.loads(line))
        traces[(trace.method, trace.episode)] = trace
    found = []
    for line in (folder / "episodes.csv").read_text().splitlines()[1:]:  # the first is the header
        row = EpisodeRow.from_csv_line(line)
        trace = traces[(row.method, row.episode)]
        found.append(
            Episode(
                row.world,
                row.method,
                row.seed,
                str(row.end_reason),
                row.coverage,
                row.sim_time_s,
                math.nan if trace.explorable_left_m2 is None else trace.explorable_left_m2,
                Counter(trace.aborts_by_cause),
                trace.frontiers_with_path_left or 0,
                trace.frontiers_with_path_to_space_left,
                trace.explorable_given_up_m2,
                trace.frontiers_with_path_on_map_left,
                trace.frontiers_unrevealable_left or 0,
                row.free_coverage,
            )
        )
    return found


def explorable_share(world: str, seeds: list[int]) -> float:
    """About the most of ``world``'s free space an episode can map, over the starts drawn with
    ``seeds`` (mean): the share of the map's free cells that are explorable (their centre in sight,
    within the mapping range, of a cell the robot can reach from its start), with the simulator's
    robot and sensor. A map whose free space lies partly behind gaps narrower than the robot, or
    whose file stores its unknown as free, has a share below 1. An episode may map a little more
    (on 11 of 12 real buildings 0.02-0.7 points of the free space more, mean per map): beams clip
    the corners of cells whose centre no reachable cell sees."""
    config = SimConfig()
    shares = []
    for seed in seeds:
        loaded = config.fit_world(load_world(world, seed))
        free = int(np.count_nonzero(loaded.grid.data == CellState.FREE))
        shares.append(loaded.explorable_count / max(free, 1))
    return mean(shares)


def table(episodes: list[Episode], shares: dict[str, float]) -> tuple[str, list[dict[str, object]]]:
    """The per-map, per-method table (Markdown) and its rows; ``shares``: each map's
    :func:`explorable_share`."""
    rows = _rows(episodes)
    lines = [
        "| map | method | episodes | explored | unreachable | time cap | >= 99 % | unreachable, a path left "
        "| of them, to space left | of them, on the map as built | explorable given up (m², most) "
        "| unrevealable frontiers left | aborts by cause | explorable left (m², mean) | coverage min "
        "| time / fastest |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|",
    ]
    for row in rows:
        causes = ", ".join(f"{k} {v}" for k, v in sorted(row["aborts"].items()) if v) or "none"  # type: ignore[attr-defined]
        lines.append(
            f"| {row['map']} | {row['method']} | {row['episodes']} | {row['explored']} | {row['unreachable']} "
            f"| {row['time_cap']} | {row['at_99']} | {row['unreachable_with_a_path']} "
            f"| {_shown(row['unreachable_with_a_path_to_space'])} "
            f"| {_shown(row['unreachable_with_a_path_on_map'])} | {_shown(row['explorable_given_up_m2_max'])} "
            f"| {row['unrevealable_left']} | {causes} "
            f"| {row['explorable_left_m2']} | {row['min_coverage']:.2%} | {row['time_over_fastest']} |"
        )
    return "\n".join(lines) + "\n\n" + _closing_line(episodes, shares) + "\n", rows


def _rows(episodes: list[Episode]) -> list[dict[str, object]]:
    """The table's rows, per map and method."""
    groups: dict[tuple[str, str], list[Episode]] = defaultdict(list)
    for episode in episodes:
        groups[(episode.world, episode.method)].append(episode)
    fastest = {w: min(mean(e.sim_time_s for e in g) for (w2, _), g in groups.items() if w2 == w) for w, _ in groups}
    rows: list[dict[str, object]] = []
    for (world, method), group in groups.items():
        reasons = Counter(e.end_reason for e in group)
        aborts = {cause.value: sum(e.aborts[cause.value] for e in group) for cause in AbortCause}
        rows.append(
            {
                "map": world,
                "method": method,
                "episodes": len(group),
                **{r: reasons[r] for r in ("explored", "unreachable", "time_cap")},
                "at_99": sum(e.coverage >= 0.99 for e in group),
                "unreachable_with_a_path": sum(e.end_reason == "unreachable" and e.with_path_left > 0 for e in group),
                "unreachable_with_a_path_to_space": _counted(group, "with_path_to_space_left"),
                "unreachable_with_a_path_on_map": _counted(group, "with_path_on_map_left"),
                "explorable_given_up_m2_max": _most_given_up(group),
                "unrevealable_left": sum(e.unrevealable_left for e in group),
                "aborts": aborts,
                "explorable_left_m2": round(mean(e.explorable_left_m2 for e in group), 2),
                "min_coverage": round(min(e.coverage for e in group), 4),
                "time_over_fastest": round(mean(e.sim_time_s for e in group) / fastest[world], 2),
            }
        )
    return rows


def _closing_line(episodes: list[Episode], shares: dict[str, float]) -> str:
    """The survey in one paragraph: coverage, caps, the audit's counts and the free space mapped
    against its explorable share."""
    given_up = [e.explorable_given_up_m2 for e in episodes]
    on_truth = (
        "n/a"
        if None in given_up
        else f"{sum(m > 0 for m in given_up if m is not None)} episodes gave up explorable space with a path "
        f"({max(m for m in given_up if m is not None):.2f} m² the most)"
    )
    return (
        f"All {len(episodes)} episodes: {sum(e.coverage >= 0.99 for e in episodes)} at 99 % of the explorable "
        f"space or more, {sum(e.end_reason == 'time_cap' for e in episodes)} at the time cap, "
        f"{sum(e.end_reason == 'unreachable' and e.with_path_left > 0 for e in episodes)} ended unreachable with "
        f"a path left on their own map ({_shown(_counted(episodes, 'with_path_to_space_left'))} of them to a frontier "
        "that leaves space, the others only to frontiers whose unknown side is wall on the true map; "
        f"{_shown(_counted(episodes, 'with_path_on_map_left'))} on the normal costmap, through the walls "
        "as mapped, the others only through walls the narrow-passage recovery thinned); on the true map, "
        f"{on_truth}; mean coverage {mean(e.coverage for e in episodes):.4f}; mean coverage of the maps' free "
        f"space {mean(e.free_coverage for e in episodes):.4f}, against its explorable share of "
        f"{mean(shares[e.world] for e in episodes):.4f} (the free cells whose centre a cell the robot can reach "
        "sees within the mapping range; beams that clip the corners of the others map a little more)."
    )


def _most_given_up(episodes: list[Episode]) -> float | None:
    """The most explorable space (m²) an episode gave up with a path; None when a trace predates it."""
    given_up = [e.explorable_given_up_m2 for e in episodes]
    return None if None in given_up else round(max(m for m in given_up if m is not None), 2)


def _counted(episodes: list[Episode], count: str) -> int | None:
    """The episodes that ended ``unreachable`` with one or more of the frontiers ``count`` names
    (an :class:`Episode` attribute: those with a path that leave space, or with a path on the
    normal costmap); None when a trace predates the count."""
    counts = [getattr(e, count) for e in episodes]
    if any(n is None for n in counts):
        return None
    return sum(e.end_reason == "unreachable" and n > 0 for e, n in zip(episodes, counts, strict=True))


def _shown(count: object) -> str:
    return "n/a" if count is None else str(count)


@dataclass(frozen=True)
class DrawnEpisode:
    """One of the survey's worst episodes, run again and drawn.

    Attributes:
        episode: the survey's row of it.
        picture: its picture, relative to the survey's folder.
        unseen: where the explorable space it left lies, largest first.
    """

    episode: Episode
    picture: Path
    unseen: list[UnseenPlace]

    def to_json(self) -> dict[str, object]:
        """As ``survey.json`` keeps it (the results page reads it)."""
        e = self.episode
        return {
            "map": e.world,
            "method": e.method,
            "seed": e.seed,
            "end_reason": e.end_reason,
            "coverage": e.coverage,
            "explorable_left_m2": round(e.explorable_left_m2, 2),
            "sim_time_s": e.sim_time_s,
            "picture": self.picture.as_posix(),
            "unseen": [{k: round(v, 2) for k, v in asdict(p).items()} for p in self.unseen],
        }

    def line(self) -> str:
        """As a line of the survey's Markdown."""
        e = self.episode
        places = "; ".join(place.describe() for place in self.unseen)
        return (
            f"- {e.world}, {e.method}, seed {e.seed}: {e.end_reason} at {e.coverage:.2%} of the explorable "
            f"space, {e.explorable_left_m2:.1f} m² left, {e.sim_time_s:.0f} s; unseen: "
            f"{places or 'no piece of 0.25 m² or more'} ({self.picture.as_posix()})"
        )


def draw_worst(episodes: list[Episode], maps: dict[str, str], out: Path) -> list[DrawnEpisode]:
    """The :data:`WORST` episodes (a time cap first, then the lowest coverage), run again and drawn
    into ``OUT/worst/`` (what ``frontier-rl explore --png`` draws), each with where the explorable
    space it left lies (:meth:`~frontier_rl.recording.EpisodeRecorder.unseen_places`); ``maps``:
    each world's name (a map file's stem) and the map as given. Exits with an error if an episode run
    again does not end as the survey's did (the engine changed since: run the survey again)."""
    worst = sorted(episodes, key=lambda e: (e.end_reason != "time_cap", e.coverage))[:WORST]
    (out / "worst").mkdir(parents=True, exist_ok=True)
    drawn = []
    for e in worst:
        world = load_world(maps[e.world], e.seed)
        recorder = EpisodeRecorder(world)
        result = explore(world, e.method, seed=e.seed, on_decision=recorder)
        same_time = abs(result.sim_time_s - e.sim_time_s) <= 0.1  # the table's rounding
        if str(result.end_reason) != e.end_reason or abs(result.coverage - e.coverage) > 1e-4 or not same_time:
            sys.exit(
                f"error: {e.world} {e.method} seed {e.seed} ran again to {result.end_reason} at "
                f"{result.coverage:.4f} in {result.sim_time_s:.1f} s, not as surveyed ({e.end_reason}, "
                f"{e.coverage:.4f}, {e.sim_time_s:.1f} s): the engine changed since; run the survey again"
            )
        picture = Path("worst") / f"{e.world}-{e.method.replace(':', '_').replace('/', '_')}-{e.seed}.png"
        recorder.save_png(out / picture, result, f"{e.world} / {e.method} / seed {e.seed}")
        drawn.append(DrawnEpisode(e, picture, recorder.unseen_places(result)))
    return drawn


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--maps", default=",".join(MAPS), help="comma-separated catalogue maps or map files")
    parser.add_argument("--methods", default=METHODS)
    parser.add_argument("--episodes", type=int, default=5, help="random starts per map")
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    frontier_rl = Path(sys.executable).with_name("frontier-rl")
    maps = named_maps([m.strip() for m in args.maps.split(",") if m.strip()])
    for name, world in maps.items():
        run_map(frontier_rl, world, args.methods, args.episodes, args.out / name, args.workers)
    episodes = [replace(e, world=name) for name in maps for e in read_episodes(args.out / name)]
    shares = {
        name: explorable_share(world, sorted({e.seed for e in episodes if e.world == name}))
        for name, world in maps.items()
    }
    markdown, rows = table(episodes, shares)
    drawn = draw_worst(episodes, maps, args.out)
    worst = [d.line() for d in drawn]
    write_text_atomic(args.out / "survey.md", markdown + "\nThe worst episodes:\n\n" + "\n".join(worst) + "\n")
    survey = {"rows": rows, "worst": [d.to_json() for d in drawn], "explorable_shares": shares}
    write_text_atomic(args.out / "survey.json", json.dumps(survey, indent=1) + "\n")
    print(markdown)
    print("\n".join(worst))


if __name__ == "__main__":
    main()
