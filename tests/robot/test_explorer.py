"""The explorer's decisions (ROS-free): the same exploration as an in-process episode when it
drives the simulated robot, and what it does with failed, stalled and reached goals."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from frontier_rl import api
from frontier_rl.core.navigation.thin_walls import Recovery
from frontier_rl.core.sim.candidates import Look
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import Ranking
from frontier_rl.core.sim.metrics import EndReason
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose, RobotConfig
from frontier_rl.errors import ConfigError
from frontier_rl.policies.registry import make_policy
from frontier_rl.robot.explorer import FrontierExplorer, check_robot_policy
from frontier_rl.robot.explorer_decision import Finished, Goal, GoalStatus
from frontier_rl.robot.explorer_params import DEFAULT_MIN_FRONTIER_SIZE_M, ExplorerParams
from frontier_rl.robot.sim_robot import SimulatedRobot, explore_in_process
from tests.core.sim.test_looks import window_map


def _explore(world_name: str, seed: int, policy: str) -> tuple[Finished, SimulatedRobot, FrontierExplorer]:
    world = api.load_world(world_name, seed)
    robot = SimulatedRobot(world, seed=seed)
    _, policy_rng = np.random.default_rng(seed).spawn(2)
    explorer = FrontierExplorer(make_policy(policy), ExplorerParams(time_cap=robot.sim.max_sim_time), rng=policy_rng)
    return explore_in_process(robot, explorer), robot, explorer


@pytest.mark.parametrize(
    ("world", "seed", "policy"),
    [("office", 3, "nearest"), ("office", 0, "fixed:0.75"), ("rooms", 1, "nearest"), ("cluttered", 2, "nearest")],
)
def test_the_explorer_on_the_simulated_robot_explores_as_an_episode_does(world: str, seed: int, policy: str) -> None:
    finished, robot, explorer = _explore(world, seed, policy)
    episode = api.explore(world, policy, seed=seed)
    assert finished.reason.value == episode.end_reason
    assert robot.result().coverage == pytest.approx(episode.coverage, abs=0.01)
    assert explorer.decisions > 10


def test_an_unreachable_end_names_the_frontiers_left() -> None:
    finished, _, explorer = _explore("cluttered", 2, "nearest")
    assert finished.reason is EndReason.UNREACHABLE
    assert finished.left and finished.unknown_beside_m2 > 0
    assert explorer.goals_given_up > 0
    assert explorer.tick(OccupancyGrid(np.zeros((5, 5), np.int8), 0.05, (0.0, 0.0)), Pose(0.1, 0.1, 0), 1.0) is None


def _corridor() -> OccupancyGrid:
    """A 4 m corridor, its east half unknown."""
    data = np.full((20, 80), CellState.OCCUPIED, np.int8)
    data[4:16, 1:40] = CellState.FREE
    data[4:16, 40:79] = CellState.UNKNOWN
    return OccupancyGrid(data, 0.05, (0.0, 0.0))


def _first_goal(explorer: FrontierExplorer, grid: OccupancyGrid, now: float = 0.0) -> Goal:
    decision = explorer.tick(grid, Pose(0.5, 0.5, 0.0), now)
    assert isinstance(decision, Goal)
    return decision


def test_a_goal_with_no_progress_is_given_up_and_blacklisted() -> None:
    explorer = FrontierExplorer(make_policy("nearest"), ExplorerParams(progress_timeout=5.0))
    grid = _corridor()
    goal = _first_goal(explorer, grid)
    assert explorer.tick(grid, Pose(0.5, 0.5, 0.0), 4.0) is None  # still within the timeout
    again = explorer.tick(grid, Pose(0.5, 0.5, 0.0), 6.0)
    assert explorer.goals_given_up == 1
    # the only frontier was blacklisted: retried at once, as the engine does before it would end
    assert isinstance(again, Goal) and math.hypot(again.x - goal.x, again.y - goal.y) < 0.5


def test_progress_resets_the_timeout() -> None:
    explorer = FrontierExplorer(make_policy("nearest"), ExplorerParams(progress_timeout=5.0))
    grid = _corridor()
    _first_goal(explorer, grid)
    for step in range(1, 8):
        assert explorer.tick(grid, Pose(0.5 + 0.2 * step, 0.5, 0.0), 4.0 * step) is None
    assert explorer.goals_given_up == 0


def _wall_to_go_round() -> OccupancyGrid:
    """A 5 m by 3 m room halved by a wall open at its east end, the west end of its north half unknown."""
    data = np.full((60, 100), CellState.OCCUPIED, np.int8)
    data[2:58, 2:98] = CellState.FREE
    data[28:32, :80] = CellState.OCCUPIED
    data[45:58, 2:20] = CellState.UNKNOWN
    return OccupancyGrid(data, 0.05, (0.0, 0.0))


def test_progress_along_the_way_round_a_wall_resets_the_timeout() -> None:
    # driving east to the wall's end takes the robot away from its goal in the north-west
    explorer = FrontierExplorer(make_policy("nearest"), ExplorerParams(progress_timeout=5.0))
    grid = _wall_to_go_round()
    goal = _first_goal(explorer, grid)
    assert goal.y > 1.6
    poses = [Pose(0.5 + 0.4 * step, 0.5, 0.0) for step in range(1, 9)]
    assert math.hypot(goal.x - poses[-1].x, goal.y - poses[-1].y) > math.hypot(goal.x - 0.5, goal.y - 0.5) + 1.5
    for step, pose in enumerate(poses, start=1):
        assert explorer.tick(grid, pose, 3.0 * step) is None
    assert explorer.goals_given_up == 0
    decisions = [explorer.tick(grid, poses[-1], now) for now in (27.0, 30.0)]  # standing still
    assert explorer.goals_given_up == 1 and isinstance(decisions[-1], Goal)


def test_progress_along_the_way_counts_when_the_goal_cell_itself_is_inflated_over() -> None:
    # a speck mapped beside the goal after the decision: the way ends a cell or two short of the
    # goal, within the robot's reach of it, and driving round the wall is still progress
    explorer = FrontierExplorer(make_policy("nearest"), ExplorerParams(progress_timeout=5.0))
    goal = _first_goal(explorer, _wall_to_go_round())
    specked = _wall_to_go_round()
    row, col = specked.world_to_cell(goal.x, goal.y)
    specked.data[row - 2, col] = CellState.OCCUPIED
    for step in range(1, 9):
        assert explorer.tick(specked, Pose(0.5 + 0.4 * step, 0.5, 0.0), 3.0 * step) is None
    assert explorer.goals_given_up == 0


def test_progress_made_before_the_robot_stuck_is_not_counted_again_along_the_way() -> None:
    explorer = FrontierExplorer(make_policy("nearest"), ExplorerParams(progress_timeout=5.0))
    grid = _corridor()
    _first_goal(explorer, grid)
    for now in range(1, 6):  # 0.3 m nearer each second, then stuck
        assert explorer.tick(grid, Pose(0.5 + 0.3 * now, 0.5, 0.0), float(now)) is None
    stuck = Pose(2.0, 0.5, 0.0)
    assert all(explorer.tick(grid, stuck, float(now)) is None for now in range(6, 11))
    assert isinstance(explorer.tick(grid, stuck, 11.0), Goal) and explorer.goals_given_up == 1


def _walled_off(door_open: bool) -> OccupancyGrid:
    """A 4 m corridor below a wall, open at its east end (``door_open``) onto a room whose north is unknown."""
    data = np.full((140, 80), CellState.OCCUPIED, np.int8)
    data[2:18, 2:78] = CellState.FREE
    data[26:110, 2:78] = CellState.FREE
    data[110:138, 2:78] = CellState.UNKNOWN
    if door_open:
        data[18:26, 68:78] = CellState.FREE
    return OccupancyGrid(data, 0.05, (0.0, 0.0))


def test_nearer_to_where_the_way_ends_is_no_progress_once_the_map_walls_the_goal_off() -> None:
    # the door drawn shut after the goal was chosen: the way now ends in the corridor below the
    # goal; driving along the corridor shortens that way but leaves the goal as far in a straight line
    explorer = FrontierExplorer(make_policy("nearest"), ExplorerParams(progress_timeout=5.0))
    goal = explorer.tick(_walled_off(door_open=True), Pose(2.5, 0.5, 0.0), 0.0)
    assert isinstance(goal, Goal) and goal.y > 5.0
    closed = _walled_off(door_open=False)
    below = Pose(goal.x, 0.5, 0.0)
    assert math.hypot(goal.x - 2.5, goal.y - 0.5) - math.hypot(goal.x - below.x, goal.y - below.y) < 0.1
    assert abs(below.x - 2.5) > 0.4  # the way along the corridor, shorter by more than progress_distance
    assert explorer.tick(closed, Pose((2.5 + below.x) / 2, 0.5, 0.0), 3.0) is None
    end = explorer.tick(closed, below, 5.5)
    assert explorer.goals_given_up == 1
    assert isinstance(end, Finished) and end.reason is EndReason.UNREACHABLE


def test_a_goal_whose_frontier_is_seen_is_replaced() -> None:
    explorer = FrontierExplorer(make_policy("nearest"))
    grid = _corridor()
    _first_goal(explorer, grid)
    seen = grid.data.copy()
    seen[4:16, 40:60] = CellState.FREE
    decision = explorer.tick(OccupancyGrid(seen, 0.05, (0.0, 0.0)), Pose(1.5, 0.5, 0.0), 1.0)
    assert isinstance(decision, Goal) and decision.x > 2.5
    assert explorer.goals_given_up == 0


@pytest.mark.parametrize("paused_after", [False, True])
def test_a_goal_reached_with_its_frontier_unseen_is_blacklisted(paused_after: bool) -> None:
    """Also when a pause comes after the goal was reached and before the tick
    that judges it: that forgot the goal, and its unrevealable frontier was chosen again and again."""
    explorer = FrontierExplorer(make_policy("nearest"))
    grid = _corridor()
    goal = _first_goal(explorer, grid)
    explorer.goal_reached()
    if paused_after:
        explorer.goal_lost()
    explorer.tick(grid, Pose(goal.x, goal.y, 0.0), 1.0)
    assert explorer.goals_given_up == 1


@pytest.mark.parametrize("then", ["tick", "time cap", "stop"])
def test_a_goal_aborted_is_judged_on_the_map_after_it_or_at_the_end(then: str) -> None:
    """A node's map lags the robot: an aborted goal is judged on a map from after its end, at the
    next tick, or as the run ends before one (the time cap, a stop): a frontier that map shows seen
    is dropped, one it still shows given up (the time cap ended the run with it not counted)."""
    grid = _corridor()
    seen = OccupancyGrid(grid.data.copy(), grid.resolution, grid.origin)
    seen.data[4:16, 40:79] = CellState.FREE  # the east half mapped on the way
    seen.data[4:16, 78] = CellState.OCCUPIED
    for later, given_up in ((seen, 0), (grid, 1)):
        explorer = FrontierExplorer(make_policy("nearest"), ExplorerParams(time_cap=10.0))
        _first_goal(explorer, grid)
        explorer.goal_aborted()
        assert explorer.goal is not None and explorer.goals_given_up == 0  # not judged yet
        if then == "tick":
            explorer.tick(later, Pose(1.0, 0.5, 0.0), 1.0)
        elif then == "time cap":
            assert isinstance(explorer.tick(later, Pose(1.0, 0.5, 0.0), 10.0), Finished)
        else:
            explorer.judge_abort(later)
        assert explorer.goals_given_up == given_up, (then, given_up)


def test_a_goal_lost_on_the_way_is_not_held_against_its_frontier() -> None:
    explorer = FrontierExplorer(make_policy("nearest"))
    grid = _corridor()
    goal = _first_goal(explorer, grid)
    explorer.goal_lost()
    again = explorer.tick(grid, Pose(0.5, 0.5, 0.0), 1.0)
    assert explorer.goals_given_up == 0
    assert isinstance(again, Goal) and (again.x, again.y) == (goal.x, goal.y)


def test_a_map_that_grows_keeps_the_blacklist_in_place() -> None:
    """A SLAM map grows, and its origin moves: the failed goal stays where it was in the world."""
    explorer = FrontierExplorer(make_policy("nearest"))
    grid = _corridor()
    goal = _first_goal(explorer, grid)
    explorer.goal_failed(grid)
    grown = np.full((30, 90), CellState.UNKNOWN, np.int8)
    grown[10:30, 10:90] = grid.data
    moved = OccupancyGrid(grown, 0.05, (-0.5, -0.5))
    assert explorer._blacklist is not None
    explorer._blacklist_for(moved)
    assert explorer._blacklist.blocked(np.array([[goal.x, goal.y]]))[0]


def test_the_time_cap_ends_exploration() -> None:
    explorer = FrontierExplorer(make_policy("nearest"), ExplorerParams(time_cap=10.0))
    grid = _corridor()
    _first_goal(explorer, grid)
    end = explorer.tick(grid, Pose(0.5, 0.5, 0.0), 10.0)
    assert isinstance(end, Finished) and end.reason is EndReason.TIME_CAP
    assert len(end.left) == 1 and end.unknown_beside_m2 > 0


def test_return_to_init_goes_back_to_the_first_pose() -> None:
    explorer = FrontierExplorer(make_policy("nearest"), ExplorerParams(return_to_init=True))
    grid = _corridor()
    _first_goal(explorer, grid)
    home = explorer.home(grid, Pose(1.5, 0.5, 0.0))
    assert home is not None and (home.x, home.y) == (0.5, 0.5) and len(home.frontier) == 0 and home.path is None


def rooms_with_a_narrow_door() -> OccupancyGrid:
    """Two 2.3 m rooms, mapped, through a wall with a door of 0.2 m: closed on the normal costmap,
    open on the narrow-passage recovery's half-cell level."""
    data = np.full((60, 100), CellState.OCCUPIED, np.int8)
    data[2:58, 2:98] = CellState.FREE
    data[:, 49:51] = CellState.OCCUPIED
    data[28:32, 49:51] = CellState.FREE
    return OccupancyGrid(data, 0.05, (0.0, 0.0))


@pytest.mark.parametrize("recovery_paths", [True, False])
def test_the_way_home_through_a_door_too_narrow_for_the_normal_costmap_is_a_path(recovery_paths: bool) -> None:
    explorer = FrontierExplorer(make_policy("nearest"), ExplorerParams(recovery_paths=recovery_paths))
    grid = rooms_with_a_narrow_door()
    assert explorer.tick(grid, Pose(1.0, 1.5, 0.0), 0.0) is not None
    home = explorer.home(grid, Pose(4.0, 1.5, 0.0))
    assert home is not None and (home.x, home.y) == (1.0, 1.5)
    if not recovery_paths:
        assert home.path is None and home.recovery is Recovery.NONE
        return
    assert home.path is not None and home.recovery is Recovery.HALF_CELL
    assert math.dist(home.path[0], (4.0, 1.5)) < 0.1 and math.dist(home.path[-1], (1.0, 1.5)) < 0.05
    assert np.all(np.abs(home.path[:, 1] - 1.5) < 0.6)  # through the door, at y = 1.4-1.6 m
    near = explorer.home(grid, Pose(2.0, 1.0, 0.0))  # in the same room: a point goal
    assert near is not None and (near.x, near.y, near.path, near.recovery) == (1.0, 1.5, None, Recovery.NONE)


def test_the_way_home_to_a_start_drawn_over_takes_the_wide_door() -> None:
    # a dock drawn on the start: the normal costmap's way ends beside it, not through the narrow door
    grid = rooms_with_a_narrow_door()
    grid.data[8:50, 49:51] = CellState.FREE  # a wide door as well, north of the narrow one
    explorer = FrontierExplorer(make_policy("nearest"))
    assert explorer.tick(grid, Pose(1.0, 1.5, 0.0), 0.0) is not None
    grid.data[28:33, 18:23] = CellState.OCCUPIED
    home = explorer.home(grid, Pose(4.0, 1.5, 0.0))
    assert home is not None and home.path is None and home.recovery is Recovery.NONE


def _door_drawn_too_narrow() -> tuple[OccupancyGrid, SimConfig]:
    """Two rooms, the west one mapped, through a wall with a door its map draws 0.2 m wide, for a
    robot of 0.2 m radius (it came through the door, which is wider): closed on every costmap
    level; the east room's far end (11-12 m) unknown."""
    data = np.full((80, 240), CellState.OCCUPIED, np.int8)
    data[2:78, 2:238] = CellState.FREE
    data[:, 60:64] = CellState.OCCUPIED
    data[38:42, 60:64] = CellState.FREE
    data[2:78, 220:238] = CellState.UNKNOWN
    return OccupancyGrid(data, 0.05, (0.0, 0.0)), SimConfig(robot=RobotConfig(radius=0.2))


@pytest.mark.parametrize("came_through", [True, False])
def test_the_way_the_robot_came_stays_open_when_its_map_closes_the_door_behind_it(came_through: bool) -> None:
    grid, config = _door_drawn_too_narrow()
    explorer = FrontierExplorer(make_policy("nearest"), config=config)
    if came_through:
        for x in np.arange(5.0, 1.5, -0.02):  # from the east room through the door
            explorer.passed(Pose(float(x), 2.0, 0.0))
    decision = explorer.tick(grid, Pose(1.5, 2.0, 0.0), 0.0)
    if not came_through:
        assert isinstance(decision, Finished) and decision.reason is EndReason.UNREACHABLE
        return
    assert isinstance(decision, Goal) and decision.recovery is Recovery.HALF_CELL and decision.x > 10.0
    assert decision.path is not None
    through = decision.path[(decision.path[:, 0] > 3.0) & (decision.path[:, 0] < 3.2)]
    assert len(through) and np.all(np.abs(through[:, 1] - 2.0) < 0.1)  # along the way it came


def test_a_policy_that_plans_on_the_true_map_is_refused() -> None:
    with pytest.raises(ConfigError, match="true map"):
        check_robot_policy(make_policy("oracle"), "oracle")
    check_robot_policy(make_policy("fixed:0.75"), "fixed:0.75")


@pytest.mark.parametrize(
    ("field", "value"),
    [("planner_frequency", 0.0), ("progress_timeout", -1.0), ("time_cap", math.nan), ("min_frontier_size", -0.1)],
)
def test_bad_settings_name_the_setting(field: str, value: float) -> None:
    with pytest.raises(ValueError, match=field):
        ExplorerParams(**{field: value})


def test_the_simulated_robot_aborts_a_goal_it_cannot_reach_and_cancels_on_request() -> None:
    robot = SimulatedRobot(api.load_world("office", 3), seed=3)
    robot.send_goal(-50.0, -50.0)
    ends = [robot.step() for _ in range(200)]
    end = next(e for e in ends if e is not None)
    assert end.status is GoalStatus.ABORTED and not robot.busy
    robot.send_goal(robot.pose.x + 1.0, robot.pose.y)
    robot.step()
    robot.cancel()
    assert not robot.busy and robot.step() is None
    with pytest.raises(ValueError, match="not a point"):
        robot.send_goal(math.nan, 0.0)


def _paths_followed(robot: SimulatedRobot, explorer: FrontierExplorer) -> list[tuple[Goal, Pose]]:
    """Record each goal ``robot`` is sent along a path, with where the robot stood."""
    followed: list[tuple[Goal, Pose]] = []
    follow = robot.follow_path

    def record(path: np.ndarray) -> None:
        assert explorer.goal is not None
        followed.append((explorer.goal, robot.pose))
        follow(path)

    robot.follow_path = record  # type: ignore[method-assign]
    return followed


@pytest.mark.parametrize("recovery_paths", [True, False])
def test_a_goal_found_with_the_walls_thinned_goes_with_the_path_planned_there(recovery_paths: bool) -> None:
    """``elsabot_home`` seed 1 starts where the normal costmap reaches only the cell the robot stands
    on: its goals are found on the narrow-passage recovery's levels. A navigation stack planning on
    its normal costmap finds no way to them, and the robot never left its start (7 % mapped); sent
    with the path planned on the level they were found on, followed as Nav2's controller follows
    one, the robot explores the home."""
    world = api.load_world("elsabot_home", 1)
    robot = SimulatedRobot(world, seed=1)
    params = ExplorerParams(time_cap=robot.sim.max_sim_time, recovery_paths=recovery_paths)
    explorer = FrontierExplorer(make_policy("nearest"), params, rng=np.random.default_rng(1))
    followed = _paths_followed(robot, explorer)
    explore_in_process(robot, explorer)
    if not recovery_paths:
        assert not followed and robot.result().coverage < 0.1
        return
    assert robot.result().coverage > 0.99
    goal, pose = followed[0]
    assert goal.recovery is not Recovery.NONE and goal.path is not None
    assert math.hypot(goal.path[0, 0] - pose.x, goal.path[0, 1] - pose.y) < 0.05  # from the robot
    assert tuple(goal.path[-1]) == pytest.approx((goal.x, goal.y))  # to the goal
    assert np.hypot(*np.diff(goal.path, axis=0).T).max() < 0.08  # cell by cell
    renewed = [(g, p) for (f, _), (g, p) in itertools.pairwise(followed) if (g.x, g.y) == (f.x, f.y)]
    assert renewed  # a goal under way is sent again every planner tick, its path planned from where the robot is
    assert all(g.path is not None and math.hypot(g.path[0, 0] - p.x, g.path[0, 1] - p.y) < 0.05 for g, p in renewed)


def test_the_simulated_robot_follows_a_path_its_costmaps_allow_and_aborts_one_they_do_not() -> None:
    robot = SimulatedRobot(api.load_world("office", 3), seed=3)
    cand = robot.sim.navigator.candidates(robot.pose)
    goal_cell = (int(cand.frontiers.goal_cells[0][0]), int(cand.frontiers.goal_cells[0][1]))
    path = cand.grid.cells_to_world(cand.costmap.plan(cand.grid.world_to_cell(robot.pose.x, robot.pose.y), goal_cell))
    robot.follow_path(path)
    assert all(robot.step() is None for _ in range(3))
    leg = robot.sim.leg
    robot.follow_path(path[len(path) // 2 :])  # the same goal's next path: the drive under way takes it
    assert robot.sim.leg is leg and leg is not None and leg.given_path
    end = next(e for e in (robot.step() for _ in range(2000)) if e is not None)
    assert end.status is GoalStatus.SUCCEEDED
    assert math.hypot(robot.pose.x - path[-1, 0], robot.pose.y - path[-1, 1]) < 0.2
    there = (robot.pose.x, robot.pose.y)
    cand = robot.sim.navigator.candidates(robot.pose)
    beyond_a_wall = next(  # a reachable cell whose straight way from the robot crosses a wall of its map
        cand.grid.cell_to_world(int(r), int(c))
        for r, c in np.argwhere(cand.reachable)
        if (
            cand.grid.data[tuple(cand.grid.world_to_cells(np.linspace(there, cand.grid.cell_to_world(r, c), 200)).T)]
            == CellState.OCCUPIED
        ).any()
    )
    off_the_map = (there[0] + 30.0, there[1] + 30.0)
    for goal in (beyond_a_wall, off_the_map):  # two points: the controller would drive the line between them
        robot.follow_path(np.array([there, goal]))
        end = next(e for e in (robot.step() for _ in range(200)) if e is not None)
        assert end.status is GoalStatus.ABORTED
        assert (robot.pose.x, robot.pose.y) == pytest.approx(there)  # a turn on the spot, as for a goal not planned
    for bad in (np.zeros((0, 2)), np.array([[0.0, math.nan]]), np.zeros((3, 3))):
        with pytest.raises(ValueError, match="not a list of points"):
            robot.follow_path(bad)


def test_the_default_frontier_size_is_the_engines_drop_size() -> None:
    from frontier_rl.core.sim.config import DROP_CELL_M, SimConfig

    assert pytest.approx(SimConfig().min_frontier_cells * DROP_CELL_M) == DEFAULT_MIN_FRONTIER_SIZE_M
    assert FrontierExplorer(make_policy("nearest")).config.min_frontier_cells == SimConfig().min_frontier_cells


def test_with_no_frontier_left_the_explorer_takes_the_last_look_through_a_window() -> None:
    """As the simulated robot does (:mod:`frontier_rl.core.sim.looks`): a gap of three cells in a
    wall, through which floor was seen, is too small a frontier, but worth a look; the look lasts
    until the navigation stack ends it, and one that maps nothing is a visit and ends the looks.
    The floor seen through the gap has a frontier no costmap has a way to: before the explorer gives
    up the unknown it opens onto, the gap gets one more look into it, a visit whatever it maps."""
    explorer = FrontierExplorer(make_policy("nearest"))
    grid, pose = window_map(), Pose(0.5, 0.5, 0.0)
    look = explorer.tick(grid, pose, 0.0)
    assert isinstance(look, Goal) and look.look is Look.SMALL and len(look.frontier) > 0
    assert explorer.tick(grid, pose, 1.0) is None  # its cluster is below the drop size: still a look
    assert explorer.judged_on(grid)  # its mapped floor is counted on a map from after it
    explorer.goal_reached()
    into = explorer.tick(grid, Pose(look.x, look.y, 0.0), 2.0)
    assert isinstance(into, Goal) and into.look is Look.UNKNOWN_LEFT and not explorer._looks.looking
    assert {tuple(p) for p in into.frontier} & {tuple(p) for p in look.frontier}  # the same gap
    explorer.goal_reached()
    finished = explorer.tick(grid, Pose(into.x, into.y, 0.0), 3.0)
    assert isinstance(finished, Finished) and explorer.decisions == 2 and explorer.goals_given_up == 0


def test_a_look_that_maps_the_room_behind_the_window_lets_the_exploration_go_on() -> None:
    explorer = FrontierExplorer(make_policy("nearest"))
    grid, pose = window_map(), Pose(0.5, 0.5, 0.0)
    look = explorer.tick(grid, pose, 0.0)
    assert isinstance(look, Goal) and look.look is Look.SMALL
    seen = window_map()
    seen.data[30:50, 62:100] = CellState.FREE  # 760 cells, 1.9 m² of the room behind the gap
    explorer.goal_reached()
    after = explorer.tick(seen, Pose(look.x, look.y, 0.0), 2.0)
    assert isinstance(after, Goal) and after.look is Look.NONE  # the room's frontiers, beyond the gap


def test_floor_mapped_far_from_a_look_is_not_the_looks() -> None:
    """On a merged map a teammate's floor elsewhere (or a SLAM map grown elsewhere) made a look
    that mapped nothing pay, and the looks went on on its word."""
    explorer = FrontierExplorer(make_policy("nearest"))
    grid = window_map()
    look = explorer.tick(grid, Pose(0.5, 0.5, 0.0), 0.0)
    assert isinstance(look, Goal) and look.look is Look.SMALL
    elsewhere = OccupancyGrid(np.pad(window_map().data, ((0, 0), (0, 200)), constant_values=CellState.UNKNOWN), 0.05)
    elsewhere.data[10:70, 250:320] = CellState.FREE  # 10.5 m², more than 3.5 m from the look
    explorer.goal_reached()
    finished = explorer.tick(elsewhere, Pose(look.x, look.y, 0.0), 2.0)
    assert isinstance(finished, Finished) or (
        isinstance(finished, Goal) and finished.look not in (Look.SMALL, Look.BLIND)
    )
    assert not explorer._looks.looking


def test_a_look_the_navigation_stack_gave_up_ends_no_look() -> None:
    """Nav2 plans on its own costmap, where a look found on the recovery's may have no path: the
    first such abort ended every look at the small clusters."""
    explorer = FrontierExplorer(make_policy("nearest"))
    grid, pose = window_map(), Pose(0.5, 0.5, 0.0)
    first = explorer.tick(grid, pose, 0.0)
    assert isinstance(first, Goal) and first.look is Look.SMALL
    explorer.goal_failed(grid)
    second = explorer.tick(grid, pose, 1.0)
    assert isinstance(second, Goal) and second.look is Look.SMALL  # the same cluster, from elsewhere
    assert math.hypot(second.x - first.x, second.y - first.y) > 0.2 and explorer.goals_given_up == 1


@pytest.mark.parametrize("paused_after", [False, True])
def test_a_look_the_navigation_stack_aborted_is_judged_on_the_next_ticks_map(paused_after: bool) -> None:
    """A node's map lags the robot (slam_toolbox's comes every 5 s): a look Nav2 aborted near its
    viewpoint, judged on the map at hand, had mapped nothing yet, and the looks could end. Judged at
    the next tick (after a pause too), on the map that came after the abort, it paid."""
    explorer = FrontierExplorer(make_policy("nearest"))
    grid, pose = window_map(), Pose(0.5, 0.5, 0.0)
    look = explorer.tick(grid, pose, 0.0)
    assert isinstance(look, Goal) and look.look is Look.SMALL
    explorer.goal_aborted()
    if paused_after:
        explorer.goal_lost()
    assert explorer.goal is look and explorer.goals_given_up == 0  # not judged yet
    seen = window_map()
    seen.data[30:50, 62:100] = CellState.FREE  # 1.9 m² of the room behind the gap, on the next map
    after = explorer.tick(seen, Pose(look.x - 0.3, look.y, 0.0), 2.0)
    assert explorer.goals_given_up == 1  # aborted: given up, as the engine gives up such a leg
    assert explorer._looks.confirmed  # a look that paid: on the map at hand it had mapped nothing
    assert isinstance(after, Goal) and after.look is Look.NONE  # the room's frontiers


class _PointPolicy:
    """Drives to a point of its own, as the point models 1 and 2 do."""

    name = "point"

    def rank(self, context: object, rng: np.random.Generator) -> Ranking:
        return Ranking(np.zeros(0, np.int64), goal=(0.5, 0.5))


def test_a_point_policy_among_looks_takes_the_look_nearest_its_point() -> None:
    """Its point goal was no look: no visit was recorded, and the same looks came back for ever."""
    explorer = FrontierExplorer(_PointPolicy())
    grid, pose = window_map(), Pose(0.5, 0.5, 0.0)
    look = explorer.tick(grid, pose, 0.0)
    assert isinstance(look, Goal) and look.look is Look.SMALL and len(look.frontier) > 0
    explorer.goal_reached()
    into = explorer.tick(grid, Pose(look.x, look.y, 0.0), 2.0)  # the gap once more, into the unknown left
    assert isinstance(into, Goal) and into.look is Look.UNKNOWN_LEFT
    explorer.goal_reached()
    assert isinstance(explorer.tick(grid, Pose(into.x, into.y, 0.0), 3.0), Finished)
