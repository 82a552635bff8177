"""The give-ups of the harder survey on a real SLAM map (willow_2010, 0.1 m cells), replayed for their
first minutes: a robot that stalled at a wall's corner, and one its own map walled in (issue 58)."""

from __future__ import annotations

import pytest

from frontier_rl.api import explore, load_world
from frontier_rl.core.sim.config import SimConfig

pytestmark = pytest.mark.slow


def test_the_careful_follower_no_longer_stalls_at_a_wall_corner() -> None:
    # Before: 53 legs in a row given up for want of progress at one spot, ended at 23 % after 2,250 s.
    result = explore(load_world("willow_2010", 2), "nearest", seed=2, config=SimConfig(max_sim_time=2300.0))
    assert result.aborts_by_cause["no_progress"] == 0
    assert result.end_reason == "time_cap" and result.coverage > 0.5


def test_a_robot_its_own_map_walls_in_finds_its_way_out() -> None:
    # Before: one reachable cell on its map after 393 s, ended `unreachable` at 14 % of the building.
    result = explore(
        load_world("willow_2010", 2), "learned:models/model7.zip", seed=2, config=SimConfig(max_sim_time=800.0)
    )
    assert result.end_reason == "time_cap" and result.coverage > 0.25


def test_a_robot_that_slipped_across_a_corner_into_a_pocket_gets_out_along_its_trail() -> None:
    # gdc_3ne, 0.05 m cells. Before: walled in on its map, every way out closed, ended `unreachable`
    # at 23 % after 1,616 s.
    result = explore(load_world("gdc_3ne", 3), "fixed:0.75", seed=3, config=SimConfig(max_sim_time=2000.0))
    assert result.end_reason == "time_cap"
