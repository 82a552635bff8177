"""The ranking service without ROS (what the ROS 1 and ROS 2 nodes both serve): every request is
answered, in order, with the reason when it cannot be ranked, for each robot of a team."""

from __future__ import annotations

import math
import threading
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from frontier_rl.errors import MapError
from frontier_rl.robot.answers import MapCells, MapFrame, MapInfo
from frontier_rl.robot.node_settings import StaleMapAnswer
from frontier_rl.robot.ranking_service import Answer, RankingService, ServiceSettings

AT_ORIGIN = MapFrame("map", 0.0, 0.0, 0.0)
NOW_S = 100.0


def _room(stamp_s: float = NOW_S) -> MapCells:
    cells = np.full((60, 60), -1, np.int8)
    cells[10:50, 10:30] = 0
    return MapCells(MapInfo(AT_ORIGIN, 60, 60, 0.05, round(stamp_s * 1e9)), cells.reshape(-1))


class _Answers:
    """Collects the service's answers and the warnings it logs."""

    def __init__(self) -> None:
        self.answers: list[Answer] = []
        self.warnings: list[str] = []
        self._arrived = threading.Condition()

    def __call__(self, answer: Answer) -> None:
        with self._arrived:
            self.answers.append(answer)
            self._arrived.notify_all()

    def wait(self, count: int, timeout: float = 60.0) -> list[Answer]:
        with self._arrived:
            assert self._arrived.wait_for(lambda: len(self.answers) >= count, timeout), self.answers
            return list(self.answers)


def _service(**settings: object) -> tuple[RankingService, _Answers]:
    answers = _Answers()
    chosen = {"robots": ("tb3_0", "tb3_1"), "policy": "fixed:0.75", **settings}
    service = RankingService(ServiceSettings(**chosen), answers, answers.warnings.append, lambda: NOW_S)  # type: ignore[arg-type]
    return service, answers


@pytest.fixture
def team() -> Iterator[tuple[RankingService, _Answers]]:
    service, answers = _service()
    try:
        assert service.start(lambda: False)
        yield service, answers
    finally:
        service.close()


def test_every_request_of_a_team_is_answered_with_its_robots_frontiers(team: tuple[RankingService, _Answers]) -> None:
    service, answers = team
    for ns in ("tb3_0", "tb3_1"):
        service.on_map(ns, lambda sequence: _room())
        service.on_pose(ns, (1.0, 1.0, 0.0))
    for i in range(5):
        for ns in ("tb3_0", "tb3_1", "ghost"):
            service.on_request(f"{ns} {ns}-{i}")
    got = answers.wait(15)
    by_request = {(a.robot, a.request): a for a in got}
    assert len(by_request) == 15 and service.answered == 15
    for i in range(5):
        for ns in ("tb3_0", "tb3_1"):
            answer = by_request[(ns, f"{ns}-{i}")]
            assert answer.centres and answer.weight == 0.75 and answer.status.reason == ""
            assert answer.info is not None and answer.info.stamp_s == NOW_S
        ghost = by_request[("ghost", f"ghost-{i}")]
        assert ghost.centres == () and "unknown robot 'ghost'" in ghost.status.reason


def test_a_request_without_a_map_or_a_pose_is_answered_empty_with_why(team: tuple[RankingService, _Answers]) -> None:
    service, answers = team
    service.on_request("tb3_0 a")
    service.on_map("tb3_0", lambda sequence: _room())
    service.on_request("tb3_0 b")
    service.on_pose("tb3_0", (math.nan, 1.0, 0.0))
    service.on_request("tb3_0 c")
    service.on_pose("tb3_0", (9.0, 9.0, 0.0))
    service.on_request("tb3_0 d")
    reasons = [a.status.reason for a in answers.wait(4)]
    assert reasons == [
        "no usable map of 'tb3_0' yet",
        "no pose of 'tb3_0' yet",
        "pose of 'tb3_0' is not finite: nan, 1.0, yaw 0.0",
        "pose of 'tb3_0' (9.00, 9.00) lies outside its map",
    ]


def _bad_map(sequence: int) -> MapCells:
    raise MapError("map data has 3 values, expected width × height = 3600")


@pytest.mark.parametrize("keep", [True, False])
def test_a_malformed_map_keeps_the_last_good_one_or_drops_it(keep: bool) -> None:
    service, answers = _service(robots=("",), keep_last_map=keep)
    try:
        assert service.start(lambda: False)
        service.on_map("", lambda sequence: _room())
        service.on_map("", _bad_map)
        service.on_pose("", (1.0, 1.0, 0.0))
        service.on_request("")
        answer = answers.wait(1)[0]
    finally:
        service.close()
    assert bool(answer.centres) is keep
    assert any("rejected (map data has 3 values" in w for w in answers.warnings)
    assert ("the last good map is kept" if keep else "no map until a good one arrives") in answers.warnings[0]


def test_a_stale_map_is_ranked_and_said_so_or_answered_empty() -> None:
    for stale, ranked in ((StaleMapAnswer.STALE, True), (StaleMapAnswer.EMPTY, False)):
        service, answers = _service(robots=("",), max_map_age=10.0, stale=stale)
        try:
            assert service.start(lambda: False)
            service.on_map("", lambda sequence: _room(stamp_s=NOW_S - 60.0))
            service.on_pose("", (1.0, 1.0, 0.0))
            service.on_request("")
            answer = answers.wait(1)[0]
        finally:
            service.close()
        assert bool(answer.centres) is ranked and "is stale: 60.0 s old" in answer.status.reason


def test_a_policy_that_plans_on_the_true_map_is_refused_at_once() -> None:
    with pytest.raises(Exception, match="true map"):
        _service(policy="oracle")


def test_warnings_are_throttled_by_kind_however_their_texts_differ(team: tuple[RankingService, _Answers]) -> None:
    """A robot off its map warned at every request: each warning named another pose, and the
    throttle was keyed by the text; requests naming ever new robots each had a key of their own."""
    service, answers = team
    service.on_map("tb3_0", lambda sequence: _room())
    for i in range(5):
        service.on_pose("tb3_0", (9.0 + i, 9.0, 0.0))
        service.on_request(f"tb3_0 off-{i}")
        service.on_request(f"ghost{i} g-{i}")
    got = answers.wait(10)
    assert len({a.status.reason for a in got}) == 10  # each answer still says what was wrong
    assert [w.split(":")[0] for w in answers.warnings] == [
        "request off-0 of 'tb3_0' answered empty",
        "request g-0 of 'ghost0' answered empty",
    ]


def test_only_a_fixed_weight_is_announced_not_a_user_policys_own(tmp_path: Path) -> None:
    """Any policy with a float ``weight`` attribute was announced on /frontier_weight as fixed."""
    path = tmp_path / "adaptive.py"
    path.write_text(
        "from frontier_rl import Ranking\n"
        "class Adaptive:\n"
        "    name = 'adaptive'\n"
        "    weight = 0.5  # where it starts; it changes as the robot explores\n"
        "    def rank(self, context, rng):\n"
        "        return Ranking(list(range(len(context.frontiers))), self.weight)\n"
    )
    assert _service(policy=f"{path}:Adaptive")[0].fixed_weight is None
    assert _service(policy="fixed:0.6")[0].fixed_weight == 0.6


def test_the_ros2_commands_defaults_are_the_services() -> None:
    """The defaults stood in three places (the settings, the ROS 2 command, the ROS 1 node, which
    now reads the settings'): the command's must say the same."""
    import inspect

    from frontier_rl.cli.ros2 import rank

    defaults = {name: p.default for name, p in inspect.signature(rank).parameters.items()}
    service = {"top_k": "top_k", "min_cluster_size": "min_cells", "max_map_age": "max_map_age"}
    service |= {"stale_map": "stale", "keep_last_map": "keep_last_map", "max_pending": "max_pending"}
    for option, field in service.items():
        assert defaults[option] == getattr(ServiceSettings, field), option
