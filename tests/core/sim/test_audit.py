"""The audit before an episode gives up (issue 58): a goal the robot's map still has a way to gets
its tries again within a budget, and the frontiers left say whether the final map had a path."""

from __future__ import annotations

import numpy as np
import pytest

from frontier_rl.core.frontiers.blacklist import AUDIT_BUDGET, Blacklist
from frontier_rl.core.navigation.thin_walls import Recovery
from frontier_rl.core.sim import look_state
from frontier_rl.core.sim.candidates import Look, find_candidates
from frontier_rl.core.sim.config import UNSEEN_ROOM_M2, SimConfig
from frontier_rl.core.sim.episode import run_episode
from frontier_rl.core.sim.episode_log import completion_reason, leaves_space
from frontier_rl.core.sim.frontiers_left import audit, frontiers_left
from frontier_rl.core.sim.metrics import EndReason, FrontierLeft, explorable_given_up_m2
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.core.world.worlds import make_world
from frontier_rl.policies import make_policy
from tests.core.sim.test_completion import door_world

FREE = np.int8(CellState.FREE)
RES = 0.05
MAX_FAILURES = SimConfig().navigation.max_goal_failures


def test_the_audit_budget_lifts_goals_that_used_their_tries_once_more_and_then_never() -> None:
    state = np.full((40, 40), FREE, np.int8)
    bl = Blacklist(radius=0.25, max_failures=MAX_FAILURES, resolution=RES, origin=(0.0, 0.0))
    goal = np.array([[1.0, 1.0]])
    for _ in range(MAX_FAILURES):
        bl.fail(1.0, 1.0, state)
    bl.retry()
    assert bl.blocked(goal).all()  # used its tries
    bl.retry(AUDIT_BUDGET * MAX_FAILURES)
    assert not bl.blocked(goal).any() and not bl.gave_up()  # the audit's: as many again
    for _ in range(AUDIT_BUDGET * MAX_FAILURES - MAX_FAILURES):
        bl.fail(1.0, 1.0, state)
    bl.retry(AUDIT_BUDGET * MAX_FAILURES)
    assert bl.blocked(goal).all() and bl.gave_up()  # the budget is spent: given up for good


def test_a_goal_reached_twice_in_vain_is_unrevealable_and_the_audit_leaves_it() -> None:
    state = np.full((40, 40), FREE, np.int8)
    bl = Blacklist(radius=0.25, max_failures=MAX_FAILURES, resolution=RES, origin=(0.0, 0.0))
    goal = np.array([[1.0, 1.0]])
    bl.fail(1.0, 1.0, state, reached=True)
    bl.retry()
    assert not bl.blocked(goal).any()  # one visit: tried again once, from wherever the robot then is
    bl.fail(1.0, 1.0, state, reached=True)
    assert bl.history_of(goal) == (MAX_FAILURES, True)
    bl.retry(AUDIT_BUDGET * MAX_FAILURES)
    assert bl.blocked(goal).all()  # the view it was chosen for revealed nothing, twice: not chased again
    assert not bl.gave_up()  # not for want of a way: no look from elsewhere
    bl.fail(2.0, 2.0, state)
    bl.fail(2.0, 2.0, state, reached=True)
    bl.retry(AUDIT_BUDGET * MAX_FAILURES)
    assert not bl.blocked(np.array([[2.0, 2.0]])).any()  # an abort and a visit: the audit tries it again


def test_a_frontier_that_reappears_elsewhere_keeps_its_history() -> None:
    state = np.full((40, 40), FREE, np.int8)
    bl = Blacklist(radius=0.25, max_failures=MAX_FAILURES, resolution=RES, origin=(0.0, 0.0))
    streak = np.column_stack((np.full(5, 1.025), 0.525 + RES * np.arange(5)))  # a frontier along x = 1 m
    bl.fail(0.6, 0.6, state, reached=True, frontier=streak)
    moved = streak + np.array([RES, 2 * RES])  # a cell to the side and two on: the same frontier, its goal 0.5 m away
    bl.fail(1.1, 0.6, state, reached=True, frontier=moved)
    assert len(bl.entries) == 1 and bl.entries[0].visits == 2
    assert bl.blocked(np.array([[0.6, 0.6], [1.1, 0.6], [1.6, 0.6]])).tolist() == [True, True, False]
    assert bl.history_of(moved + np.array([0.0, RES])) == (2, True)
    far = streak + np.array([0.5, 0.0])  # ten cells away: another frontier
    bl.fail(1.6, 0.6, state, frontier=far)
    assert len(bl.entries) == 2 and bl.history_of(far) == (1, False)


def _sim_on_two_rooms() -> ExplorationSimulator:
    grid, start = door_world(0.8)
    return ExplorationSimulator(make_world(grid, "two rooms", start=start), SimConfig(), np.random.default_rng(0))


def _offer_none(monkeypatch: pytest.MonkeyPatch, looks: str) -> None:
    offered = getattr(look_state, looks)
    monkeypatch.setattr(look_state, looks, lambda *args: offered(*args).subset(np.zeros(0, np.int64)))


@pytest.fixture
def no_small_cluster_look(monkeypatch: pytest.MonkeyPatch) -> None:
    """No blind look (:func:`~frontier_rl.core.sim.looks.blind_looks`) and no look into the unknown
    a frontier left opens onto (:func:`~frontier_rl.core.sim.looks.looks_into_unknown_left`): as
    where no small cluster promises enough. Here one at the door's jamb would look into the far
    room, which the robot has not seen, before the looks at the frontiers given up."""
    _offer_none(monkeypatch, "blind_looks")
    _offer_none(monkeypatch, "looks_into_unknown_left")


@pytest.fixture
def no_look_from_elsewhere(monkeypatch: pytest.MonkeyPatch, no_small_cluster_look: None) -> None:
    """Frontiers given up after their tries get no look from elsewhere: as where no viewpoint away
    from the goals tried sees enough of their unknown (:func:`~frontier_rl.core.sim.looks.spent_looks`),
    and no look at a small cluster."""
    _offer_none(monkeypatch, "spent_looks")


def _fail_every_candidate(sim: ExplorationSimulator, times: int) -> None:
    goals = [sim.map().cell_to_world(*cell) for cell in sim.frontiers().goal_cells]
    for x, y in goals:
        for _ in range(times):
            sim.blacklist.fail(x, y, sim.mapper.state)
    sim.refresh()


def test_before_the_frontiers_given_up_the_jambs_small_cluster_gets_a_look_into_the_far_room(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The frontiers given up after their tries open onto the far room; a small cluster at the
    door's jamb that opens onto it too gets a look first, floor seen through it or not."""
    _offer_none(monkeypatch, "blind_looks")
    sim = _sim_on_two_rooms()
    _fail_every_candidate(sim, AUDIT_BUDGET * MAX_FAILURES)
    cand = sim.candidates()
    assert cand.looks is Look.UNKNOWN_LEFT and len(cand.frontiers) and not sim.finished


def test_a_frontier_given_up_after_its_tries_gets_a_look_from_elsewhere_and_is_unrevealable_after_two(
    no_small_cluster_look: None,
) -> None:
    sim = _sim_on_two_rooms()
    before = len(sim.frontiers())
    _fail_every_candidate(sim, MAX_FAILURES)
    assert len(sim.frontiers()) == before  # the audit gave them their tries again
    tried = np.array([sim.map().cell_to_world(*cell) for cell in sim.frontiers().goal_cells])
    _fail_every_candidate(sim, AUDIT_BUDGET * MAX_FAILURES)
    for _ in range(2):  # two looks from elsewhere, each recorded as a visit that revealed nothing
        cand = sim.candidates()
        assert cand.looks is Look.GIVEN_UP and len(cand.frontiers) and not sim.finished
        gaps = np.hypot(*(cand.frontiers.goals[:, None, :] - tried[None, :, :]).transpose(2, 0, 1))
        assert (gaps > sim.blacklist.radius).all()  # from another place than any goal tried
        for i in range(len(cand.frontiers)):
            frontier = cand.grid.cells_to_world(cand.frontiers.cells_of(i))
            sim.blacklist.fail(*cand.frontiers.goals[i], sim.mapper.state, reached=True, frontier=frontier)
        tried = np.vstack((tried, cand.frontiers.goals))
        sim.refresh()
    assert sim.finished
    result = sim.result(0.0)
    assert result.end_reason == "unreachable"  # the far room is left, behind frontiers seen in vain
    assert result.frontiers_with_path_left == 0 and result.frontiers_unrevealable_left > 0


def test_a_frontier_the_map_has_a_way_to_is_retried_after_its_tries_within_the_budget(
    no_look_from_elsewhere: None,
) -> None:
    sim = _sim_on_two_rooms()
    _fail_every_candidate(sim, AUDIT_BUDGET * MAX_FAILURES)
    assert sim.finished
    left = sim.frontiers_left()
    assert left and any(f.has_path for f in left)  # given up although the map has a way
    result = sim.result(0.0)
    assert result.end_reason == "unreachable"
    assert result.frontiers_with_path_left == sum(f.has_path for f in left) > 0
    assert result.summary().to_json()["frontiers_with_path_left"] == result.frontiers_with_path_left
    # a door of 0.8 m: the path runs through the walls as mapped, not only through thinned ones
    assert result.frontiers_with_path_on_map_left == result.frontiers_with_path_left
    assert result.summary().to_json()["frontiers_with_path_on_map_left"] == result.frontiers_with_path_on_map_left
    # the far room is unseen space beside and behind them
    assert result.frontiers_with_path_to_space_left == sum(f.has_path and f.leaves_space for f in left) > 0
    # and the robot could have seen it on the true map: the far room's explorable space, once (but
    # for a few unseen cells no frontier opens onto)
    unseen_m2 = np.count_nonzero(sim.world.explorable & (sim.mapper.state == CellState.UNKNOWN)) * RES**2
    assert 0.99 * unseen_m2 < result.explorable_given_up_m2 <= unseen_m2
    assert result.summary().explorable_given_up_m2 == pytest.approx(result.explorable_given_up_m2, abs=1e-4)


def test_a_frontier_whose_unknown_side_is_wall_leaves_no_space_and_is_not_counted_as_space_given_up(
    no_look_from_elsewhere: None,
) -> None:
    """The same frontiers given up, against a true world in which every cell the robot has not
    seen is wall: they still have a path, but they leave nothing to explore."""
    sim = _sim_on_two_rooms()
    _fail_every_candidate(sim, AUDIT_BUDGET * MAX_FAILURES)
    assert sim.finished
    truth = sim.world.grid.data.copy()
    truth[sim.mapper.state == CellState.UNKNOWN] = CellState.OCCUPIED
    walled = OccupancyGrid(truth, sim.world.grid.resolution, sim.world.grid.origin)
    left = frontiers_left(
        sim.candidates(), walled, sim.pose, sim.config, sim.blacklist, sim.mapper.state, sim.mapper.felt
    )
    assert left and all(f.has_path and not f.leaves_space and f.unseen_free_cells == 0 for f in left)
    assert completion_reason(left) == EndReason.EXPLORED
    assert all(f.leaves_space for f in sim.frontiers_left())  # against the true world: the far room
    assert completion_reason(sim.frontiers_left()) == EndReason.UNREACHABLE
    assert explorable_given_up_m2(left) == 0.0


def test_space_given_up_that_the_robot_could_not_have_seen_on_the_true_map_is_not_explorable_given_up(
    no_look_from_elsewhere: None,
) -> None:
    """The far room left with a path, in a world whose explorable space (what this robot can see
    from where it can go on the true map) leaves it out: space left, none of it explorable."""
    sim = _sim_on_two_rooms()
    _fail_every_candidate(sim, AUDIT_BUDGET * MAX_FAILURES)
    nothing = np.zeros(sim.world.grid.shape, np.bool_)
    args = (sim.candidates(), sim.world.grid, sim.pose, sim.config, sim.blacklist, sim.mapper.state, sim.mapper.felt)
    left = frontiers_left(*args, explorable=nothing)
    assert left and all(f.has_path and f.leaves_space for f in left)
    assert explorable_given_up_m2(left) == 0.0
    assert explorable_given_up_m2(frontiers_left(*args, explorable=sim.world.explorable)) > 1.0


def test_explorable_space_given_up_counts_each_region_once_and_only_behind_frontiers_with_a_path() -> None:
    def left(regions: dict[int, float], has_path: bool = True, unrevealable: bool = False) -> FrontierLeft:
        return FrontierLeft(0.0, 0.0, 5, 5, 5, 0.0125, 2, 1.0, has_path=has_path, unrevealable=unrevealable,
                            explorable_behind=regions)  # fmt: skip

    segments = [left({1: 0.5, 2: 0.25}), left({2: 0.25})]  # two segments of one frontier, both onto region 2
    assert explorable_given_up_m2(segments) == pytest.approx(0.75)
    assert explorable_given_up_m2([*segments, left({3: 9.0}, has_path=False), left({4: 9.0}, unrevealable=True)]) == (
        pytest.approx(0.75)
    )


@pytest.mark.parametrize(
    ("beside", "behind_m2", "leaves"), [(4, 0.0, False), (5, 0.0, True), (0, 0.5, False), (0, 0.51, True)]
)
def test_a_frontier_leaves_space_with_more_than_a_speck_beside_or_a_room_behind(
    beside: int, behind_m2: float, leaves: bool
) -> None:
    assert SimConfig().speck_cells(RES) == 4 and UNSEEN_ROOM_M2 == 0.5
    assert leaves_space(beside, behind_m2, 4) is leaves


@pytest.mark.parametrize(("door_m", "level"), [(0.25, Recovery.HALF_CELL), (0.4, Recovery.NONE)])
def test_the_audit_says_whether_a_path_runs_through_walls_as_mapped(door_m: float, level: Recovery) -> None:
    """A door the robot's map narrowed below its width has a path only on the narrow-passage
    recovery's costmap, whose walls are thinned; a wider one on the normal costmap."""
    grid, start = door_world(door_m)
    data = grid.data.copy()
    data[:, 66:] = CellState.UNKNOWN  # the far room unseen: a frontier beyond the door
    unseen = OccupancyGrid(data, grid.resolution)
    levels = audit(unseen, start, SimConfig(), np.zeros(unseen.shape, np.bool_)).levels.reshape(unseen.shape)
    assert set(levels[:, 64:].ravel().tolist()) == {-1, int(level)}


def _square_left(side: int, views: bool | None = None) -> FrontierLeft:
    """The frontier left round a square of ``side`` x ``side`` unknown cells in the open floor of a
    walled room (3 x 3 m), given up after the audit's budget of failed legs; with ``views``, a goal
    every 0.35 m over the floor failed too, reached and scanned from (True) or not (False)."""
    data = np.full((60, 60), FREE, np.int8)
    data[[0, -1], :] = data[:, [0, -1]] = CellState.OCCUPIED
    data[30 : 30 + side, 30 : 30 + side] = CellState.UNKNOWN
    grid, pose, config = OccupancyGrid(data, RES), Pose(0.5, 0.5, 0.0), SimConfig()
    blacklist = Blacklist(radius=0.25, max_failures=MAX_FAILURES, resolution=RES, origin=(0.0, 0.0))
    offered = find_candidates(grid, pose, config, blacklist, data).frontiers
    assert len(offered) == 1 and config.speck_cells(RES) == 4
    for _ in range(AUDIT_BUDGET * MAX_FAILURES):
        blacklist.fail(*offered.goals[0], data, frontier=grid.cells_to_world(offered.cells_of(0)))
    steps = np.arange(-9, 10) * 0.35  # a lattice through the frontier's goal, none nearer it than 0.35 m
    lattice = offered.goals[0] + np.stack(np.meshgrid(steps, steps), axis=-1).reshape(-1, 2)
    for x, y in lattice[((lattice > 0) & (lattice < 3)).all(axis=1)] if views is not None else ():
        blacklist.fail(x, y, data, reached=views)
    cand = find_candidates(grid, pose, config, blacklist, data)
    assert len(cand.frontiers) == 0
    truth = OccupancyGrid(np.where(data == CellState.UNKNOWN, FREE, data), RES)
    (left,) = frontiers_left(cand, truth, pose, config, blacklist, data, np.zeros(data.shape, np.bool_))
    assert left.has_path and left.path_on_map and left.failures >= AUDIT_BUDGET * MAX_FAILURES
    assert not any(blacklist.unrevealable(entry) for entry in blacklist.entries)  # none reached twice
    return left


@pytest.mark.parametrize(("side", "unrevealable"), [(2, True), (3, False)])
def test_a_frontier_left_with_a_path_whose_unknown_no_look_could_see_more_than_a_speck_of_is_unrevealable(
    side: int, unrevealable: bool
) -> None:
    """Of four cells (a speck) no look from anywhere reveals more than a speck, so the frontier is
    unrevealable, not space given up with a path; of nine, it is not."""
    assert _square_left(side).unrevealable is unrevealable


@pytest.mark.parametrize("reached", [True, False])
def test_a_look_from_where_the_robot_reached_a_goal_and_scanned_is_a_view_had(reached: bool) -> None:
    """Nine unknown cells, and a goal tried every 0.35 m over the floor: where the robot reached
    them and scanned, every look at the square was had (within the blacklist's radius of one) and
    it is unrevealable; where it only failed to get there, the looks are still to have."""
    assert _square_left(3, views=reached).unrevealable is reached


def test_frontiers_behind_a_door_narrower_than_the_robot_have_no_path() -> None:
    grid, start = door_world(0.15)
    result = run_episode(make_world(grid, "door", start=start), make_policy("nearest"), seed=0)
    assert result.end_reason == "unreachable"
    assert result.frontiers_with_path_left == 0  # given up for want of a way, not after tries
    assert all(not f.has_path for f in result.frontiers_left)


def test_find_candidates_retries_within_the_audit_budget_only_when_nothing_else_is_left() -> None:
    data = np.full((60, 60), CellState.UNKNOWN, np.int8)
    data[:, :30] = FREE
    grid = OccupancyGrid(data, RES)
    pose = Pose(0.5, 1.5, 0.0)
    config = SimConfig()
    bl = Blacklist(0.25, MAX_FAILURES, RES, (0.0, 0.0))
    first = find_candidates(grid, pose, config, bl, data)
    for x, y in (grid.cell_to_world(*cell) for cell in first.frontiers.goal_cells):
        for _ in range(MAX_FAILURES):
            bl.fail(x, y, data)
    assert len(find_candidates(grid, pose, config, bl, data).frontiers) == len(first.frontiers)
    for x, y in (grid.cell_to_world(*cell) for cell in first.frontiers.goal_cells):
        for _ in range(AUDIT_BUDGET * MAX_FAILURES):
            bl.fail(x, y, data)
    assert len(find_candidates(grid, pose, config, bl, data).frontiers) == 0


@pytest.mark.parametrize("own_failures", [0, 1, AUDIT_BUDGET * MAX_FAILURES - 1])
def test_a_frontier_blocked_only_by_a_neighbours_failures_gets_the_tries_its_history_leaves(own_failures: int) -> None:
    # a room, and a slot narrower than the robot from it into unknown space: the slot's end is a
    # frontier seen down the slot from a goal in the room, half a metre from it
    data = np.full((60, 80), CellState.OCCUPIED, np.int8)
    data[2:58, 2:30] = FREE
    data[20:40, 35:78] = CellState.UNKNOWN
    data[28:31, 30:38] = FREE  # its last cells open onto the unknown on three sides: a frontier of 7 cells
    grid = OccupancyGrid(data, RES)
    pose, config = Pose(0.5, 1.5, 0.0), SimConfig()
    bl = Blacklist(0.25, MAX_FAILURES, RES, (0.0, 0.0))
    first = find_candidates(grid, pose, config, bl, data)
    assert len(first.frontiers) == 1
    goal = np.asarray(grid.cell_to_world(*first.frontiers.goal_cells[0]))
    cells = grid.cells_to_world(first.frontiers.cells_of(0))
    own, beside = goal - np.array([0.0, 0.1]), goal + np.array([0.0, 0.2])  # its own failed goal; a neighbour's
    assert np.hypot(*(beside - goal)) <= bl.radius < min(np.hypot(*(beside - own)), np.hypot(*(cells - beside).T).min())
    for _ in range(own_failures):
        bl.fail(*own, data, frontier=cells)
    for _ in range(AUDIT_BUDGET * MAX_FAILURES):
        bl.fail(*beside, data, frontier=np.array([[0.2, 2.8]]))  # its tries spent, its frontier elsewhere
    assert bl.history_of(cells) == (own_failures, False) and bl.blocked(goal[None, :]).all()
    again = find_candidates(grid, pose, config, bl, data).frontiers
    assert len(again) == 1 and np.allclose(again.goals[0], goal)  # not given up: its own history leaves a try
    tries = 0
    while len(find_candidates(grid, pose, config, bl, data).frontiers):  # the tries fail too
        bl.fail(*goal, data, frontier=cells)
        tries += 1
        assert tries <= AUDIT_BUDGET * MAX_FAILURES - own_failures  # within the budget its history left
    assert tries >= 1 and bl.history_of(cells)[0] >= AUDIT_BUDGET * MAX_FAILURES


def test_a_frontier_whose_own_history_is_spent_stays_given_up_beside_a_neighbours_goal() -> None:
    data = np.full((60, 80), CellState.OCCUPIED, np.int8)
    data[2:58, 2:30] = FREE
    data[20:40, 35:78] = CellState.UNKNOWN
    data[28:31, 30:38] = FREE
    grid = OccupancyGrid(data, RES)
    pose, config = Pose(0.5, 1.5, 0.0), SimConfig()
    bl = Blacklist(0.25, MAX_FAILURES, RES, (0.0, 0.0))
    first = find_candidates(grid, pose, config, bl, data)
    goal = np.asarray(grid.cell_to_world(*first.frontiers.goal_cells[0]))
    cells = grid.cells_to_world(first.frontiers.cells_of(0))
    for _ in range(MAX_FAILURES):  # visited twice, nothing revealed: unrevealable
        bl.fail(*(goal - np.array([0.0, 0.1])), data, reached=True, frontier=cells)
    for _ in range(AUDIT_BUDGET * MAX_FAILURES):
        bl.fail(*(goal + np.array([0.0, 0.2])), data, frontier=np.array([[0.2, 2.8]]))
    assert bl.history_of(cells) == (MAX_FAILURES, True)
    assert len(find_candidates(grid, pose, config, bl, data).frontiers) == 0
