"""Goals given up are counted by why: at the decision (no path), or by the leg (no progress, a
detour, no path after the recoveries); the counts add up to the aborts, a team's over its robots."""

from __future__ import annotations

from collections import Counter

import numpy as np
import pytest

from frontier_rl.core.sim import simulator
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import run_episode
from frontier_rl.core.sim.episode_log import aborts_by_cause
from frontier_rl.core.sim.leg_result import AbortCause
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.catalog import generate_world
from frontier_rl.policies import make_policy

CAUSES = [cause.value for cause in AbortCause]


def test_a_goal_without_a_path_at_the_decision_is_counted_as_not_planned(monkeypatch: pytest.MonkeyPatch) -> None:
    sim = ExplorationSimulator(generate_world("office", 0), SimConfig(), np.random.default_rng(0))
    monkeypatch.setattr(simulator, "plan_path", lambda *args: None)
    candidates = len(sim.frontiers())
    sim.execute(np.arange(candidates))
    result = sim.result(0.0)
    assert result.aborts == candidates > 0
    assert result.aborts_by_cause == {cause: candidates if cause == "not_planned" else 0 for cause in CAUSES}
    assert result.summary().to_json()["aborts_by_cause"] == result.aborts_by_cause


def test_the_causes_add_up_to_the_aborts_of_an_episode() -> None:
    result = run_episode(generate_world("cluttered", 0), make_policy("nearest"), SimConfig(), seed=0)
    assert list(result.aborts_by_cause) == CAUSES
    assert sum(result.aborts_by_cause.values()) == result.aborts > 0  # a leg lost its way in the rubble


def test_a_team_sums_its_robots_causes_and_names_every_cause() -> None:
    robots = [Counter({AbortCause.NO_PATH: 1}), Counter({AbortCause.NO_PATH: 2, AbortCause.DETOUR: 1}), Counter()]
    assert aborts_by_cause(robots) == {"not_planned": 0, "no_progress": 0, "detour": 1, "no_path": 3}
