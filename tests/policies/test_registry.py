"""Tests of frontier_rl.policies.registry: policy names as given on the command line."""

from __future__ import annotations

import numpy as np
import pytest

from frontier_rl.core.frontiers.detection import detect_frontiers
from frontier_rl.core.sim.episode import DecisionContext
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.errors import ConfigError, UnknownNameError
from frontier_rl.policies import (
    POLICY_NAMES,
    ExploreLite,
    FixedWeight,
    FrontierTour,
    InformationGain,
    LargestFrontier,
    NearestFrontier,
    OracleTour,
    RandomFrontier,
    make_policy,
)

SIMPLE = {
    "nearest": NearestFrontier,
    "largest": LargestFrontier,
    "explore-lite": ExploreLite,
    "info-gain": InformationGain,
    "random": RandomFrontier,
    "tour": FrontierTour,
}


def test_policy_names() -> None:
    assert set(POLICY_NAMES) == {*SIMPLE, "oracle", "fixed:W", "tour:N", "learned:PATH.zip"}
    assert isinstance(make_policy("oracle"), OracleTour)


@pytest.mark.parametrize("name", sorted(SIMPLE))
def test_make_policy_for_every_simple_name(name: str) -> None:
    policy = make_policy(name)
    assert isinstance(policy, SIMPLE[name])
    assert policy.name == name
    assert make_policy(f"  {name} ").name == name  # surrounding blanks are ignored


@pytest.mark.parametrize(
    ("spec", "weight"), [("fixed:0.3", 0.3), ("fixed:0.75", 0.75), ("fixed:0", 0.0), ("fixed:1", 1.0)]
)
def test_make_policy_fixed_weight(spec: str, weight: float) -> None:
    policy = make_policy(spec)
    assert isinstance(policy, FixedWeight)
    assert policy.weight == weight
    assert policy.name == spec


@pytest.mark.parametrize("stops", [1, 4, 16])
def test_make_policy_tour_with_its_number_of_stops(stops: int) -> None:
    policy = make_policy(f"tour:{stops}")
    assert isinstance(policy, FrontierTour)
    assert policy.max_frontiers == stops and policy.name == f"tour:{stops}"
    assert make_policy("tour") == FrontierTour(max_frontiers=10)


@pytest.mark.parametrize(("spec", "needle"), [("tour:", "whole number"), ("tour:x", "whole number"),
                                              ("tour:1.5", "whole number"), ("tour:-3", "whole number"),
                                              ("tour:0", "1 to 16 stops, got 'tour:0'"),
                                              ("tour:17", "1 to 16 stops, got 'tour:17'"),
                                              ("tour:99999999999999999999", "1 to 16 stops")])  # fmt: skip
def test_bad_tour_stops_raise_config_error_naming_the_spec(spec: str, needle: str) -> None:
    with pytest.raises(ConfigError, match=needle) as info:
        make_policy(spec)
    assert spec in str(info.value)


def test_a_number_of_stops_longer_than_python_converts_is_refused_in_one_line() -> None:
    """A 5,000-digit number was a ValueError (Python converts at most 4,300 digits)."""
    with pytest.raises(ConfigError, match="tour:N takes 1 to 16 stops"):
        make_policy("tour:" + "1" * 5000)


def test_every_policy_ranks_a_real_frontier_set() -> None:
    data = np.full((30, 60), CellState.UNKNOWN, np.int8)
    data[5, 2:20] = CellState.FREE
    data[15, 10:16] = CellState.FREE
    data[25, 30:58] = CellState.FREE
    grid = OccupancyGrid(data, 0.05)
    context = DecisionContext(
        grid, detect_frontiers(grid, Pose(0.5, 0.75)), Pose(0.5, 0.75), 0.0, 3.5, robot_radius=0.105
    )
    assert len(context.frontiers) == 3
    for spec in [*SIMPLE, "fixed:0.3", "tour:2"]:
        ranking = make_policy(spec).rank(context, np.random.default_rng(0))
        # explore_lite skips frontiers under 0.75 m (15 cells) while larger ones are left
        expected = [0, 2] if spec == "explore-lite" else [0, 1, 2]
        assert sorted(ranking.order.tolist()) == expected, spec
    assert make_policy("fixed:0.3").rank(context, np.random.default_rng(0)).weight == 0.3
    assert make_policy("fixed:1").rank(context, np.random.default_rng(0)).order.tolist() == [1, 0, 2]  # nearest
    assert make_policy("fixed:0").rank(context, np.random.default_rng(0)).order.tolist() == [2, 0, 1]  # largest
    assert make_policy("nearest").rank(context, np.random.default_rng(0)).weight is None


@pytest.mark.parametrize("spec", ["fixed:abc", "fixed:", "fixed", "fixed:0.5:1"])
def test_unparsable_fixed_weight_raises_config_error_naming_the_spec(spec: str) -> None:
    with pytest.raises(ConfigError) as info:
        make_policy(spec)
    assert repr(spec) in str(info.value) or spec in str(info.value)


@pytest.mark.parametrize(("spec", "value"), [("fixed:1.5", "1.5"), ("fixed:nan", "nan"), ("fixed:-0.1", "-0.1"),
                                              ("fixed:inf", "inf")])  # fmt: skip
def test_fixed_weight_outside_0_1_raises_config_error_naming_the_value(spec: str, value: str) -> None:
    with pytest.raises(ConfigError) as info:
        make_policy(spec)
    assert value in str(info.value)


@pytest.mark.parametrize("spec", ["fixed:1.5", "fixed:nan"])
def test_fixed_weight_outside_0_1_message_names_the_spec(spec: str) -> None:
    with pytest.raises(ConfigError) as info:
        make_policy(spec)
    assert spec in str(info.value)


@pytest.mark.parametrize("spec", ["bogus", "nearest:3", "Nearest", "", "info_gain", "largest:1", "fixed-0.5"])
def test_unknown_names_raise_unknown_name_error_naming_the_spec(spec: str) -> None:
    with pytest.raises(UnknownNameError) as info:
        make_policy(spec)
    message = str(info.value)
    assert repr(spec) in message
    assert "nearest" in message and "fixed:W" in message  # and lists the valid names
    assert isinstance(info.value, KeyError)  # UnknownNameError is a KeyError too
