"""The explorer against a Nav2 that misbehaves (``fake_nav2.py``), over real rclpy and Fast DDS in a
loopback-only network namespace: it gives up what it must, says why, never hangs, and resumes."""

from __future__ import annotations

import json
import re
import shlex
import sys
from pathlib import Path

import pytest

from frontier_rl.robot.way_home import HOME_TRIES
from frontier_rl.ros2.loopback import cli, loopback_problem, run_in_loopback

pytestmark = pytest.mark.slow

_PROBLEM = loopback_problem()
if _PROBLEM is not None:
    pytest.skip(_PROBLEM, allow_module_level=True)

_FAKE = f"{shlex.quote(sys.executable)} {shlex.quote(str(Path(__file__).with_name('fake_nav2.py')))}"
_EXPLORE = f"{shlex.quote(cli())} ros2 explore --json --goal-silence-timeout 2"
_DEBUG = "--ros-args --log-level frontier_rl_explorer:=debug"
"""The explorer's debug lines on its log: each goal sent, each wait for a newer map."""


def _run(
    home: Path, nav2: str, explore_for: int = 60, progress_timeout: float = 1.0, options: str = ""
) -> tuple[int, dict[str, object] | None, str]:
    """The explorer (for at most ``explore_for`` s, then Ctrl-C; with ``options``) beside the shell
    command ``nav2`` (in a process group of its own, ended after): its exit status, last JSON
    status and its log."""
    script = (
        f"setsid sh -c {shlex.quote(nav2)} > nav2.log 2>&1 & nav2=$!; "
        f"timeout --preserve-status -s INT {explore_for} {_EXPLORE} --progress-timeout {progress_timeout} "
        f"{options} > explore.log 2> explore.err; status=$?; "
        "kill -9 -$nav2 2>/dev/null; wait; exit $status"
    )
    done = run_in_loopback(script, home, explore_for + 30)
    out = (home / "explore.log").read_text()
    log = out + (home / "explore.err").read_text() + (home / "nav2.log").read_text() + done.stderr
    lines = [line for line in out.splitlines() if line.startswith("{")]
    return done.returncode, (json.loads(lines[-1]) if lines else None), log


@pytest.mark.parametrize("mode", ["reject", "abort", "stall", "succeed", "cancel"])
def test_goals_nav2_will_not_reach_are_given_up_and_exploration_ends(mode: str, tmp_path: Path) -> None:
    """A goal another node cancelled (``cancel``) was held as under way until its progress timeout
    (30 s here: the run would not end in time)."""
    code, status, log = _run(tmp_path, f"{_FAKE} --mode {mode}", progress_timeout=30.0 if mode == "cancel" else 1.0)
    assert code == 0 and status is not None, log
    assert status["state"] == "finished" and status["reason"] == "unreachable", log
    assert isinstance(status["given_up"], int) and status["given_up"] >= 1
    assert isinstance(status["frontiers_left"], int) and status["frontiers_left"] >= 1
    if mode == "stall":  # the goal still under way at the end is cancelled (the robot drove on to it)
        assert "cancelling goal" in log and "goal canceled" in log, log
    if mode == "cancel":  # each given up at once, as Nav2's aborts are
        assert "goal 1 cancelled by another node on navigate_to_pose" in log, log
        assert "navigate_to_pose goal canceled by another node" in log and "cancelling goal" not in log, log


def test_the_way_home_nav2_gives_up_is_sent_again_from_where_the_robot_stands_then_the_run_ends(
    tmp_path: Path,
) -> None:
    code, status, log = _run(tmp_path, f"{_FAKE} --mode abort", options="--return-to-init")
    assert code == 0 and status is not None and status["state"] == "finished", log
    assert status["reason"] == "unreachable", log
    # each abort but the last sends the way again; the last ends the run
    assert log.count("the way home aborted by Nav2 (status 6): planned again from (0.50, 0.50)") == HOME_TRIES - 1, log
    assert f"try {HOME_TRIES} of {HOME_TRIES}" in log and f"try {HOME_TRIES + 1} " not in log, log


def test_the_way_home_along_a_path_is_planned_afresh_while_the_robot_follows_it(tmp_path: Path) -> None:
    """Nav2 replans a navigate_to_pose goal itself, but follow_path's controller follows the path
    it was given: the way home along a path (from a room behind a door only the narrow-passage
    recovery's levels pass) was sent once, planned on the map at the end of exploration."""
    nav2 = f"{_FAKE} --mode stall --door --carried-to 1.0,1.075"
    code, status, log = _run(tmp_path, nav2, 40, options=f"--return-to-init --goal-silence-timeout 10 {_DEBUG}")
    assert code == 0 and status is not None and status["state"] == "finished", log
    assert log.count("sent the way home at (0.50, 0.50) along a path") >= 3, log
    assert "cancelling the way home: the explorer is stopping" in log, log


def test_a_path_goal_that_goes_to_navigate_to_pose_is_not_sent_again_at_each_tick(tmp_path: Path) -> None:
    """Without ``follow_path``, a goal found with the map's walls thinned goes to navigate_to_pose,
    which replans it itself: sent again at each planner tick with its path planned afresh, it
    restarted Nav2's behaviour tree every second, recoveries and all."""
    nav2 = f"{_FAKE} --mode stall --door --no-follow"
    code, status, log = _run(tmp_path, nav2, progress_timeout=3.0, options=f"--goal-silence-timeout 10 {_DEBUG}")
    assert code == 0 and status is not None and status["state"] == "finished", log
    assert "action is not up: goal" in log, log  # a path goal went to navigate_to_pose
    sent = re.findall(r"sent (goal \d+) at", log)
    assert sent and len(sent) == len(set(sent)), log  # each goal once
    assert (tmp_path / "nav2.log").read_text().count("goal naming behavior_tree") == len(sent), log


def test_a_path_goal_whose_follow_path_server_went_away_goes_to_navigate_to_pose_at_the_next_tick(
    tmp_path: Path,
) -> None:
    """The controller server crashes with a path goal under way: the goal is sent to
    navigate_to_pose at the next planner tick (once), not held until Nav2's silence drops it."""
    nav2 = f"{_FAKE} --mode stall --door --follow-gone-after 1"
    options = f"--goal-silence-timeout 10 {_DEBUG}"
    code, status, log = _run(tmp_path, nav2, 90, progress_timeout=4.0, options=options)
    assert code == 0 and status is not None and status["state"] == "finished", log
    assert "follow_path server gone" in log and "no word from follow_path" not in log, log
    along = re.findall(r"sent (goal \d+) at \(([-\d.]+, [-\d.]+)\) along a path", log)
    assert along, log
    label, _ = along[0]
    moved = re.findall(rf"sent {label} at \([-\d.]+, [-\d.]+\)$", log, re.MULTILINE)
    assert len(moved) == 1, log  # to navigate_to_pose, once


@pytest.mark.parametrize(
    ("nav2", "parameter", "named", "error"),
    [
        (
            "--error-code 9001",
            "behavior_tree:=/opt/bt/explore.xml",
            "behavior_tree '/opt/bt/explore.xml'",
            "cannot load the behaviour tree '/opt/bt/explore.xml', error 9001: the stand-in's error: set",
        ),
        # navigate_to_pose goals aborted with follow_path's code are given up as any; a path goal so ends the run
        (
            "--error-code 101 --door",
            "controller_id:=Precise",
            "controller_id 'Precise'",
            "has no controller 'Precise' (or goal checker '', progress checker ''), error 101",
        ),
    ],
)
def test_goals_name_the_nav2_plugins_set_and_one_nav2_has_not_ends_the_run_saying_what_to_set(
    nav2: str, parameter: str, named: str, error: str, tmp_path: Path
) -> None:
    code, status, log = _run(tmp_path, f"{_FAKE} --mode abort {nav2}", options=f"--ros-args -p {parameter}")
    assert code == 2 and status is None, log
    assert f"goal naming {named}" in log, log
    err = (tmp_path / "explore.err").read_text()
    assert error in err and "Traceback" not in log, log
    assert len([line for line in err.splitlines() if line.startswith("error:")]) == 1, log


def test_a_goal_under_way_on_one_nav2_action_is_cancelled_when_the_next_goes_to_the_other(tmp_path: Path) -> None:
    """Nav2's two servers do not preempt each other: a stalled navigate_to_pose goal would drive on
    beside the path the controller follows, and a path beside the next navigate_to_pose goal."""
    code, status, log = _run(tmp_path, f"{_FAKE} --mode stall --door", options="--goal-silence-timeout 10")
    assert code == 0 and status is not None and status["state"] == "finished", log
    nav2 = (tmp_path / "nav2.log").read_text().splitlines()
    sent = [
        (i, "follow_path" if "controller_id" in line else "navigate_to_pose")
        for i, line in enumerate(nav2)
        if line.startswith("goal naming")
    ]
    switches = [k for k in range(1, len(sent)) if sent[k][1] != sent[k - 1][1]]
    assert {sent[k][1] for k in switches} == {"follow_path", "navigate_to_pose"}, log  # both ways
    for k in switches:  # the other action's goal cancelled before the goal after the switch is sent
        before, action = sent[k - 1]
        after = sent[k + 1][0] if k + 1 < len(sent) else len(nav2)
        assert f"{action} goal canceled" in nav2[before:after], (k, log)


def test_a_way_home_nav2_rejects_is_not_sent_again(tmp_path: Path) -> None:
    code, status, log = _run(tmp_path, f"{_FAKE} --mode reject", options="--return-to-init")
    assert code == 0 and status is not None and status["state"] == "finished", log
    assert "planned again" not in log, log


def test_a_malformed_map_and_a_nan_pose_are_ignored_with_a_warning(tmp_path: Path) -> None:
    code, status, log = _run(tmp_path, f"{_FAKE} --mode abort --bad-inputs")
    assert code == 0 and status is not None and status["state"] == "finished", log
    assert "map ignored: map data has 100 values" in log
    assert "pose ignored" in log and "not finite" in log


def test_a_nav2_that_dies_with_a_goal_is_waited_for_and_the_explorer_resumes(tmp_path: Path) -> None:
    nav2 = f"{_FAKE} --mode stall --die-after 1; sleep 1; {_FAKE} --mode abort"
    code, status, log = _run(tmp_path, nav2, progress_timeout=30.0)
    assert code == 0 and status is not None and status["state"] == "finished", log
    assert "no word from navigate_to_pose on goal 1 for 2 s: dropped" in log
    assert isinstance(status["goals"], int) and status["goals"] >= 2


def test_without_nav2_the_explorer_waits_and_ctrl_c_ends_it_with_one_line(tmp_path: Path) -> None:
    code, status, log = _run(tmp_path, "sleep 30", explore_for=4)  # under load, maybe before the node ran
    assert code == 130, log
    assert status is not None and status["state"] == "interrupted" and status["goals"] == 0, log
    assert "Traceback" not in log


def test_ctrl_c_cancels_the_goal_under_way(tmp_path: Path) -> None:
    """The explorer ended on Ctrl-C and Nav2 drove on to its last goal."""
    code, status, log = _run(tmp_path, f"{_FAKE} --mode stall", explore_for=8, progress_timeout=30.0)
    assert code == 130 and status is not None and status["state"] == "interrupted", log
    assert "cancelling goal 1: the explorer is stopping" in log and "goal canceled" in log, log
    assert "Traceback" not in log


@pytest.mark.parametrize(
    ("nav2", "sent", "cancelled"),
    [
        ("", "goal naming", ["navigate_to_pose goal canceled"]),
        # a path sent again: the old one is cancelled, and the new one once Nav2 accepts it
        ("--door", "controller_id", ["follow_path goal canceled"] * 2),
    ],
)
def test_a_stop_before_nav2_answered_the_goal_cancels_it_once_nav2_accepts_it(
    nav2: str, sent: str, cancelled: list[str], tmp_path: Path
) -> None:
    """The goal was forgotten: Nav2 accepted it after the explorer had gone, and the robot drove on."""
    fake = f"{_FAKE} --mode stall --response-delay 0.8 {nav2}"
    script = (
        f"setsid sh -c {shlex.quote(fake)} > nav2.log 2>&1 & nav2=$!; "
        f"{_EXPLORE} --progress-timeout 3 --planner-frequency 2 > explore.log 2> explore.err & explore=$!; "
        f"for i in $(seq 900); do [ $(grep -c {shlex.quote(sent)} nav2.log) -ge {len(cancelled)} ] && break; "
        "sleep 0.1; done; kill -INT $explore; wait $explore; status=$?; sleep 2; "  # what the stand-in did meanwhile
        "kill -9 -$nav2 2>/dev/null; wait; exit $status"
    )
    done = run_in_loopback(script, tmp_path, 150)
    log = "".join((tmp_path / name).read_text() for name in ("explore.log", "explore.err", "nav2.log")) + done.stderr
    assert done.returncode == 130, log
    assert "the explorer is stopping (once Nav2 answers it: 1 unanswered)" in log, log
    canceled = [line for line in (tmp_path / "nav2.log").read_text().splitlines() if "goal canceled" in line]
    assert canceled[-len(cancelled) :] == cancelled, log
    assert "Traceback" not in log, log


def test_explore_resume_pauses_the_run_cancelling_its_goal_and_goes_on(tmp_path: Path) -> None:
    """explore_lite's explore/resume: false stops the robot until true; the time paused is not explored."""
    client = f"{shlex.quote(sys.executable)} {shlex.quote(str(Path(__file__).with_name('resume_client.py')))}"
    script = (
        f"setsid sh -c {shlex.quote(_FAKE + ' --mode stall')} > nav2.log 2>&1 & nav2=$!; "
        f"timeout --preserve-status -s INT 60 {_EXPLORE} --progress-timeout 1 > explore.log 2> explore.err & "
        f"explore=$!; {client} > client.log 2> client.err; kill -INT $explore; wait $explore; "
        "kill -9 -$nav2 2>/dev/null; wait"
    )
    done = run_in_loopback(script, tmp_path, 120)
    names = ("client.log", "client.err", "explore.log", "explore.err", "nav2.log")
    log = "".join((tmp_path / name).read_text() for name in names) + done.stderr
    assert (tmp_path / "client.log").read_text(), log
    report = json.loads((tmp_path / "client.log").read_text())
    paused, *during = report["paused"]
    resumed = next(s for s in during if s["goals"] > paused["goals"])  # the first goal after the pause
    assert paused["state"] == "paused" and "explore/resume" in paused["detail"], log
    before = during[: during.index(resumed)]
    assert all(s["state"] == "paused" or s["detail"] == "resumed" for s in before), log  # no goal meanwhile
    assert resumed["state"] == "exploring" and resumed["goals"] == paused["goals"] + 1, log
    # the time explored stood still while paused, two seconds of wall time (the clock is the wall's here)
    assert resumed["time_s"] - paused["time_s"] < 1.0, log
    assert report["cancelled_while_paused"] and "paused: the goal under way cancelled" in log, log
    assert "Traceback" not in log, log


def test_a_goal_reached_is_judged_on_a_map_from_after_it(tmp_path: Path) -> None:
    """The map comes every 0.3 s and shows the goal's frontier seen only after Nav2 said "reached":
    judged on the map at hand, the frontier just seen was given up."""
    nav2 = f"{_FAKE} --mode succeed --goal-time 1.5 --map-period 0.3 --reveal"
    code, status, log = _run(tmp_path, nav2, progress_timeout=30.0)
    assert code == 0 and status is not None, log
    assert status["reason"] == "explored" and status["given_up"] == 0 and status["goals"] == 1, log


@pytest.mark.parametrize("mode", ["abort", "reject"])
def test_a_goal_aborted_is_judged_on_a_map_from_after_it_and_one_rejected_at_once(mode: str, tmp_path: Path) -> None:
    """The map comes every 0.3 s: a goal Nav2 aborted waits for a map from after its end before it
    is given up, as a goal reached does; one it rejected (the robot never drove) does not wait."""
    # the goal held 0.5 s: the first abort comes after the second map, which gives the node the maps' period to wait by
    code, status, log = _run(tmp_path, f"{_FAKE} --mode {mode} --map-period 0.3 --goal-time 0.5", options=_DEBUG)
    assert code == 0 and status is not None and status["reason"] == "unreachable", log
    assert status["given_up"] == status["goals"], log  # each given up, once
    assert ("aborted by Nav2 (status 6): waiting up to" in log) == (mode == "abort"), log
    assert mode == "abort" or "waiting up to" not in log, log


def test_a_map_that_stops_coming_is_said_so(tmp_path: Path) -> None:
    """The map comes every 0.3 s until the second goal: that goal is judged on the last map, and the log says why."""
    nav2 = f"{_FAKE} --mode succeed --goal-time 1.5 --map-period 0.3 --map-stops-at-goal 2"
    code, status, log = _run(tmp_path, nav2, progress_timeout=30.0)
    assert code == 0 and status is not None and status["reason"] == "unreachable", log
    assert "no map on /map for" in log and "(it came every 0.30 s): goal 2 is judged on the last one" in log, log


def test_a_ctrl_c_before_the_node_ran_still_prints_the_json_status(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    from frontier_rl.cli.ros2 import _explore_with
    from frontier_rl.policies import registry
    from frontier_rl.robot.explorer_params import ExplorerParams
    from frontier_rl.ros2.explorer_options import ExplorerNodeOptions

    def loading(spec: str) -> None:  # a model still loading when Ctrl-C came
        raise KeyboardInterrupt

    monkeypatch.setattr(registry, "make_policy", loading)
    with pytest.raises(KeyboardInterrupt):
        _explore_with("nearest", ExplorerParams(), ExplorerNodeOptions(), json_out=True)
    status = json.loads(capsys.readouterr().out)
    assert status["state"] == "interrupted" and status["goals"] == 0 and status["reason"] is None
