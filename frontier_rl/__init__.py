"""frontier_rl: learn where a search-and-rescue robot should look next.

A fast 2D frontier-exploration simulator (LiDAR, log-odds mapping, move_base-like navigation),
the classic frontier-selection baselines, and the thesis's frontier-ranking models as Gymnasium
environments (registered under the ``FrontierRL/`` namespace by ``import frontier_rl.envs``).

The names below are importable from here; each loads its module the first time it is used, so
``import frontier_rl`` stays light, and none of them but :func:`train` and :class:`TrainConfig`
loads Gymnasium or torch.

* The policy interface: :class:`ExplorationPolicy` (a ``name`` and ``rank(context, rng)``), the
  :class:`DecisionContext` it sees (the map, the candidate :class:`Frontiers`, the :class:`Pose`, ...)
  and the :class:`Ranking` it returns.
* The engine's types: :class:`OccupancyGrid`, :class:`CellState`, :class:`World`, :class:`SimConfig`,
  :class:`EpisodeResult` (its rounded scalars an :class:`EpisodeSummary`), :func:`run_episode`.
* The policies: :class:`NearestFrontier`, :class:`LargestFrontier`, :class:`FixedWeight`,
  :class:`ExploreLite`, :class:`InformationGain`, :class:`RandomFrontier`, :class:`FrontierTour`,
  :class:`OracleTour`, and :func:`make_policy` for a spec as on the command line.
* The main jobs (:mod:`frontier_rl.api`): :func:`load_world`, :func:`explore`, :func:`evaluate`
  (returning an :class:`ExperimentSummary` of :class:`MethodSummary` values) and :func:`train`.

A policy of your own in a few lines, run on a generated office::

    import numpy as np
    import frontier_rl
    from frontier_rl import DecisionContext, Ranking

    class Greedy:
        \"\"\"The largest frontier per metre to drive.\"\"\"

        name = "greedy"

        def rank(self, context: DecisionContext, rng: np.random.Generator) -> Ranking:
            frontiers = context.frontiers  # sizes (cells) and distances (m) of the candidates
            return Ranking(np.argsort(-frontiers.sizes / (1.0 + frontiers.distances), kind="stable"))

    result = frontier_rl.explore("office", Greedy(), seed=0)
    print(f"{result.sim_time_s:.0f} s, {result.coverage:.0%} of the explorable space mapped")

Saved in ``greedy.py``, the same class runs on the command line as ``greedy.py:Greedy``
(``frontier-rl explore --policy greedy.py:Greedy``, ``frontier-rl evaluate --methods greedy.py:Greedy``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from frontier_rl.lazy_exports import lazy_exports
from frontier_rl.registration import ENV_IDS, env_id

__version__ = "0.1.0"

_NAMES: dict[str, str] = {
    "DecisionContext": "frontier_rl.core.sim.episode",
    "EpisodeAwarePolicy": "frontier_rl.core.sim.episode",
    "ExplorationPolicy": "frontier_rl.core.sim.episode",
    "Ranking": "frontier_rl.core.sim.episode",
    "run_episode": "frontier_rl.core.sim.episode",
    "EpisodeResult": "frontier_rl.core.sim.metrics",
    "EpisodeSummary": "frontier_rl.core.sim.metrics",
    "SimConfig": "frontier_rl.core.sim.config",
    "Frontiers": "frontier_rl.core.frontiers.detection",
    "CellState": "frontier_rl.core.world.grid",
    "OccupancyGrid": "frontier_rl.core.world.grid",
    "Pose": "frontier_rl.core.world.robot",
    "World": "frontier_rl.core.world.worlds",
    "ExploreLite": "frontier_rl.policies",
    "FixedWeight": "frontier_rl.policies",
    "FrontierTour": "frontier_rl.policies",
    "InformationGain": "frontier_rl.policies",
    "LargestFrontier": "frontier_rl.policies",
    "NearestFrontier": "frontier_rl.policies",
    "OracleTour": "frontier_rl.policies",
    "POLICY_NAMES": "frontier_rl.policies",
    "PolicySpec": "frontier_rl.policies",
    "RandomFrontier": "frontier_rl.policies",
    "make_policy": "frontier_rl.policies",
    "Failure": "frontier_rl.swarm",
    "Strategy": "frontier_rl.swarm",
    "TeamConfig": "frontier_rl.swarm",
    "TeamResult": "frontier_rl.swarm",
    "ConfigError": "frontier_rl.errors",
    "FrontierRLError": "frontier_rl.errors",
    "MapError": "frontier_rl.errors",
    "UnknownNameError": "frontier_rl.errors",
    "evaluate": "frontier_rl.api",
    "explore": "frontier_rl.api",
    "load_world": "frontier_rl.api",
    "train": "frontier_rl.api",
    "ExperimentSummary": "frontier_rl.evaluation.results.summary",
    "MethodSummary": "frontier_rl.evaluation.results.summary",
    "TrainConfig": "frontier_rl.rl.config",
}
"""Each name importable from the package, and the module that defines it (loaded on first use)."""

__getattr__, __dir__ = lazy_exports(__name__, _NAMES)

__all__ = [
    "ENV_IDS",
    "POLICY_NAMES",
    "CellState",
    "ConfigError",
    "DecisionContext",
    "EpisodeAwarePolicy",
    "EpisodeResult",
    "EpisodeSummary",
    "ExperimentSummary",
    "ExplorationPolicy",
    "ExploreLite",
    "Failure",
    "FixedWeight",
    "FrontierRLError",
    "FrontierTour",
    "Frontiers",
    "InformationGain",
    "LargestFrontier",
    "MapError",
    "MethodSummary",
    "NearestFrontier",
    "OccupancyGrid",
    "OracleTour",
    "PolicySpec",
    "Pose",
    "RandomFrontier",
    "Ranking",
    "SimConfig",
    "Strategy",
    "TeamConfig",
    "TeamResult",
    "TrainConfig",
    "UnknownNameError",
    "World",
    "__version__",
    "env_id",
    "evaluate",
    "explore",
    "load_world",
    "make_policy",
    "run_episode",
    "train",
]

if TYPE_CHECKING:
    from frontier_rl.api import evaluate, explore, load_world, train
    from frontier_rl.core.frontiers.detection import Frontiers
    from frontier_rl.core.sim.config import SimConfig
    from frontier_rl.core.sim.episode import (
        DecisionContext,
        EpisodeAwarePolicy,
        ExplorationPolicy,
        Ranking,
        run_episode,
    )
    from frontier_rl.core.sim.metrics import EpisodeResult, EpisodeSummary
    from frontier_rl.core.world.grid import CellState, OccupancyGrid
    from frontier_rl.core.world.robot import Pose
    from frontier_rl.core.world.worlds import World
    from frontier_rl.errors import ConfigError, FrontierRLError, MapError, UnknownNameError
    from frontier_rl.evaluation.results.summary import ExperimentSummary, MethodSummary
    from frontier_rl.policies import (
        POLICY_NAMES,
        ExploreLite,
        FixedWeight,
        FrontierTour,
        InformationGain,
        LargestFrontier,
        NearestFrontier,
        OracleTour,
        PolicySpec,
        RandomFrontier,
        make_policy,
    )
    from frontier_rl.rl.config import TrainConfig
    from frontier_rl.swarm import Failure, Strategy, TeamConfig, TeamResult
