"""The explorer's settings are its node's ROS 2 parameters, over real rclpy and Fast DDS in a
loopback-only network namespace: ``--ros-args`` overrides them, ``ros2 param set`` changes them
while it runs, and a bad value is refused with its reason."""

from __future__ import annotations

import json
import shlex
import sys
from pathlib import Path
from typing import Any

import pytest

from frontier_rl.ros2.loopback import cli, loopback_problem, run_in_loopback

pytestmark = pytest.mark.slow

_PROBLEM = loopback_problem()
if _PROBLEM is not None:
    pytest.skip(_PROBLEM, allow_module_level=True)

_CLIENT = f"{shlex.quote(sys.executable)} {shlex.quote(str(Path(__file__).with_name('parameter_client.py')))}"
_EXPLORE = f"{shlex.quote(cli())} ros2 explore --json --progress-timeout 30"


def _with_client(home: Path, explore_arguments: str, client_arguments: str = "") -> tuple[dict[str, Any], str]:
    """Run the explorer with ``explore_arguments`` beside the parameter client: the client's
    report and the logs of both."""
    script = (
        f"timeout --preserve-status -s INT 60 {_EXPLORE} {explore_arguments} > explore.log 2> explore.err & "
        f"explore=$!; {_CLIENT} {client_arguments} > client.log 2> client.err; stop $explore"
    )
    done = run_in_loopback(script, home, 90)
    log = "".join((home / name).read_text() for name in ("client.err", "explore.log", "explore.err"))
    assert (home / "client.log").read_text(), log + done.stderr
    return json.loads((home / "client.log").read_text()), log


def test_the_settings_are_parameters_overridden_by_ros_args_and_set_at_run_time(tmp_path: Path) -> None:
    report, log = _with_client(
        tmp_path, "--ros-args -p planner_frequency:=2 -p visualize:=false -p behavior_tree:=/opt/bt/explore.xml"
    )
    assert report["before"] == {
        "planner_frequency": 2.0,  # an integer override taken as the number it is
        "progress_timeout": 30.0,
        "min_frontier_size": 0.2,
        "time_cap": 0.0,
        "progress_distance": 0.1,
        "visualize": False,
        "policy": "nearest",
        "use_sim_time": False,
        "behavior_tree": "/opt/bt/explore.xml",
        "controller_id": "",
    }
    taken, negative, text, policy, cap, controller, checker = report["sets"]
    assert taken["successful"] and cap["successful"] and controller["successful"]
    assert not checker["successful"] and "goal_checker_id must be a string, got 3" in checker["reason"]
    assert report["after"]["controller_id"] == "FollowPath"
    assert not negative["successful"] and "planner_frequency must be a positive number" in negative["reason"]
    assert (
        not text["successful"] and "visualize must be true or false (a boolean), got the text 'yes'" in text["reason"]
    )
    assert not policy["successful"]  # read-only
    assert report["after"] | {"progress_timeout": 5} == report["after"]
    assert report["after"]["time_cap"] == 600.0 and report["after"]["planner_frequency"] == 2.0
    assert "settings now" in log and "Traceback" not in log


def test_use_sim_time_from_ros_args_is_kept(tmp_path: Path) -> None:
    """-p use_sim_time:=true was set back to false (the command's --use-sim-time, not given)."""
    report, log = _with_client(tmp_path, "--ros-args -p use_sim_time:=true", "--get")
    assert report["before"]["use_sim_time"] is True, log


@pytest.mark.parametrize(
    ("arguments", "needle"),
    [
        ("--ros-args -p planner_frequency:=-1", "parameter planner_frequency must be a positive number, got -1.0"),
        ("--ros-args -p return_to_init:=3", "parameter return_to_init must be true or false (a boolean), got 3"),
        ("--planer-frequency 2", "no such option or argument: '--planer-frequency'"),
        ("--ros-args -p policy:=tour", "parameter policy is read-only, got 'tour'"),  # was taken, not ranked with
        ("--namespace 1abc", "--namespace '1abc' is not a name ROS 2 allows"),  # was a traceback
        ("--pose-topic 'bad topic'", "--pose-topic 'bad topic' is not a name ROS 2 allows"),
        ("--teammates a,1b", "--teammates '1b' is not a name ROS 2 allows"),
    ],
)
def test_a_bad_override_is_one_line_naming_it(arguments: str, needle: str, tmp_path: Path) -> None:
    done = run_in_loopback(f"{_EXPLORE} {arguments} > explore.log 2> explore.err", tmp_path, 60)
    err = (tmp_path / "explore.err").read_text()
    assert done.returncode not in (0, 130) and needle in err, err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1, err


@pytest.mark.parametrize(
    ("command", "arguments", "needle"),
    [
        ("explore", "--ros-args -p", "Couldn't parse trailing -p flag"),
        ("explore", "--ros-args -r __ns:=/1x", "Couldn't parse remap rule"),
        ("explore", "--ros-args --garbage", "arguments ROS does not know: ['--garbage']"),  # a traceback
        ("explore --policy learned:missing_model.zip", "--ros-args --log-level bogus", "Couldn't parse log level"),
        (
            "rank --robots a,b,c,d --policy learned:missing_model.zip",
            "--ros-args -p",
            "Couldn't parse trailing -p flag",
        ),
        ("sim --world missing_world.yaml", "--ros-args -r", "Couldn't parse trailing -r flag"),
    ],
)
def test_ros_arguments_rcl_cannot_parse_end_in_an_error_line(
    command: str, arguments: str, needle: str, tmp_path: Path
) -> None:
    """They ended in a traceback; rcl's own log lines still come before the error. They are read
    before anything slow starts, which named its own trouble first where it had any: the policy's
    model loaded (explore; rank's workers, with four robots 20 s before the error on this machine),
    the world (sim)."""
    script = f"{shlex.quote(cli())} ros2 {command} {arguments} > out.log 2> out.err"
    done = run_in_loopback(script, tmp_path, 60)
    err = (tmp_path / "out.err").read_text()
    assert done.returncode == 2 and "error: --ros-args: " in err and needle in err, err
    assert "Traceback" not in err and "missing_" not in err, err


def test_parameter_files_before_and_after_ros_args_are_read_in_order(tmp_path: Path) -> None:
    """Of a Nav2 params.yaml only its first node (amcl) was read; the node's own time_cap and
    progress_distance in a file were named "not used"; of two files, the first was dropped."""
    (tmp_path / "nav2.yaml").write_text(
        "amcl:\n  ros__parameters: {alpha1: 0.2}\n"
        "explore_node:\n  ros__parameters: {planner_frequency: 0.5, progress_timeout: 20.0, potential_scale: 3.0}\n"
    )
    (tmp_path / "ours.yaml").write_text(
        "frontier_rl_explorer:\n  ros__parameters: {time_cap: 100.0, progress_distance: 0.3, planner_frequency: 0.75,"
        " controller_id: FollowPath}\n"
    )
    arguments = "--min-frontier-size 0.4 --params-file nav2.yaml --ros-args --params-file ours.yaml"
    report, log = _with_client(tmp_path, arguments, "--get")
    read = report["before"]
    assert read["planner_frequency"] == 0.75  # the later file wins
    assert read["time_cap"] == 100.0 and read["progress_distance"] == 0.3
    assert read["min_frontier_size"] == 0.4 and read["progress_timeout"] == 30.0  # the command line wins
    assert read["controller_id"] == "FollowPath" and read["behavior_tree"] == ""
    assert "nav2.yaml: not used here: potential_scale" in log and "alpha1" not in log, log


def test_an_explorer_without_its_inputs_says_on_the_log_what_it_waits_for(tmp_path: Path) -> None:
    """With no map (a namespace given to the explorer and not to the robot) it said nothing."""
    script = f"timeout --preserve-status -s INT 9 {_EXPLORE} --namespace tb3_0 > explore.log 2> explore.err"
    done = run_in_loopback(script, tmp_path, 60)
    err = (tmp_path / "explore.err").read_text()
    assert done.returncode == 130 and "waiting for a map on /tb3_0/map" in err and "Traceback" not in err, err
