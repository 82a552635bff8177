"""The results page of multi-robot teams: strategies, policies in teams, a robot that fails."""

from __future__ import annotations

from pathlib import Path

from matplotlib.figure import Figure
from results_data import Study, label
from results_format import markdown_table, p_text, percent, reproduce_section, save, seconds

from frontier_rl.evaluation.results.summary import ExperimentSummary, TeamPoint
from frontier_rl.evaluation.statistics.paired import paired_stats
from frontier_rl.swarm.config import Strategy, TeamMethod


def _mean_with_ci(point: TeamPoint) -> str:
    half = "" if point.ci95_half_s is None else f" ± {seconds(point.ci95_half_s)}"
    return f"{seconds(point.mean_time_s)}{half}"


def _strategies_table(summary: ExperimentSummary) -> str:
    sizes = sorted({p.robots for p in summary.teams})
    strategies = list(dict.fromkeys(p.strategy for p in summary.teams))
    rows = []
    for strategy in strategies:
        points = {p.robots: p for p in summary.teams if p.strategy == strategy}
        rows.append([strategy, *(_mean_with_ci(points[n]) if n in points else "" for n in sizes)])
    header = ("strategy", *(f"{n} robot{'s' if n > 1 else ''} (s)" for n in sizes))
    return markdown_table(header, rows)


def _team_figure(summary: ExperimentSummary) -> Figure:
    fig = Figure(figsize=(6.4, 4.0), layout="constrained")
    ax = fig.subplots()
    for strategy in dict.fromkeys(p.strategy for p in summary.teams):
        points = sorted((p for p in summary.teams if p.strategy == strategy), key=lambda p: p.robots)
        ax.errorbar(
            [p.robots for p in points],
            [p.mean_time_s for p in points],
            yerr=[p.ci95_half_s or 0.0 for p in points],
            marker="o",
            capsize=3,
            label=strategy,
        )
    ax.set_xlabel("robots")
    ax.set_ylabel("mean time to explore (s)")
    ax.set_xticks(sorted({p.robots for p in summary.teams}))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return fig


def _policies_table(study: Study) -> str:
    run = study.experiment("policies")
    methods = list(run.summary.methods)
    parsed = {m: TeamMethod.parse(m) for m in methods}
    written: dict[str, str] = {}  # a policy's canonical text -> as the methods first write it
    for team in parsed.values():
        written.setdefault(team.policy.canonical, str(team.policy))
    policies = list(written)
    sizes = sorted({t.robots or 1 for t in parsed.values()})
    base_policy = policies[0]
    rows = []
    for n in sizes:
        at_size = {t.policy.canonical: m for m, t in parsed.items() if (t.robots or 1) == n}
        base = run.times(at_size[base_policy])
        cells = [str(n), seconds(sum(base) / len(base))]
        for policy in policies[1:]:
            times = run.times(at_size[policy])
            versus = paired_stats(times, base)
            cells.append(
                f"{seconds(sum(times) / len(times))}, {percent(-(versus.reduction_pct or 0.0))} "
                f"(p = {p_text(versus.p_two_tailed)})"
            )
        rows.append(cells)
    header = (
        "robots",
        f"`{label(written[base_policy])}` (s)",
        *(f"{label(written[p])}: s, against `{label(written[base_policy])}`" for p in policies[1:]),
    )
    return markdown_table(
        header, rows, note="Time against the first policy's with the same team size; paired, two-sided t-test."
    )


def _failure_rows(study: Study, without: ExperimentSummary) -> list[list[str]]:
    rows = []
    order = [strategy.value for strategy in Strategy]
    failures = sorted((p for p in study.parts() if p.startswith("fail_")), key=lambda p: order.index(p[len("fail_") :]))
    for part in failures:
        run = study.experiment(part)
        method = next(m for m in run.summary.methods if TeamMethod.parse(m).robots is not None)
        entry = run.summary.methods[method]
        reasons = entry.end_reasons or {}
        same = without.methods.get(method)
        without_s = seconds(same.mean_time_s) if same else "n/a"
        rows.append(
            [
                TeamMethod.parse(method).strategy.value,
                seconds(entry.mean_time_s),
                without_s,
                f"{reasons.get('explored', 0)} / {entry.n}",
            ]
        )
    return rows


def _failure(study: Study) -> tuple[str, str]:
    """The robot and the time (s) of the failure the study's commands name (``--fail ROBOT@SECONDS``)."""
    for command in study.provenance.commands:
        words = command.command.split()
        if "--fail" in words:
            robot, _, at_s = words[words.index("--fail") + 1].partition("@")
            return robot, at_s
    raise ValueError(f"study {study.name} names no --fail")


def teams_page(study: Study, images: Path) -> str:
    """Teams of 1 to 4 robots with each strategy, other policies in teams, and a failing robot."""
    strategies = study.experiment("strategies").summary
    table = _strategies_table(strategies)
    failures = markdown_table(
        ("strategy", "mean time with the failure (s)", "without it (s)", "explored"), _failure_rows(study, strategies)
    )
    robot, at_s = _failure(study)
    figure = save(_team_figure(strategies), images / "teams_sizes.png")
    policy = label(next(iter(strategies.methods)).split("@")[0])
    return f"""# Teams of robots

Every robot has its own LiDAR, map, navigator and blacklist and ranks with the same policy; maps are
merged when robots are within communication range (unlimited here, but for `rendezvous`, which
shares at its meetings). `uncoordinated` robots each rank their own map; `coordinated` robots lower
the utility of frontiers a teammate is heading to (Burgard et al. 2000); `rendezvous` is the
thesis's commander and explorers, which explore alone and meet to merge. Each cell is the mean over
{strategies.episodes} episodes on each of {", ".join(f"`{w}`" for w in strategies.worlds)}, with its
95 % confidence interval; every robot runs `{policy}`.

## Team size and strategy

{table}
![Mean time against team size]({figure})

## Other policies in teams

Coordinated teams of each size, each robot running the policy named.

{_policies_table(study)}
## One robot failing

Three robots; robot {robot} stops for good at {at_s} s and what it had not shared is lost. The others must
still finish the map.

{failures}
{reproduce_section(study)}"""
