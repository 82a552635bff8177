"""The episode runner shared by single robots and teams: seeding, the decision hook, the stall guard."""

from __future__ import annotations

import time

import numpy as np
import pytest

from frontier_rl.core.sim.episode import DecisionContext, Ranking, run_episode
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.catalog import generate_world
from frontier_rl.policies import make_policy
from frontier_rl.swarm import TeamConfig, run_team_episode


def test_decisions_that_take_no_time_end_in_an_error_not_a_hang(monkeypatch: pytest.MonkeyPatch) -> None:
    # a leg that takes no simulated time (a policy cannot cause one: tests/core/sim/test_ranking_check.py)
    monkeypatch.setattr(ExplorationSimulator, "execute", lambda self, order, weight=None: None)
    with pytest.raises(RuntimeError, match=r"stalled: 1001 decisions in a row took no simulated time at t = 0\.0 s"):
        run_episode(generate_world("office", 0), make_policy("nearest"))


def test_the_hook_sees_every_decision_and_its_time_is_not_counted() -> None:
    world, policy = generate_world("rooms", 1), make_policy("nearest")
    seen: list[tuple[float, int]] = []

    def hook(sim: ExplorationSimulator, context: DecisionContext, ranking: Ranking) -> None:
        assert context.sim_time == sim.sim_time and len(ranking.order) == len(context.frontiers)
        seen.append((sim.sim_time, len(context.frontiers)))
        if len(seen) == 1:
            time.sleep(0.5)

    started = time.perf_counter()
    result = run_episode(world, policy, seed=3, on_decision=hook)
    total = time.perf_counter() - started
    assert len(seen) == result.decisions > 1
    assert [t for t, _ in seen] == sorted(t for t, _ in seen) and seen[0][0] == 0.0
    assert result.wall_time_s < total - 0.45  # the half-second in the hook is left out
    plain = run_episode(world, policy, seed=3)
    assert plain.sim_time_s == result.sim_time_s and plain.decisions == result.decisions  # the hook changes nothing


@pytest.mark.parametrize("seed", [0, 7])
def test_a_seed_or_a_generator_from_it_give_the_same_episode(seed: int) -> None:
    world, policy = generate_world("office", 2), make_policy("random")
    by_seed = run_episode(world, policy, seed=seed)
    by_rng = run_episode(world, policy, seed=np.random.default_rng(seed))
    assert (by_seed.sim_time_s, by_seed.decisions, by_seed.path_length_m) == (
        by_rng.sim_time_s, by_rng.decisions, by_rng.path_length_m
    )  # fmt: skip
    other = run_episode(world, policy, seed=seed + 1)
    assert (other.sim_time_s, other.path_length_m) != (by_seed.sim_time_s, by_seed.path_length_m)
    team = run_team_episode(world, policy, team=TeamConfig(robots=1), seed=seed)
    assert (team.sim_time_s, team.decisions) == (by_seed.sim_time_s, by_seed.decisions)
