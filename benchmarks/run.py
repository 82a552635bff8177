"""Speed benchmarks of the simulator against its speed budget (the target beside each benchmark).

Run as ``python benchmarks/run.py [--quick] [--json PATH]`` (``make bench``). Everything runs in one
process pinned to one core, with numba/OpenMP/BLAS limited to one thread. Each benchmark is warmed up
first, so numba compilation is never timed, and reports the median over repeats. The JSON report is
what the documentation's Speed page is generated from (``experiments/studies.py run speed``); missed
targets are marked but do not change the exit code.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

os.environ.update(dict.fromkeys(("NUMBA_NUM_THREADS", "OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS"), "1"))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # bench this checkout, not an install

import argparse
import gc
import json
import platform
import statistics
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass

import numba
import numpy as np

from benchmarks.startup import bench_startup
from frontier_rl.atomic_write import write_text_atomic
from frontier_rl.core.frontiers.blacklist import Blacklist
from frontier_rl.core.frontiers.detection import detect_frontiers
from frontier_rl.core.frontiers.ranking import rank, weighted_cost
from frontier_rl.core.mapping.mapper import LogOddsMapper
from frontier_rl.core.navigation.costmap import Costmap
from frontier_rl.core.sensing.lidar import Lidar
from frontier_rl.core.sim.candidates import find_candidates
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import DecisionContext, ExplorationPolicy, Ranking, decision_context, run_episode
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.catalog import building_world, generate_world
from frontier_rl.core.world.grid import OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.core.world.worlds import World
from frontier_rl.io.catalogue import MAPS_DIR
from frontier_rl.policies import make_policy

POLICY = "fixed:0.75"
WARMUP_SEED = 10_000  # office world used only to trigger compilation, never timed


@dataclass(frozen=True)
class Row:
    """One line of the results table; ``target`` is None for rows reported without a target."""

    metric: str
    value: float
    unit: str
    target: float | None = None
    higher_is_better: bool = True
    detail: str = ""  # appended to the value (e.g. " / max")

    @property
    def ok(self) -> bool | None:
        """Whether the target is met (None without a target)."""
        if self.target is None:
            return None
        return self.value >= self.target if self.higher_is_better else self.value <= self.target


def fmt(value: float, unit: str) -> str:
    """A value with its unit, with as many digits as its size deserves."""
    text = f"{value:,.0f}" if abs(value) >= 100 else f"{value:.3g}" if abs(value) >= 1 else f"{value:.3f}"
    return f"{text}×" if unit == "×" else f"{text} {unit}"


def timed(fn: Callable[[], object], repeats: int) -> list[float]:
    """Wall time (s) of ``repeats`` calls of ``fn``, after one untimed warm-up call."""
    fn()
    gc.collect()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return times


def random_poses(world: World, n: int, rng: np.random.Generator) -> list[Pose]:
    """``n`` poses on random explorable cells with random headings."""
    rows, cols = np.nonzero(world.explorable)
    pick = rng.integers(0, rows.size, n)
    poses = []
    for r, c in zip(rows[pick], cols[pick], strict=True):
        x, y = world.grid.cell_to_world(float(r), float(c))
        poses.append(Pose(x, y, float(rng.uniform(-np.pi, np.pi))))
    return poses


def bench_lidar(n_poses: int, repeats: int) -> list[Row]:
    """Scans per second, alone and fused with the log-odds map update, on the office world."""
    world = generate_world("office", 0)
    lidar = Lidar(world.grid)
    rng = np.random.default_rng(1)
    poses = random_poses(world, n_poses, rng)

    def scans() -> None:
        for pose in poses:
            lidar.scan(pose, rng)

    def scans_mapped() -> None:
        mapper = LogOddsMapper(world.grid, explorable=world.explorable)
        for pose in poses:
            mapper.integrate_simulated(lidar, pose, rng)

    return [
        Row("LiDAR scans per second (office)", n_poses / statistics.median(timed(scans, repeats)), "scans/s",
            10_000),
        Row("Scan + map update per second (office)",
            n_poses / statistics.median(timed(scans_mapped, repeats)), "scans/s"),
    ]  # fmt: skip


def partial_map(coverage: float) -> tuple[OccupancyGrid, Pose]:
    """The full-size map (250 × 250) of an office episode stopped at ``coverage``, and the pose."""
    world = generate_world("office", 0)
    policy = make_policy(POLICY)
    sim = ExplorationSimulator(world, rng=np.random.default_rng(0))
    rng = np.random.default_rng(0)
    while sim.coverage < coverage and not sim.finished:
        sim.execute(policy.rank(decision_context(sim), rng).order)
    return OccupancyGrid(sim.mapper.state.copy(), world.grid.resolution, world.grid.origin), sim.pose


def bench_frontiers(repeats: int) -> list[Row]:
    """Frontier detection + ranking on a half-explored 250² office map and on a 4 × 4 tiling of it
    (1000²), alone (every cluster accepted) and with the costmap and reachability in front."""
    small, pose = partial_map(0.5)
    width_m, height_m = small.size_m
    big = OccupancyGrid(np.tile(small.data, (4, 4)), small.resolution, small.origin)
    big_pose = Pose(pose.x + width_m, pose.y + height_m, pose.theta)  # same spot in an inner tile
    config = SimConfig()

    rows: list[Row] = []
    for grid, robot, target, n_rep in (
        (small, pose, 1.0, repeats),
        (big, big_pose, 10.0, max(repeats // 8, 5)),
    ):
        label = f"{grid.height}×{grid.width}"

        def detect_rank(grid: OccupancyGrid = grid, robot: Pose = robot) -> int:
            frontiers = detect_frontiers(grid, robot, reachable=None)
            rank(weighted_cost(frontiers, 0.75))
            return len(frontiers)

        def with_reach(grid: OccupancyGrid = grid, robot: Pose = robot) -> None:
            costmap = Costmap.build(grid, config.robot, config.navigation)
            reachable = costmap.reachable_known(grid.world_to_cell(robot.x, robot.y))
            rank(weighted_cost(detect_frontiers(grid, robot, reachable), 0.75))

        n_frontiers = detect_rank()
        ms = 1e3 * statistics.median(timed(detect_rank, n_rep))
        metric = f"Frontier detection + ranking, {label} (half explored, {n_frontiers} frontiers)"
        rows.append(Row(metric, ms, "ms", target, higher_is_better=False))
        ms = 1e3 * statistics.median(timed(with_reach, n_rep))
        rows.append(Row(f"… with costmap + reachability, {label}", ms, "ms", higher_is_better=False))
    return rows


def bench_episodes(n_seeds: int) -> list[Row]:
    """Full office episodes with the fixed-weight policy, one per seed (world and noise)."""
    run_episode(generate_world("office", WARMUP_SEED), make_policy(POLICY), seed=WARMUP_SEED)
    gc.collect()
    results = [run_episode(generate_world("office", s), make_policy(POLICY), seed=s) for s in range(n_seeds)]
    walls = [r.wall_time_s for r in results]
    rtfs = [r.real_time_factor for r in results]
    per_s = [r.decisions / r.wall_time_s for r in results]
    n = f"{n_seeds} office seeds"
    return [
        Row(f"Decisions per second (median, {n})", statistics.median(per_s), "decisions/s", 100),
        Row(f"Episode wall time (median, {n})", statistics.median(walls), "s", 0.5, higher_is_better=False),
        Row("Episode wall time (min / max)", min(walls), "s", detail=f" / {fmt(max(walls), 's')}"),
        Row(f"Real-time factor (median, {n}; aim 2,000×)", statistics.median(rtfs), "×", 1_000),
        Row("Real-time factor (min / max)", min(rtfs), "×", detail=f" / {fmt(max(rtfs), '×')}"),
        Row("Episode sim time (median)", statistics.median(r.sim_time_s for r in results), "s"),
        Row("Episode decisions (median)", statistics.median(r.decisions for r in results), "decisions"),
    ]


def bench_large_map(n_seeds: int, maps: Path) -> list[Row]:
    """Whole episodes on ``nav2_warehouse`` (a SLAM map of 1,006 × 1,674 cells of 0.03 m, read as
    drawn: ``resolve_world`` would resample it to 0.05 m) from random starts: wall time and wall
    time per decision. No rows where ``maps`` (default: the folder of the maps the package ships)
    lacks it."""
    from frontier_rl.core.world.worlds import make_world
    from frontier_rl.io import load_map

    path = maps / "nav2_warehouse" / "warehouse.yaml"
    if not path.is_file():
        print(f"- large-map rows skipped: {path} not found")
        return []
    loaded = load_map(path)
    worlds = [make_world(loaded.grid, "warehouse", rng=np.random.default_rng(s)) for s in range(n_seeds)]
    gc.collect()
    results = [run_episode(world, make_policy(POLICY), seed=s) for s, world in enumerate(worlds)]
    walls = [r.wall_time_s for r in results]
    per_decision = [1e3 * r.wall_time_s / max(r.decisions, 1) for r in results]
    n = f"{n_seeds} starts"
    return [
        Row(f"nav2_warehouse episode wall time (median, {n})", statistics.median(walls), "s",
            higher_is_better=False, detail=f" (max {fmt(max(walls), 's')})"),
        Row(f"nav2_warehouse wall time per decision (median, {n})", statistics.median(per_decision), "ms",
            higher_is_better=False),
        Row("nav2_warehouse episode sim time (median)", statistics.median(r.sim_time_s for r in results), "s"),
    ]  # fmt: skip


def decision_snapshots(world: World, count: int) -> list[tuple[OccupancyGrid, Pose]]:
    """``count`` (map, pose) states spread over a ``nearest`` episode on ``world``: the robot's
    cropped map at a decision, and where it stood."""
    states: list[tuple[OccupancyGrid, Pose]] = []

    def keep(sim: ExplorationSimulator, ctx: DecisionContext, _: Ranking) -> None:
        states.append((ctx.grid, ctx.pose))

    run_episode(world, make_policy("nearest"), seed=0, on_decision=keep)
    step = max(1, len(states) // count)
    return states[step // 2 :: step][:count]


def bench_decisions(n_states: int, repeats: int, model: Path, worlds: dict[str, World] | None = None) -> list[Row]:
    """The work of one decision (the candidates on the robot's map, then the policy's ranking) for
    ``nearest``, the frontier-choice model ``model``, model 7 (``model7.zip`` beside it, when there
    is one) and ``tour``, on ``worlds`` (by label; by default office maps and a 1,000 × 1,000
    building, 50 m × 50 m), each over ``n_states`` map states of a ``nearest`` episode (median). The
    policies run back to back in every repeat, and each ratio to ``nearest`` is the median of the
    repeats' ratios: the machine's speed drifts between repeats far more than within one."""
    if not model.is_file():
        print(f"- decision rows skipped: {model} not found")
        return []
    config = SimConfig()
    policies = {"nearest": make_policy("nearest"), "model 5": make_policy(f"learned:{model}")}
    labels = {"model 5": "Model-5"}
    if (model7 := model.with_name("model7.zip")).is_file():
        policies["model 7"], labels["model 7"] = make_policy(f"learned:{model7}"), "Model-7"
    policies["tour"], labels["tour"] = make_policy("tour"), "`tour`"
    if worlds is None:
        worlds = {"office": generate_world("office", 0),
                  "1,000² building": building_world(np.random.default_rng(0), (50.0, 50.0))}  # fmt: skip
    rows: list[Row] = []
    for label, world in worlds.items():
        states = decision_snapshots(world, n_states)

        def decide(policy: ExplorationPolicy, states: list[tuple[OccupancyGrid, Pose]] = states) -> None:
            for grid, pose in states:
                nav = config.navigation
                blacklist = Blacklist(nav.blacklist_radius, nav.max_goal_failures, grid.resolution, grid.origin)
                cand = find_candidates(grid, pose, config, blacklist, grid.data)
                if len(cand.frontiers):
                    ctx = DecisionContext(grid, cand.frontiers, pose, 0.0, config.lidar.max_range, cand.costmap,
                                          robot_radius=config.robot.radius)  # fmt: skip
                    policy.rank(ctx, np.random.default_rng(0))

        for policy in policies.values():
            decide(policy)  # warm-up
        times: list[dict[str, float]] = []
        for k in range(repeats):  # the policies back to back, on a machine in one state; the order rotates
            pair: dict[str, float] = {}
            names = list(policies)
            for name in names[k % len(names) :] + names[: k % len(names)]:
                start = time.perf_counter()
                decide(policies[name])
                pair[name] = time.perf_counter() - start
            times.append(pair)
        ms = {name: 1e3 * statistics.median(t[name] for t in times) / len(states) for name in policies}
        large = world.grid.shape[0] * world.grid.shape[1] >= 1_000_000  # the bound is for large maps
        rows.append(Row(f"`nearest` decision, {label} (mean of {len(states)} map states)", ms["nearest"], "ms",
                        higher_is_better=False))  # fmt: skip
        for name, shown in labels.items():
            ratio = statistics.median(t[name] / t["nearest"] for t in times)
            bound = 2.0 if large and name == "model 5" else None
            rows += [
                Row(f"{shown} decision, {label}", ms[name], "ms", higher_is_better=False),
                Row(f"{shown} decision over `nearest`'s, {label} (median of {repeats} paired repeats)"
                    + (" (aim ≤ 2 ×)" if bound else ""), ratio, "×", bound, higher_is_better=False),
            ]  # fmt: skip
    return rows


def bench_teams(n_seeds: int) -> list[Row]:
    """Team episodes on office worlds: the wall time of a 4-robot coordinated episode over a
    1-robot episode of the same world and seed (median of the per-seed ratios)."""
    from frontier_rl.swarm import Strategy, TeamConfig, run_team_episode

    policy = make_policy(POLICY)
    four = TeamConfig(robots=4, strategy=Strategy.COORDINATED)
    run_team_episode(generate_world("office", WARMUP_SEED), policy, team=four, seed=WARMUP_SEED)
    gc.collect()
    ratios, walls, speedups = [], [], []
    for seed in range(n_seeds):
        world = generate_world("office", seed)
        alone = run_episode(world, policy, seed=seed)
        team = run_team_episode(world, policy, team=four, seed=seed)
        ratios.append(team.wall_time_s / alone.wall_time_s)
        walls.append(team.wall_time_s)
        speedups.append(alone.sim_time_s / team.sim_time_s)
    n = f"{n_seeds} office seeds"
    return [
        Row(f"4-robot coordinated episode wall time (median, {n})", statistics.median(walls), "s",
            higher_is_better=False),
        Row(f"4-robot / 1-robot episode wall time (median ratio, {n})", statistics.median(ratios), "×", 4.0,
            higher_is_better=False, detail=f" (max {fmt(max(ratios), '×')})"),
        Row(f"4-robot sim-time speed-up over 1 robot (median, {n})", statistics.median(speedups), "×"),
    ]  # fmt: skip


def bench_envs(n_episodes: int) -> list[Row]:
    """Gymnasium env steps (decisions, with the observation encoding) per second on office worlds,
    the action fixed at bin 75 (w = 0.75); episode resets are included."""
    import gymnasium as gym

    import frontier_rl.envs

    rows = []
    for model, size, target in ((4, 64, 100.0), (4, 250, None), (3, 64, None), (5, 64, None)):
        env = gym.make(frontier_rl.env_id(model, size))
        env.reset(seed=0, options={"world_seed": WARMUP_SEED})
        env.step(0)  # compile the path-cost kernel too
        gc.collect()
        steps = 0
        started = time.perf_counter()
        for k in range(n_episodes):
            env.reset(seed=k, options={"world_seed": k})
            done = False
            while not done:
                _, _, terminated, truncated, _ = env.step(75 if model != 5 else 0)
                done = terminated or truncated
                steps += 1
        rate = steps / (time.perf_counter() - started)
        label = f"Env steps per second per core, {frontier_rl.env_id(model, size)} ({n_episodes} office worlds)"
        rows.append(Row(label, rate, "steps/s", target))
    return rows


def bench_processes(repeats: int) -> list[Row]:
    """Whole ``frontier-rl`` processes (start-up included): ``--help`` and an explore on a small map,
    each beside the floor under it."""
    timings = bench_startup(repeats)
    return [Row(metric, value, unit, target, higher_is_better=False) for metric, value, unit, target in timings]


def machine_info() -> dict[str, str]:
    """CPU model, core pinning and library versions."""
    cpu = platform.processor() or "unknown"
    cpuinfo = Path("/proc/cpuinfo")
    if cpuinfo.exists():
        models = [ln.split(":", 1)[1].strip() for ln in cpuinfo.read_text().splitlines() if "model name" in ln]
        cpu = models[0] if models else cpu
    cores = sorted(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else []
    return {
        "cpu": cpu,
        "pinned_to_core": str(cores[0]) if len(cores) == 1 else "not pinned",
        "python": platform.python_version(),
        "numpy": np.__version__,
        "numba": numba.__version__,
        "platform": platform.platform(),
    }


def rounded(value: object, digits: int = 6) -> object:
    """``value`` with every float in it cut to ``digits`` significant digits: a timer's last digits
    are noise, and a JSON file of them reads as if they were not."""
    if isinstance(value, float):
        return float(f"{value:.{digits}g}")
    if isinstance(value, dict):
        return {key: rounded(item, digits) for key, item in value.items()}
    if isinstance(value, list):
        return [rounded(item, digits) for item in value]
    return value


def table(rows: list[Row]) -> str:
    """The results as a Markdown table."""
    lines = ["| metric | value | target | ok? |", "|---|---|---|---|"]
    for row in rows:
        target = "—" if row.target is None else f"{'≥' if row.higher_is_better else '≤'} {fmt(row.target, row.unit)}"
        ok = {None: "—", True: "✅", False: "❌ **MISSED**"}[row.ok]
        lines.append(f"| {row.metric} | {fmt(row.value, row.unit)}{row.detail} | {target} | {ok} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    """Run every benchmark, print the machine info and the table; always returns 0."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--quick", action="store_true", help="fewer repeats and seeds (a smoke run)")
    parser.add_argument("--json", type=Path, metavar="PATH", help="also write the results as JSON")
    parser.add_argument("--maps", type=Path, default=MAPS_DIR,
                        help="the folder holding nav2_warehouse/ (default: the package's maps)")  # fmt: skip
    parser.add_argument("--model", type=Path, default=Path(__file__).resolve().parents[1] / "models" / "model5.zip",
                        help="the frontier-choice model of the decision rows (default models/model5.zip)")  # fmt: skip
    args = parser.parse_args(argv)
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})

    started = time.perf_counter()
    info = machine_info()
    rows = bench_episodes(5 if args.quick else 20)  # first: its warm-up episode compiles everything
    rows = (
        bench_lidar(500 if args.quick else 2_000, 3 if args.quick else 15)
        + bench_frontiers(20 if args.quick else 200)
        + rows
        + bench_large_map(1 if args.quick else 3, args.maps)
        + bench_decisions(6 if args.quick else 20, 3 if args.quick else 9, args.model)
        + bench_teams(3 if args.quick else 10)
        + bench_envs(2 if args.quick else 10)
        + bench_processes(2 if args.quick else 9)
    )
    total = time.perf_counter() - started

    print("\n".join(f"- {key}: {value}" for key, value in info.items()))
    print(f"- benchmark run: {total:.1f} s{' (--quick)' if args.quick else ''}\n")
    print(table(rows))
    missed = [row.metric for row in rows if row.ok is False]
    print(f"\n{len(missed)} target(s) missed" + (": " + "; ".join(missed) if missed else ""))
    if args.json:
        payload = {"machine": info, "quick": args.quick, "runtime_s": total,
                   "results": [asdict(row) | {"ok": row.ok} for row in rows]}  # fmt: skip
        write_text_atomic(args.json, json.dumps(rounded(payload), indent=2, ensure_ascii=False) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
