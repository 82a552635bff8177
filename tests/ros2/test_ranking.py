"""The thesis's ranking service on ROS 2 (``frontier-rl ros2 rank``) over real rclpy and Fast DDS,
in a loopback-only network namespace: a team of two simulated robots, and every request answered."""

from __future__ import annotations

import json
import shlex
import sys
from pathlib import Path

import pytest

from frontier_rl.ros2.loopback import cli, loopback_problem, run_in_loopback

pytestmark = pytest.mark.slow

_PROBLEM = loopback_problem()
if _PROBLEM is not None:
    pytest.skip(_PROBLEM, allow_module_level=True)


_SLAM_MAPS = " ".join(f"-r /tb3_{i}/map:=/tb3_{i}/slam_map" for i in range(2))
"""ROS's remappings of both robots' maps: the simulator publishes them there, the service reads them there."""


@pytest.mark.parametrize(("pose_type", "ros_args"), [("pose", f"--ros-args {_SLAM_MAPS}"), ("tf", "")])
def test_every_request_is_answered_for_a_team_and_an_unknown_robot_with_a_reason(
    pose_type: str, ros_args: str, tmp_path: Path
) -> None:
    """Each robot's pose from its pose topic, or from its namespace's ``tf`` and ``tf_static``; the
    maps remapped by ``--ros-args`` in both commands (either one alone and no map would be ranked)."""
    frontier_rl = shlex.quote(cli())
    script_path = Path(__file__).resolve().parents[2] / "benchmarks" / "ranking_client.py"
    client = f"{shlex.quote(sys.executable)} {shlex.quote(str(script_path))}"
    script = (
        f"{frontier_rl} ros2 sim --world office --seed 3 --robots 2 {ros_args} > sim.log 2>&1 & sim=$!; "
        f"{frontier_rl} ros2 rank --robots tb3_0,tb3_1 --policy fixed:0.75 --pose-type {pose_type} {ros_args} "
        "> rank.log 2>&1 & rank=$!; "
        f"{client} tb3_0,tb3_1,ghost --count 10 --ready tb3_0,tb3_1 > client.log 2> client.err; status=$?; "
        "stop $rank $sim || status=1; exit $status"
    )
    done = run_in_loopback(script, tmp_path, 210)  # the client waits at most 3 x 60 s
    logs = "\n".join(p.read_text() for p in sorted(tmp_path.glob("*.log")) + sorted(tmp_path.glob("*.err")))
    assert done.returncode == 0, f"{done.stderr}\n{logs}"
    report = json.loads((tmp_path / "client.log").read_text())
    statuses = {(s["robot"], s["request"]): s for s in report["statuses"]}
    assert len(statuses) == 30, logs  # every request, once
    for robot in ("tb3_0", "tb3_1"):
        answers = [statuses[(robot, f"{robot}-{i}")] for i in range(10)]
        assert all(a["frontiers"] > 0 and a["policy"] == "fixed:0.75" for a in answers), answers
    ghosts = [statuses[("ghost", f"ghost-{i}")] for i in range(10)]
    assert all(g["frontiers"] == 0 and "ghost" in g["reason"] for g in ghosts), ghosts
    assert f"{30 + report['probes']} requests answered" in (tmp_path / "rank.log").read_text()


def test_a_ros_parameter_of_the_wrong_type_is_one_line(tmp_path: Path) -> None:
    """It was a traceback (``InvalidParameterTypeException``), in rank and sim as in explore (the
    three set their nodes up alike: rank, whose workers start first, stands for them)."""
    frontier_rl = shlex.quote(cli())
    done = run_in_loopback(f"{frontier_rl} ros2 rank --ros-args -p use_sim_time:=3 > out.log 2> err.log", tmp_path, 60)
    err = (tmp_path / "err.log").read_text()
    assert done.returncode == 2 and "Traceback" not in err, err
    assert err.strip().splitlines()[-1].startswith("error: --ros-args: Trying to set parameter 'use_sim_time'"), err
