"""Team settings: failure specs, strategies and the bad values users can give."""

from __future__ import annotations

import math

import pytest

from frontier_rl.errors import ConfigError
from frontier_rl.swarm import Failure, Strategy, TeamConfig, parse_strategy


@pytest.mark.parametrize(
    ("text", "robot", "time_s"),
    [("1@200", 1, 200.0), ("0@0", 0, 0.0), ("random@35.5", None, 35.5), ("2@random", 2, None), ("random", None, None)],
)
def test_failures_parse(text: str, robot: int | None, time_s: float | None) -> None:
    failure = Failure.parse(text)
    assert (failure.robot, failure.time_s) == (robot, time_s)
    assert Failure.parse(str(failure)) == failure


@pytest.mark.parametrize("text", ["1", "x@3", "1@soon", "-1@5", "1@-5", "1@nan", "1@inf", "@"])
def test_bad_failures_name_the_value(text: str) -> None:
    with pytest.raises(ConfigError, match="failure"):
        Failure.parse(text)


@pytest.mark.parametrize(
    ("kwargs", "needle"),
    [
        ({"robots": 0}, "robots"),
        ({"robots": 9}, "robots"),
        ({"comm_range": -1.0}, "-1.0"),
        ({"robots": 2, "failures": (Failure(2, 10.0),)}, "robot 2"),
        ({"robots": 3, "failures": (Failure(1, 10.0), Failure(1, 20.0))}, "only once"),
        ({"robots": 2, "failures": (Failure(None, 1.0),) * 3}, "3 failures"),
        ({"explore_period": 0.0}, "explore_period"),
        ({"strategy": "swarming"}, "swarming"),
    ],
)
def test_bad_team_settings_are_refused(kwargs: dict[str, object], needle: str) -> None:
    with pytest.raises(ConfigError, match=needle):
        TeamConfig(**kwargs)  # type: ignore[arg-type]


def test_communication_range_defaults() -> None:
    assert TeamConfig(robots=2).range_m == math.inf
    assert TeamConfig(robots=2, strategy=Strategy.RENDEZVOUS).range_m == TeamConfig().meeting_radius
    assert TeamConfig(robots=2, comm_range=0.0).range_m == 0.0
    assert TeamConfig(strategy="coordinated").strategy is Strategy.COORDINATED  # type: ignore[arg-type]


def test_unknown_strategy_lists_the_names() -> None:
    with pytest.raises(ConfigError, match="uncoordinated, coordinated, rendezvous"):
        parse_strategy("greedy")
