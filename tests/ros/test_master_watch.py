"""The ROS 1 node's watch on its master: a restarted master is reported once, a lost one is not."""

from __future__ import annotations

import http.client
import xml.parsers.expat

from frontier_rl.ros.master_watch import MasterWatch


def _watch(replies: list[object]) -> tuple[list[str], list[str]]:
    """Run a master watch on ``replies`` ((pid, knows the node) or an exception, one per poll)
    until it reports a restart; the restarts and losses it reported."""
    answers = iter(replies)
    restarts: list[str] = []
    lost: list[str] = []

    def identity(uri: str, caller: str) -> tuple[int, bool]:
        value = next(answers)
        if isinstance(value, Exception):
            raise value
        assert isinstance(value, tuple)
        return value

    MasterWatch("http://localhost:1", "/node", 0.0, restarts.append, lost.append, identity=identity).run()
    return restarts, lost


def test_the_master_watch_reports_a_new_master_once_and_not_a_lost_one() -> None:
    restarts, lost = _watch([(100, True), (100, True), OSError("refused"), (100, True), (200, False), (300, False)])
    assert lost == ["refused"]
    assert restarts == ["the ROS master at http://localhost:1 was restarted (pid 100, now 200)"]


def test_the_master_watch_knows_a_new_master_with_the_same_pid_and_survives_garbage() -> None:
    """A fresh container's master may get its predecessor's process id: it no longer knows the
    node. Not knowing it before it registered is no restart; an HTTP or XML error is a loss."""
    garbage = xml.parsers.expat.ExpatError("not well-formed")
    restarts, lost = _watch([(7, False), (7, True), http.client.BadStatusLine("x"), garbage, (7, True), (7, False)])
    assert restarts == ["the ROS master at http://localhost:1 no longer knows /node: restarted"]
    assert len(lost) == 2 and "not well-formed" in lost[1]
