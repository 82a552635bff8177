"""The results pages of the engine itself: whether real buildings get explored, and its speed."""

from __future__ import annotations

import shutil
from collections import defaultdict
from pathlib import Path
from statistics import mean
from typing import Any

from results_data import Episode, Study, label
from results_format import markdown_table, relative, reproduce_section, seconds

from frontier_rl.recording import UnseenPlace

FAMILY_NAMES = {
    "ros": "ROS map_server maps (SLAM)",
    "stage": "Stage bitmaps",
    "houseexpo": "HouseExpo floor plans",
    "dungeon_easy": "DungeonMaps easy",
    "dungeon_medium": "DungeonMaps medium",
    "dungeon_complex": "DungeonMaps complex",
}


def _method_name(method: str) -> str:
    """A method as a page names it: its label, or its spec as code where it has none."""
    return f"`{method}`" if label(method) == method else label(method)


def _completion_row(name: str, method: str, episodes: list[Episode]) -> list[str]:
    reasons = [e.end_reason for e in episodes]
    coverage = [e.coverage for e in episodes]
    return [
        name,
        _method_name(method),
        str(len(episodes)),
        str(reasons.count("explored")),
        str(reasons.count("unreachable")),
        str(reasons.count("time_cap")),
        f"{100 * mean(coverage):.2f} % / {100 * min(coverage):.2f} %",
        f"{mean(e.unknown_left_m2 for e in episodes):.2f}",
        seconds(mean(e.sim_time_s for e in episodes)),
    ]


COMPLETION_HEADER = (
    "maps",
    "method",
    "episodes",
    "explored",
    "unreachable",
    "time cap",
    "coverage mean / min",
    "unseen area left (m², mean)",
    "mean time (s)",
)


def real_buildings_page(study: Study, images: Path) -> str:
    """Per family of real maps and per method: how the episodes ended and how much was left."""
    family_rows, map_rows = [], []
    order = list(FAMILY_NAMES)
    for part in sorted(study.parts(), key=lambda part: order.index(part) if part in order else len(order)):
        run = study.experiment(part)
        for method in run.summary.methods:
            family_rows.append(_completion_row(FAMILY_NAMES.get(part, part), method, run.of(method)))
        if part == "ros" or part == "stage":
            by_map: dict[tuple[str, str], list[Episode]] = defaultdict(list)
            for episode in run.episodes:
                by_map[(Path(episode.world).stem, episode.method)].append(episode)
            methods = list(run.summary.methods)
            ordered = sorted(by_map.items(), key=lambda item: (item[0][0], methods.index(item[0][1])))
            map_rows += [_completion_row(world, method, group) for (world, method), group in ordered]
    return f"""# Real buildings

Does "done" mean the building is explored? Each map of the catalogue's real maps (the SLAM maps of
ROS map_server, the Stage bitmaps, the HouseExpo floor plans) is explored from several random starts,
and the first DungeonMaps test maps of each level from their own start, by each method. An episode
ends `explored` only when no frontier touches the space the robot can reach; `unreachable` when the
frontiers left could not be reached; `time_cap` when cut by the sim-time cap. Coverage is the share
of the explorable space: the cells a robot of this size can see from the poses it can reach on the
true map ([concepts](../../concepts.md)).

## Per family of maps

{markdown_table(COMPLETION_HEADER, family_rows)}
`unseen area left`: the unknown free area beside the frontiers an episode left.

## Per map

{markdown_table(COMPLETION_HEADER, map_rows)}
{reproduce_section(study)}"""


HARDER_HEADER = (
    "map",
    "method",
    "episodes",
    "explored",
    "unreachable",
    "time cap",
    "≥ 99 %",
    "coverage mean / min",
    "explorable left (m², mean)",
    "unreachable, a path left",
    "of them, to space left",
    "of them, on the map as built",
    "explorable given up (m², most)",
    "legs given up: no path / no progress / detour / not planned",
    "time / fastest",
)
_CAUSES = ("no_path", "no_progress", "detour", "not_planned")


def _count(value: object) -> str:
    """A survey row's count, "n/a" where the data predate it."""
    return "n/a" if value is None else str(value)


def _total(rows: list[dict[str, object]], count: str) -> int | None:
    """``count`` summed over the survey's rows; None when a row predates it."""
    values = [row.get(count) for row in rows]
    return None if None in values else sum(int(str(v)) for v in values)


def harder_buildings_page(study: Study, images: Path) -> str:
    """Per SLAM map of the harder survey and per method: how the episodes ended, how many reached
    99 % of the explorable space, the audit's count, the legs given up by cause and the time against
    the map's fastest method (the survey's own table, ``survey.json``); then the five worst episodes."""
    survey = study.json("survey.json")
    assert isinstance(survey, dict)
    audit = {(str(r["map"]), str(r["method"])): r for r in survey["rows"]}
    rows, runs = [], [study.experiment(part) for part in study.parts()]
    for run in runs:
        for method in run.summary.methods:
            episodes = run.of(method)
            world = Path(episodes[0].world).stem.split("#")[0]
            row = _completion_row(world, method, episodes)
            found = audit[(world, method)]
            given_up = " / ".join(str(found["aborts"][cause]) for cause in _CAUSES)
            at_99 = sum(e.coverage >= 0.99 for e in episodes)
            audited = [
                f"{found['explorable_left_m2']:.2f}",
                str(found["unreachable_with_a_path"]),
                *(_count(found.get(f"unreachable_with_a_path_{part}")) for part in ("to_space", "on_map")),
                _count(found.get("explorable_given_up_m2_max")),
                given_up,
            ]
            rows.append([*row[:6], str(at_99), row[6], *audited, f"{found['time_over_fastest']:.2f}"])
    every = [e for run in runs for e in run.episodes]
    capped = sum(e.end_reason == "time_cap" for e in every)
    at_99 = sum(e.coverage >= 0.99 for e in every)
    with_path = sum(int(r["unreachable_with_a_path"]) for r in survey["rows"])
    to_space, on_map = (_total(survey["rows"], f"unreachable_with_a_path_{part}") for part in ("to_space", "on_map"))
    space = (
        ""
        if to_space is None
        else f" {to_space} of them to a frontier that leaves space to explore (the others only to frontiers "
        "whose unknown side is wall on the true map);"
    )
    split = (
        " on the normal costmap or the narrow-passage recovery's"
        if on_map is None
        else f" {on_map} on the normal costmap, through the walls as mapped (the others only through walls "
        "the narrow-passage recovery thinned)"
    )
    unrevealable = sum(int(r.get("unrevealable_left", 0)) for r in survey["rows"])
    most = [r.get("explorable_given_up_m2_max") for r in survey["rows"]]
    on_truth = (
        ""
        if None in most
        else " On the true map, the most explorable space (what this robot could have seen from where it "
        f"can go) an episode gave up with a path was {max(float(str(m)) for m in most):.2f} m²."
    )
    worst = _worst_episodes(study, survey["worst"], images)
    return f"""# Harder buildings

Real SLAM maps with what such maps have: radial streaks where the laser saw through glass, clutter,
doorways the map narrowed, floors of up to 100 m; two of them (`uom_floor3`, `elsabot_home`) saved
by Nav2 in ROS 2. Each map of the survey
(`experiments/harder_survey.py`) is explored from several random starts by `nearest`, `fixed:0.75`,
`tour` and model 7. The end reasons are those of [Real buildings](real-buildings.md); the goal is
every episode at 99 % or more of the explorable space, and none at the time cap (25 s per m² of
explorable space: about three times what the fastest method takes).

Of the {len(every)} episodes, {at_99} reached 99 % of the explorable space and {capped} met the time
cap; mean coverage {100 * mean(e.coverage for e in every):.2f} %. {with_path} ended `unreachable`
while the audit found a frontier their final map still had a path to, its tries spent:{space}{split};
{unrevealable} frontiers were left as
unrevealable (reached twice and nothing seen, or no more than a speck of their unknown in sight of
anywhere the robot can go but where it has had its view: [concepts](../../concepts.md)).{on_truth}

{markdown_table(HARDER_HEADER, rows)}
`explorable left`: what the robot could have seen on the true map and did not. `unreachable, a
path left`: episodes that ended `unreachable` with such a frontier; `to space left`: of them, those
with such a frontier that leaves space to explore (more unseen free cells beside it than a speck
has, or more than 0.5 m² behind it; the others' unknown side is wall); `on the map as built`: of them,
those with a path on the normal costmap (the others have one only through walls the narrow-passage
recovery thinned, which may not be there: at such gaps the map's cells change between free and wall
from scan to scan, so which episodes end with one changes from run to run whenever a change of the
engine moves the legs before; [research log](../../research-log.md)). `explorable given up`: the
audit on the true map, the most explorable space behind the frontiers left with a path in one
episode: what the robot gave up after its tries and could have seen. `legs given up`: by why the
goal was given up, summed over the episodes. `time / fastest`: the method's mean time over the
fastest method's on the same map.

## The five worst episodes

The lowest coverage, a time cap first, each run again and drawn as `frontier-rl explore --world MAP
--policy METHOD --seed N --png FILE` draws it. Left, the true map with the path driven and, in amber,
the explorable space the robot did not see; right, the map it built, with the frontiers ranked at
its last decision. Under each, the pieces of that space of 0.25 m² or more: where they lie (their
centre, in the map's frame) and how near the robot's path came to them. What these places are,
looked at cell by cell, is in the [research log](../../research-log.md).

{worst}

{reproduce_section(study)}"""


def _worst_episodes(study: Study, worst: list[dict[str, Any]], images: Path) -> str:
    """The survey's worst episodes, each a heading, a line of facts and its picture (copied from the
    study's data into ``images``)."""
    sections = []
    for rank, episode in enumerate(worst, start=1):
        picture = images / f"harder_worst_{rank}.png"
        shutil.copyfile(study.folder / episode["picture"], picture)
        places = "; ".join(UnseenPlace(**place).describe() for place in episode["unseen"])
        title = f"{episode['map']}, {_method_name(episode['method'])}, seed {episode['seed']}"
        alt = f"{episode['map']}, {label(episode['method'])}, seed {episode['seed']}"  # no code span in alt text
        sections.append(
            f"### {title}\n\n`{episode['end_reason']}` at {100 * episode['coverage']:.2f} % of the explorable "
            f"space in {episode['sim_time_s']:.0f} s, {episode['explorable_left_m2']:.1f} m² left. Unseen: "
            f"{places or 'no piece of 0.25 m² or more'}.\n\n![{alt}: the true map and the explorable space "
            f"left unseen, and the robot's map]({relative(picture)})"
        )
    return "\n\n".join(sections)


def _value(row: dict[str, object]) -> str:
    value, unit = float(row["value"]), str(row["unit"])  # type: ignore[arg-type]
    text = f"{value:,.0f}" if abs(value) >= 100 else f"{value:.3g}" if abs(value) >= 1 else f"{value:.3f}"
    return (f"{text}×" if unit == "×" else f"{text} {unit}") + str(row.get("detail", ""))


def _startup_floor(results: list[dict[str, Any]]) -> str:
    """Paragraphs on the floors under a command's process and the commands above them, where the
    benchmark measured both."""

    def row(*words: str) -> dict[str, Any] | None:
        return next((r for r in results if all(word in r["metric"] for word in words)), None)

    def times(command: dict[str, Any], floor: dict[str, Any], paired: dict[str, Any] | None) -> float:
        """The command's ratio to its floor: the benchmark's paired ratio where it measured one."""
        return float(paired["value"]) if paired is not None else command["value"] / floor["value"]

    engine_floor, explore = row("floor:", "numba"), row("explore", "as a process")
    help_floor, help_row = row("floor:", "--help"), row("--help", "as a process")
    text = ""
    if engine_floor is not None and explore is not None:
        explore_times = times(explore, engine_floor, row("explore", "over its floor"))
        text += f"""
No process that runs an episode starts faster than the engine's floor row: importing NumPy, SciPy's
ndimage and numba and setting up numba's compiler target for one cached kernel take
{engine_floor["value"]:.2f} s on this machine, before any of frontier_rl is imported. The small explore
takes {explore["value"]:.2f} s, {explore_times:.2f} × that floor: its own imports,
the loading of its kernels from numba's cache, the world and the episode.
"""
    if help_floor is not None and help_row is not None:
        help_times = times(help_row, help_floor, row("--help", "over its floor"))
        text += f"""
The help's floor row is a typer command line of two commands whose help click lays out as plain
text, as it does for `frontier-rl`: Python and typer alone take {help_floor["value"]:.3f} s on this
machine.
`frontier-rl --help` takes {help_row["value"]:.3f} s, {help_times:.2f} × that floor.
"""
    if row("over its floor") is not None:
        text += """
The four processes run in rounds, one run of each per round, and a command's ratio to its floor is
the median of the rounds' ratios, so that a machine slowing down for a while slows both alike.
"""
    return text + "\n" if text else ""


def speed_page(study: Study, images: Path) -> str:
    """The speed benchmarks against the speed budget."""
    report = study.json("speed.json")
    assert isinstance(report, dict)
    rows = []
    for row in report["results"]:
        target = row["target"]
        goal = "" if target is None else f"{'≥' if row['higher_is_better'] else '≤'} {target:,g} {row['unit']}"
        rows.append([row["metric"], _value(row), goal, {None: "", True: "met", False: "**missed**"}[row["ok"]]])
    machine = report["machine"]
    floor = _startup_floor(report["results"])
    return f"""# Speed

The simulator is the product's engine: an experiment that took the thesis a week in Gazebo should take
minutes. These are the benchmarks of `benchmarks/run.py` (`make bench`): one process pinned to one core,
numba and BLAS on one thread, each benchmark warmed up first so that compilation is never timed,
and the median over repeats.

{markdown_table(("benchmark", "measured", "target", ""), rows)}
{floor}Machine: {machine["cpu"]}, Python {machine["python"]}, NumPy {machine["numpy"]}, numba {machine["numba"]};
the whole benchmark took {seconds(report["runtime_s"])} s.

{reproduce_section(study)}"""
