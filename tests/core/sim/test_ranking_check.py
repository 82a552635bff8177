"""The episode runner's check of what a policy's rank() returns: anything the simulator cannot follow is
one PolicyError line naming the policy, for a single robot and a team alike; what the built-in
policies return passes unchanged."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest

from frontier_rl.core.sim.episode import DecisionContext, Ranking, checked_ranking, run_episode
from frontier_rl.core.world.catalog import generate_world
from frontier_rl.errors import FrontierRLError, PolicyError
from frontier_rl.swarm import TeamConfig, run_team_episode


class _Answers:
    """A policy named ``name`` whose rank() returns ``answer(context)``."""

    def __init__(self, name: str, answer: Callable[[DecisionContext], object]) -> None:
        self.name = name
        self._answer = answer
        self.decisions = 0

    def rank(self, context: DecisionContext, rng: np.random.Generator) -> Ranking:
        self.decisions += 1
        return self._answer(context)  # type: ignore[return-value]


def _all(context: DecisionContext) -> np.ndarray:
    return np.arange(len(context.frontiers))


BAD_ANSWERS: list[tuple[str, Callable[[DecisionContext], object], str]] = [
    ("a list", lambda c: [0], r"rank\(\) returned \[0\] \(type list\), not a Ranking"),
    ("None", lambda c: None, r"rank\(\) returned None \(type NoneType\), not a Ranking"),
    ("a bare array", lambda c: _all(c), r"rank\(\) returned .*not a Ranking"),
    ("past the end", lambda c: Ranking(np.array([len(c.frontiers)])), r"order holds (\d+), not a candidate's index"),
    ("negative", lambda c: Ranking(np.array([0, -1])), r"order holds -1, not a candidate's index \(0 to \d+\)"),
    ("empty", lambda c: Ranking(np.zeros(0, np.int64)), r"order is empty and it sets no goal: rank the \d+ candid"),
    ("floats", lambda c: Ranking(np.array([0.5])), r"order is an array of float64 with shape \(1,\), not a 1-D int"),
    ("a list order", lambda c: Ranking([0]), r"order is \[0\] \(type list\), not a 1-D integer array"),  # type: ignore[arg-type]
    ("2-D", lambda c: Ranking(_all(c)[None, :]), r"order is an array of int64 with shape \(1, \d+\)"),
    ("booleans", lambda c: Ranking(np.ones(len(c.frontiers), bool)), r"order is an array of bool"),
    ("twice", lambda c: Ranking(np.array([0, 0])), r"order lists candidate 0 more than once"),
    ("NaN goal", lambda c: Ranking(np.zeros(0, np.int64), goal=(np.nan, 1.0)), r"goal is \(nan, 1\.0\).*not a point"),
    ("goal of 3", lambda c: Ranking(np.zeros(0, np.int64), goal=(1.0, 2.0, 3.0)), r"goal .* not a point"),  # type: ignore[arg-type]
    (
        "string weight",
        lambda c: Ranking(_all(c), weight="0.5"),
        r"weight is '0\.5' \(type str\), not a number in \[0, 1\]",
    ),  # type: ignore[arg-type]
    ("infinite weight", lambda c: Ranking(_all(c), weight=np.inf), r"weight is inf .*not a number in \[0, 1\]"),
    ("weight above 1", lambda c: Ranking(_all(c), weight=1.7), r"weight is 1\.7 .*not a number in \[0, 1\]"),
    ("negative weight", lambda c: Ranking(_all(c), weight=-0.1), r"weight is -0\.1 .*not a number in \[0, 1\]"),
]


@pytest.mark.parametrize(("answer", "needle"), [(a, n) for _, a, n in BAD_ANSWERS], ids=[i for i, _, _ in BAD_ANSWERS])
def test_a_bad_answer_stops_the_episode_at_once_naming_the_policy(
    answer: Callable[[DecisionContext], object], needle: str
) -> None:
    policy = _Answers("mine", answer)
    with pytest.raises(PolicyError, match=r"^policy 'mine': .*" + needle) as info:
        run_episode(generate_world("office", 0), policy)
    assert policy.decisions == 1 and "\n" not in str(info.value)
    assert isinstance(info.value, FrontierRLError)


def test_a_team_runs_the_same_check() -> None:
    policy = _Answers("mine", lambda c: Ranking(np.array([len(c.frontiers) + 3])))
    with pytest.raises(PolicyError, match=r"^policy 'mine': its Ranking's order holds \d+"):
        run_team_episode(generate_world("office", 0), policy, team=TeamConfig(robots=2))
    assert policy.decisions == 1


def test_a_good_answer_is_handed_on_as_it_is() -> None:
    policy = _Answers("mine", lambda c: c)  # unused: the check is called directly below
    order = np.array([2, 0, 1], np.int64)
    for ranking in (
        Ranking(order, 0.75),
        Ranking(order.astype(np.int32)),
        Ranking(order.astype(np.uint8), np.float32(0.5)),  # type: ignore[arg-type]
        Ranking(order[:1]),  # a partial order: the rest are not tried
        Ranking(np.zeros(0, np.int64), goal=(1.0, 2.5)),  # a point goal: the order is ignored
        Ranking(np.zeros(0, np.int64), goal=np.array([1.0, 2.5])),  # type: ignore[arg-type]
    ):
        assert checked_ranking(ranking, 3, policy) is ranking
    assert checked_ranking(Ranking(np.zeros(0, np.int64)), 0, policy).order.size == 0  # nothing to rank
    with pytest.raises(PolicyError, match=r"holds 0, not a candidate's index \(there is none\)"):
        checked_ranking(Ranking(np.zeros(1, np.int64)), 0, policy)


@pytest.mark.parametrize("size", [3, 64, 65, 2000])  # both ways of checking an order: in Python and in NumPy
def test_long_and_short_orders_are_checked_alike(size: int) -> None:
    policy = _Answers("mine", lambda c: c)
    order = np.random.default_rng(size).permutation(size)
    assert checked_ranking(Ranking(order), size, policy).order is order
    with pytest.raises(PolicyError, match=f"order holds {size - 1}, not a candidate's index"):
        checked_ranking(Ranking(order), size - 1, policy)
    twice = order.copy()
    twice[-1] = twice[0]
    with pytest.raises(PolicyError, match=f"order lists candidate {twice[0]} more than once"):
        checked_ranking(Ranking(twice), size, policy)
