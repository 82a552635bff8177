"""A goal reached is judged on a map from after its end, waiting at most two of the map's periods."""

from __future__ import annotations

from frontier_rl.robot.map_watch import MapWait, MapWatch


def _watch(period_s: float, maps: int, stamp_s: float = 0.0, clock_s: float = 1e9) -> MapWatch:
    watch = MapWatch()
    for i in range(maps):
        watch.map_came(i * period_s, stamp_s, clock_s)
    return watch


def test_no_judgement_waits_until_a_goal_ends() -> None:
    assert _watch(1.0, 5).judgement(4.5) is MapWait.READY


def test_a_judgement_waits_for_the_next_map_and_no_longer() -> None:
    watch = _watch(1.0, 5)  # maps at 0..4 s
    assert watch.goal_ended(4.2, 10.0)
    assert watch.judgement(4.9) is MapWait.WAIT
    watch.map_came(5.0, 0.0, 11.0)
    assert watch.judgement(5.01) is MapWait.READY
    assert watch.judgement(5.02) is MapWait.READY  # the wait is over


def test_a_map_that_stopped_before_the_goal_ended_is_said_so() -> None:
    watch = _watch(1.0, 5)  # the last map at 4 s
    assert watch.goal_ended(7.0, 10.0)
    assert watch.judgement(8.9) is MapWait.WAIT
    assert watch.judgement(9.1) is MapWait.STOPPED
    assert watch.judgement(9.2) is MapWait.READY
    assert watch.period_s == 1.0 and round(watch.age_s(9.1), 6) == 5.1 and watch.waits


def test_a_map_that_comes_only_as_the_robot_drives_stops_the_waits_after_two_stands() -> None:
    """gmapping and rtabmap map as the robot moves: standing after a goal, no map comes."""
    watch = _watch(1.0, 5)
    assert watch.goal_ended(4.2, 10.0)
    assert watch.judgement(6.3) is MapWait.QUIET and watch.waits
    for i in range(3):
        watch.map_came(7.0 + i, 0.0, 13.0 + i)  # it drove to the next goal
    assert watch.goal_ended(9.2, 15.2)
    assert watch.judgement(11.3) is MapWait.QUIET and not watch.waits
    assert not watch.goal_ended(12.0, 16.0) and watch.judgement(12.0) is MapWait.READY


def test_a_newer_map_between_quiet_stands_keeps_the_waits() -> None:
    watch = _watch(1.0, 5)
    watch.goal_ended(4.2, 10.0)
    assert watch.judgement(6.3) is MapWait.QUIET
    watch.goal_ended(6.4, 12.0)
    watch.map_came(6.5, 0.0, 12.1)
    assert watch.judgement(6.6) is MapWait.READY
    watch.goal_ended(6.7, 12.3)
    assert watch.judgement(8.8) is MapWait.QUIET and watch.waits  # not two in a row


def test_a_map_stamped_at_the_goals_end_is_new_enough() -> None:
    """The simulator publishes the map as the goal ends, before the result: its stamp says so."""
    watch = _watch(0.1, 5, stamp_s=30.0, clock_s=30.0)
    watch.goal_ended(0.45, 30.0)
    assert watch.judgement(0.46) is MapWait.READY


def test_a_map_stamped_before_the_goals_end_is_not() -> None:
    watch = _watch(0.1, 5, stamp_s=29.0, clock_s=29.0)
    watch.goal_ended(0.45, 30.0)
    assert watch.judgement(0.46) is MapWait.WAIT


def test_a_stamp_ahead_of_the_nodes_clock_is_not_trusted() -> None:
    """A robot whose clock runs 10 s ahead of the explorer's stamps the map at hand after the goal's end."""
    watch = _watch(2.0, 5, stamp_s=40.0, clock_s=30.0)
    watch.goal_ended(8.5, 31.0)
    assert watch.judgement(8.6) is MapWait.WAIT


def test_a_map_that_came_once_is_not_waited_for() -> None:
    """A fixed map (map_server's): no period to wait by."""
    for maps in (0, 1):
        watch = _watch(1.0, maps)
        assert not watch.goal_ended(3.0, 10.0)
        assert watch.judgement(3.0) is MapWait.READY and watch.period_s is None
    assert _watch(2.0, 2).period_s == 2.0  # the second map gives a period


def test_the_wait_is_half_a_second_at_least_and_fifteen_at_most() -> None:
    assert _watch(0.01, 5).wait_bound_s() == 0.5
    assert _watch(60.0, 3).wait_bound_s() == 15.0
    assert _watch(5.0, 3).wait_bound_s() == 10.0
