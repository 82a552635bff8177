"""The frontier node's decisions without ROS: which requests are ranked and why not, the status
line, request ids, throttled warnings and the master watch."""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from types import SimpleNamespace

import pytest

from frontier_rl.core.sim.config import MAX_FRONTIER_DROP_CELLS
from frontier_rl.errors import ConfigError, SettingError
from frontier_rl.policies import make_policy
from frontier_rl.robot.answers import MapFrame, MapInfo, Status, check_request, parse_request
from frontier_rl.robot.node_settings import (
    MAX_CHECK_PERIOD_S,
    StaleMapAnswer,
    check_node_policy,
    count_parameter,
    flag_parameter,
    node_policy_spec,
    robot_namespaces,
    seconds_parameter,
    settings_named,
    stale_map_parameter,
)
from frontier_rl.robot.throttled_log import ThrottledLog

INFO = MapInfo(MapFrame("map", -2.0, -1.0, 0.0), width=100, height=50, resolution=0.05, stamp_ns=100 * 10**9)
ROBOTS = ["tb3_0", "tb3_1"]


@pytest.mark.parametrize(
    ("robot", "info", "pose", "now", "rank", "needle"),
    [
        ("tb3_0", INFO, (0.0, 0.0, 0.0), 101.0, True, ""),
        ("nobody", INFO, (0.0, 0.0, 0.0), 101.0, False, "unknown robot 'nobody'"),
        ("tb3_0", None, (0.0, 0.0, 0.0), 101.0, False, "no usable map"),
        ("tb3_0", INFO, None, 101.0, False, "no pose"),
        ("tb3_0", INFO, (math.nan, 0.0, 0.0), 101.0, False, "not finite"),
        ("tb3_0", INFO, (0.0, math.inf, 0.0), 101.0, False, "not finite"),
        ("tb3_0", INFO, (0.0, 0.0, -math.inf), 101.0, False, "not finite"),
        ("tb3_0", INFO, (3.1, 0.0, 0.0), 101.0, False, "outside its map"),  # the map ends at x = 3.0
        ("tb3_0", INFO, (0.0, -1.01, 0.0), 101.0, False, "outside its map"),
        ("tb3_0", INFO, (0.0, 0.0, 0.0), 131.0, True, "stale: 31.0 s old"),
    ],
)
def test_which_requests_are_ranked(
    robot: str, info: MapInfo | None, pose: tuple[float, float, float] | None, now: float, rank: bool, needle: str
) -> None:
    verdict = check_request(robot, ROBOTS, info, pose, now, 30.0, StaleMapAnswer.STALE)
    assert verdict.rank is rank
    assert needle in verdict.reason if needle else verdict.reason == ""


def test_a_stale_map_is_answered_empty_when_so_configured_and_any_age_passes_at_zero() -> None:
    assert not check_request("tb3_0", ROBOTS, INFO, (0.0, 0.0, 0.0), 500.0, 30.0, StaleMapAnswer.EMPTY).rank
    assert check_request("tb3_0", ROBOTS, INFO, (0.0, 0.0, 0.0), 1e9, 0.0, StaleMapAnswer.EMPTY).reason == ""


def test_a_rotated_map_contains_points_in_its_own_frame() -> None:
    info = MapInfo(MapFrame("map", 1.0, 1.0, math.pi / 2), width=20, height=10, resolution=0.1, stamp_ns=0)
    assert info.contains(0.5, 2.5)  # 1.5 m along the map's x axis (world +y), 0.5 m along its y axis (world -x)
    assert not info.contains(1.5, 2.5)


def test_request_ids_and_the_status_line() -> None:
    assert parse_request(" /tb3_0 17 ", 3) == ("tb3_0", "17")
    assert parse_request("tb3_1", 3) == ("tb3_1", "3")
    assert parse_request("", 4) == ("", "4")
    assert parse_request("17", 5) == ("", "17")  # one robot without a namespace: no ROS name starts with a digit
    assert parse_request("/ 17", 5) == ("", "17")
    assert parse_request("tb3_0 sweep 2\tleg\n17 ", 6) == ("tb3_0", "sweep 2 leg 17")  # the rest, one line
    assert parse_request("17 b", 7) == ("", "17 b")
    line = json.loads(Status("tb3_0", "17", 0, "no pose", "fixed:0.75", math.nan, 1.5, math.inf).to_json())
    assert line == {"robot": "tb3_0", "request": "17", "frontiers": 0, "reason": "no pose", "policy": "fixed:0.75",
                    "weight": None, "map_stamp_s": 1.5, "map_age_s": None, "latency_s": 0.0}  # fmt: skip


def test_warnings_are_throttled_per_robot_and_kind() -> None:
    log = ThrottledLog(period_s=10.0)
    assert log.due("tb3_0", "pose", 0.0) and not log.due("tb3_0", "pose", 9.9)
    assert log.due("tb3_1", "pose", 1.0) and log.due("tb3_0", "map", 1.0)
    assert log.due("tb3_0", "pose", 10.0)


@pytest.mark.parametrize(
    ("policy", "model", "spec"),
    [("", "", "fixed:0.6"), ("", "models/model5.zip", "learned:models/model5.zip"), (" tour ", "", "tour"),
     ("learned:models/model7.zip", "", "learned:models/model7.zip"), ("nearest", " ", "nearest")],
)  # fmt: skip
def test_the_node_policy_is_policy_else_model_else_weight(policy: str, model: str, spec: str) -> None:
    assert node_policy_spec(policy, model, 0.6) == spec


def test_a_policy_and_a_model_together_are_a_config_error() -> None:
    with pytest.raises(ConfigError, match=r"not both.*rosparam delete"):
        node_policy_spec("tour", "models/model5.zip", 0.75)


def test_a_policy_that_needs_the_true_map_is_a_config_error() -> None:
    with pytest.raises(ConfigError, match="true map"):
        check_node_policy(make_policy("oracle"), "oracle")
    check_node_policy(make_policy("tour"), "tour")  # a policy of the robot's own map passes


def test_a_point_model_is_a_config_error() -> None:
    """Models 1 and 2 choose a goal cell and rank no frontier: every answer would be empty."""
    with pytest.raises(ConfigError, match="point model"):
        check_node_policy(SimpleNamespace(kind="point", name="learned:model1"), "learned:runs/model1/model.zip")
    check_node_policy(SimpleNamespace(kind="frontier", name="learned:model7"), "learned:models/model7.zip")


@pytest.mark.parametrize(
    ("name", "value", "needle"),
    [("top_k", 0, ">= 1, got 0"), ("top_k", "10", "'10'"), ("top_k", True, "True"), ("max_pending", -3, "-3"),
     ("min_cluster_size", 2.5, "2.5"),
     ("min_cluster_size", 2**63, "0 to 1,000,000"), ("max_map_age", -1.0, ">= 0"), ("max_map_age", math.nan, "nan"),
     ("max_map_age", math.inf, "inf"), ("master_check_period", 0.0, "> 0"), ("master_check_period", 1e12, "<= 3600"),
     ("keep_last_map", "false", "true or false (a boolean), got the text 'false'")],
)  # fmt: skip
def test_a_bad_node_parameter_is_named(name: str, value: object, needle: str) -> None:
    """What the node refuses at start (then exits 2 with the message): a master check period of 0
    was a busy loop, of 10¹² an OverflowError in the watch's thread, and "false" was true."""
    checks: dict[str, Callable[[str, object], object]] = {
        "top_k": lambda n, v: count_parameter(n, v, 1),
        "max_pending": lambda n, v: count_parameter(n, v, 1),
        "min_cluster_size": lambda n, v: count_parameter(n, v, 0, MAX_FRONTIER_DROP_CELLS),
        "max_map_age": lambda n, v: seconds_parameter(n, v, zero=True),
        "master_check_period": lambda n, v: seconds_parameter(n, v, zero=False, most=MAX_CHECK_PERIOD_S),
        "keep_last_map": flag_parameter,
    }
    with pytest.raises(SettingError, match=f"^{name} must be") as error:
        checks[name](name, value)
    assert needle in str(error.value) and error.value.setting == name  # each front end names it its way


def test_good_node_parameters_pass_as_they_are() -> None:
    assert count_parameter("top_k", 10, 1) == 10 and count_parameter("min_cluster_size", 0, 0) == 0
    assert (
        seconds_parameter("max_map_age", 0, zero=True) == 0.0
        and seconds_parameter("max_map_age", 30, zero=True) == 30.0
    )
    assert seconds_parameter("master_check_period", 1.0, zero=False, most=MAX_CHECK_PERIOD_S) == 1.0
    assert flag_parameter("keep_last_map", False) is False


def test_robot_namespaces() -> None:
    assert robot_namespaces("tb3_0, /tb3_1/") == ["tb3_0", "tb3_1"]
    assert robot_namespaces(["tb3_0"]) == ["tb3_0"] and robot_namespaces([""]) == [""] and robot_namespaces("") == [""]
    for bad, needle in (("tb3_0,,tb3_1", "empty namespace"), ("tb3_0,/tb3_0", "'tb3_0' twice"), (5, "got 5"),
                        ([], "no robot"), (["tb3_0", 3], "namespaces such as"), (",,", "only empty namespaces"),
                        (",".join(f"r{i}" for i in range(65)), "64 at most")):  # fmt: skip
        with pytest.raises(ConfigError, match=needle):
            robot_namespaces(bad)


def test_a_bad_setting_is_named_as_each_front_end_writes_it() -> None:
    """``ros2 rank`` said ``~top_k must be ...``, a ROS 1 parameter its user never wrote."""
    for name, expected in ((lambda s: f"~{s}", "~top_k must be"), (lambda s: "--" + s.replace("_", "-"), "--top-k")):
        with pytest.raises(ConfigError, match=f"^{expected}"), settings_named(name):
            count_parameter("top_k", 0, 1)
    assert stale_map_parameter("empty") is StaleMapAnswer.EMPTY
    with pytest.raises(SettingError, match="stale_map must be stale or empty, got 'maybe'"):
        stale_map_parameter("maybe")
