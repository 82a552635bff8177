"""Learning across robots: a PettingZoo ParallelEnv in which every robot of a team is an agent.

Robots decide at different times (each when its leg ends), so a step is one decision: the robots
waiting for one (``infos[agent]["acting"]``) carry out their actions, then the team's shared clock
runs until the next robot needs a decision. The other agents' actions are ignored that step.
Every surviving robot observes its own map each step. The reward is shared (the team's progress):
``scale × (per_coverage × coverage gained + per_free_cell × cells newly known to the team −
per_second × team time elapsed + end_bonus when the map is done)``. A failed robot's agent
terminates; the others terminate when the map is done and truncate at the sim-time cap or the
decision limit.
"""

from __future__ import annotations

import functools
from typing import Any

import gymnasium as gym
import numpy as np
from numpy.typing import NDArray
from pettingzoo import ParallelEnv

from frontier_rl.core.frontiers.ranking import rank, weighted_cost
from frontier_rl.core.sim.episode import Ranking
from frontier_rl.envs.base import EnvConfig
from frontier_rl.envs.rewards import RewardConfig, reward_preset
from frontier_rl.envs.world_source import WorldSource, reset_world_seed
from frontier_rl.errors import ConfigError, short_repr
from frontier_rl.observation.frontier_table import FEATURE_BOUND, simulator_observation, slot_order
from frontier_rl.observation.map_image import FRONTIER_FEATURES, MapEncoder
from frontier_rl.observation.weight_bins import WEIGHT_BINS, bin_to_weight
from frontier_rl.registration import ModelKind
from frontier_rl.render import FrameCanvas, rgb_array
from frontier_rl.swarm import TeamConfig, TeamSimulator

ACTIONS = (ModelKind.WEIGHT, ModelKind.FRONTIER)
"""The agents' action kinds: a weight bin of eq. 3.1 (models 3 and 4), or a candidate frontier (model 5)."""

Observation = NDArray[np.uint8] | dict[str, NDArray[Any]]


class TeamExplorationEnv(ParallelEnv):  # type: ignore[misc]  # pettingzoo ships no type information
    """A team exploring one world; agents ``robot_0`` .. ``robot_{N-1}``.

    Args:
        config: world, reward, observation size, decision limit and simulator settings (the
            decision limit counts the team's decisions).
        team: team size, strategy, communication range and failures.
        action: "weight" (observation: the robot's map with frontier and pose channels; action: a
            weight bin) or "frontier" (the frontier-choice observation and action of model 5).
        top_k: candidate slots of the "frontier" action.
        render_mode: None or "rgb_array".
        **overrides: fields of :class:`~frontier_rl.envs.base.EnvConfig`.
    """

    metadata: dict[str, Any] = {"name": "frontier_team_v0", "render_modes": ["rgb_array"], "render_fps": 4}  # noqa: RUF012

    def __init__(
        self,
        config: EnvConfig | None = None,
        team: TeamConfig | None = None,
        action: ModelKind | str = ModelKind.WEIGHT,
        top_k: int = 16,
        render_mode: str | None = None,
        **overrides: Any,
    ) -> None:
        if action not in ACTIONS:
            raise ConfigError(f"action must be one of {', '.join(ACTIONS)}, got {short_repr(action)}")
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ConfigError(f"render_mode must be one of {self.metadata['render_modes']}, got {render_mode!r}")
        if not 1 <= top_k <= 256:
            raise ConfigError(f"top_k must be between 1 and 256, got {top_k!r}")
        self.config = EnvConfig.from_kwargs(config, **overrides)
        self.team_config = team or TeamConfig(robots=2)
        self.action_kind = ModelKind(action)
        self.top_k = top_k
        self.render_mode = render_mode
        self.rewards: RewardConfig = reward_preset(self.config.reward)
        self.source = WorldSource(self.config.worlds, self.config.resolution, self.config.world_split)
        self.encoder = MapEncoder(self.config.observation_size, frontier_channel=True, pose_channel=True)
        self.possible_agents = [f"robot_{i}" for i in range(self.team_config.robots)]
        self.agents: list[str] = []
        self._team: TeamSimulator | None = None
        self._acting: int | None = None
        self._slots: dict[int, NDArray[np.int64]] = {}
        self._decisions = 0
        self._rng = np.random.default_rng()

    # ---------------------------------------------------------------- spaces
    @functools.cache  # noqa: B019 (PettingZoo wants the same object for every call)
    def observation_space(self, agent: str) -> gym.spaces.Space[Any]:
        """The map image (weight), or the map, frontier table and mask (frontier)."""
        image = gym.spaces.Box(0, 255, self.encoder.shape, np.uint8)
        if self.action_kind is ModelKind.WEIGHT:
            return image
        table = gym.spaces.Box(-FEATURE_BOUND, FEATURE_BOUND, (self.top_k * len(FRONTIER_FEATURES),), np.float32)
        return gym.spaces.Dict(
            {"map": image, "frontiers": table, "mask": gym.spaces.Box(0.0, 1.0, (self.top_k,), np.float32)}
        )

    @functools.cache  # noqa: B019
    def action_space(self, agent: str) -> gym.spaces.Space[Any]:
        """A weight bin (w = a / 100) or a frontier slot."""
        return gym.spaces.Discrete(WEIGHT_BINS if self.action_kind is ModelKind.WEIGHT else self.top_k)

    @property
    def team(self) -> TeamSimulator:
        """The running episode's team."""
        if self._team is None:
            raise RuntimeError("call reset() before using the environment")
        return self._team

    # ------------------------------------------------------------- the API
    def reset(
        self, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, Observation], dict[str, dict[str, Any]]]:
        """A new world and team, drawn from ``seed`` (``options={"world_seed": k}`` picks a world; a
        seed of the wrong kind, or a key that looks like a misspelt ``world_seed``, raises
        :class:`~frontier_rl.errors.ConfigError`; other keys are let pass, as PettingZoo's API test
        resets with ``{"options": 1}``)."""
        world_seed = reset_world_seed(options, ignore_unknown=True)  # checked before anything changes
        if seed is not None or self._team is None:
            self._rng = np.random.default_rng(seed)
        world = self.source.sample(self._rng, world_seed)
        team_rng = np.random.default_rng(int(self._rng.integers(2**63 - 1)))
        self._team = TeamSimulator(world, self.config.sim, self.team_config, team_rng)
        self.agents = self.possible_agents[:]
        self._decisions = 0
        self._acting = self._team.next_decision()
        return self._observations(), self._infos()

    def step(
        self, actions: dict[str, Any]
    ) -> tuple[dict[str, Observation], dict[str, float], dict[str, bool], dict[str, bool], dict[str, dict[str, Any]]]:
        """The acting robot carries out its action; the team then runs to the next decision."""
        team = self.team
        if not self.agents:
            raise RuntimeError("the episode has ended; call reset() before step()")
        live = self.agents[:]
        coverage, known, clock = team.coverage, team.known_cells, team.sim_time
        if self._acting is not None:
            agent = f"robot_{self._acting}"
            if agent not in actions:
                raise ValueError(
                    f"{agent} must act this step (infos[{agent!r}]['acting']), got actions for {sorted(actions)}"
                )
            team.assign(self._acting, self._ranking(self._acting, actions[agent]))
            self._decisions += 1
        self._acting = team.next_decision()
        done = team.done
        truncated_all = not done and (team.over or self._decisions >= self.config.max_decisions)
        gain = team.coverage - coverage
        total = (
            self.rewards.per_coverage * gain
            + self.rewards.per_free_cell * (team.known_cells - known)
            - self.rewards.per_second * (team.sim_time - clock)
            + (self.rewards.end_bonus if done else 0.0)
        )
        reward = {agent: float(self.rewards.scale * total) for agent in live}
        failed = {f"robot_{r.index}" for r in team.robots if not r.alive}
        terminations = {agent: done or agent in failed for agent in live}
        truncations = {agent: truncated_all and agent not in failed for agent in live}
        observations = self._observations(live)
        infos = self._infos(live)
        self.agents = [a for a in live if not (terminations[a] or truncations[a])]
        return observations, reward, terminations, truncations, infos

    def render(self) -> NDArray[np.uint8] | None:
        """The true world with every robot's path | the surviving robots' merged map."""
        if self.render_mode != "rgb_array":
            return None
        team = self.team
        trajectories = [robot.sim.trajectory() for robot in team.robots]
        return rgb_array(FrameCanvas(team.world.grid, scale=2).team(team.team_map(), trajectories))

    def close(self) -> None:
        """Nothing to release."""

    # --------------------------------------------------------------- helpers
    def _ranking(self, index: int, action: Any) -> Ranking:
        space = self.action_space(f"robot_{index}")
        value = np.asarray(action)
        if value.size != 1 or not space.contains(np.int64(value.reshape(()).item())):
            raise ValueError(f"action {action!r} of robot_{index} is outside {space}")
        choice = int(value.reshape(()).item())
        sim = self.team.robots[index].sim
        if self.action_kind is ModelKind.WEIGHT:
            weight = bin_to_weight(choice)
            return Ranking(rank(weighted_cost(sim.frontiers(), weight)), weight)
        return Ranking(slot_order(self._slots[index], choice))

    def _observations(self, agents: list[str] | None = None) -> dict[str, Observation]:
        out: dict[str, Observation] = {}
        for agent in agents if agents is not None else self.agents:
            index = int(agent.removeprefix("robot_"))
            sim = self.team.robots[index].sim
            if self.action_kind is ModelKind.WEIGHT:
                cand = sim.candidates()
                out[agent] = self.encoder.encode(cand.grid, sim.pose, cand.frontiers)
            else:
                out[agent], self._slots[index] = simulator_observation(self.encoder, self.top_k, sim)
        return out

    def _infos(self, agents: list[str] | None = None) -> dict[str, dict[str, Any]]:
        team = self.team
        infos = {}
        for agent in agents if agents is not None else self.agents:
            robot = team.robots[int(agent.removeprefix("robot_"))]
            infos[agent] = {
                "acting": robot.index == self._acting,
                "sim_time_s": robot.sim.sim_time,
                "team_coverage": team.coverage,
                "frontiers": len(robot.sim.frontiers()) if robot.alive else 0,
                "failed": not robot.alive,
                "world": team.world.name,
            }
        return infos


def parallel_env(**kwargs: Any) -> TeamExplorationEnv:
    """PettingZoo's constructor convention: ``frontier_rl.envs.team_env.parallel_env(...)``."""
    return TeamExplorationEnv(**kwargs)
