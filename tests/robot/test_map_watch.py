"""A goal reached is judged on a map from after its end, waiting at most two of the map's periods."""

from __future__ import annotations

from frontier_rl.robot.map_watch import MapWait, MapWatch


def _watch(period_s: float, maps: int, stamp_s: float = 0.0) -> MapWatch:
    watch = MapWatch()
    for i in range(maps):
        watch.map_came(i * period_s, stamp_s)
    return watch


def test_no_judgement_waits_until_a_goal_ends() -> None:
    assert _watch(1.0, 5).judgement(4.5) is MapWait.READY


def test_a_judgement_waits_for_the_next_map_and_no_longer() -> None:
    watch = _watch(1.0, 5)  # maps at 0..4 s
    watch.goal_ended(4.2, 10.0)
    assert watch.judgement(4.9) is MapWait.WAIT
    watch.map_came(5.0, 0.0)
    assert watch.judgement(5.01) is MapWait.READY
    assert watch.judgement(5.02) is MapWait.READY  # the wait is over


def test_a_map_that_stopped_ends_the_wait_after_two_periods() -> None:
    watch = _watch(1.0, 5)
    watch.goal_ended(4.2, 10.0)
    assert watch.judgement(6.1) is MapWait.WAIT
    assert watch.judgement(6.3) is MapWait.STALE
    assert watch.judgement(6.4) is MapWait.READY
    assert watch.period_s == 1.0 and round(watch.age_s(6.3), 6) == 2.3


def test_a_map_stamped_at_the_goals_end_is_new_enough() -> None:
    """The simulator publishes the map as the goal ends, before the result: its stamp says so."""
    watch = _watch(0.1, 5, stamp_s=30.0)
    watch.goal_ended(0.45, 30.0)
    assert watch.judgement(0.46) is MapWait.READY


def test_a_map_stamped_before_the_goals_end_is_not() -> None:
    watch = _watch(0.1, 5, stamp_s=29.0)
    watch.goal_ended(0.45, 30.0)
    assert watch.judgement(0.46) is MapWait.WAIT


def test_a_map_that_came_once_is_not_waited_for() -> None:
    """A fixed map (map_server's) or the first of a SLAM map: no period to wait by."""
    for maps in (0, 1, 2):
        watch = _watch(1.0, maps)
        watch.goal_ended(3.0, 10.0)
        assert watch.judgement(3.0) is MapWait.READY and watch.period_s is None


def test_a_short_period_still_waits_half_a_second() -> None:
    watch = _watch(0.01, 5)
    watch.goal_ended(0.1, 10.0)
    assert watch.judgement(0.5) is MapWait.WAIT
    assert watch.judgement(0.61) is MapWait.STALE
