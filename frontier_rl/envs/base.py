"""The shared Gymnasium machinery: one decision per ``step()``, an exact seeded ``reset()``."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace
from typing import Any, Generic, TypeVar

import gymnasium as gym
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.leg_result import LegResult
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.envs.rewards import RewardConfig, reward_preset
from frontier_rl.envs.world_source import WorldSource, reset_world_seed
from frontier_rl.errors import ConfigError, short_repr
from frontier_rl.observation.map_image import THESIS_INPUT_CELLS, MapEncoder
from frontier_rl.render import FrameCanvas, rgb_array
from frontier_rl.world_spec import world_entries

MAX_WORLD_DRAWS = 100
"""How many worlds a reset draws at most for one that is not explored from its start: an episode
that ends before its first decision has nothing to learn, and a step after it raised."""

ObsT = TypeVar("ObsT")


@dataclass(frozen=True)
class EnvConfig:
    """Settings shared by every frontier_rl environment.

    Attributes:
        worlds: generator names, map files and folders, each optionally "=WEIGHT"; each reset
            draws a family by weight, then one of its files uniformly
            (:func:`~frontier_rl.world_spec.parse_world_mix`).
        world_split: "train", or "validation" for a folder's held-out files
            (:class:`~frontier_rl.envs.world_source.WorldSource`).
        reward: reward preset name ("normalised" or "thesis", see :mod:`frontier_rl.envs.rewards`).
        observation_size: edge of the map image (pixels): 250 (the thesis) or 64 (Niroui et al.).
        max_decisions: the episode is truncated after this many steps (a stuck agent never hangs).
        resolution: cell size (m) for map files that carry none.
        sim: the simulator's settings (robot, LiDAR, mapping, navigation, the sim-time cap).
    """

    worlds: tuple[str, ...] = ("office",)
    reward: str = "normalised"
    observation_size: int = THESIS_INPUT_CELLS
    max_decisions: int = 1000
    resolution: float | None = None
    world_split: str = "train"
    sim: SimConfig = field(default_factory=SimConfig)

    def __post_init__(self) -> None:
        reward_preset(self.reward)  # check the name now
        if self.max_decisions < 1:
            raise ConfigError(f"max_decisions must be >= 1, got {self.max_decisions!r}")

    @classmethod
    def from_kwargs(cls, config: EnvConfig | None = None, **overrides: Any) -> EnvConfig:
        """``config`` (or the defaults) with ``overrides``; ``worlds`` may be a comma-separated string."""
        known = {f.name for f in fields(cls)}
        unknown = sorted(set(overrides) - known)
        if unknown:
            raise ConfigError(f"unknown environment option(s) {', '.join(unknown)}; known: {', '.join(sorted(known))}")
        if isinstance(overrides.get("worlds"), str):
            overrides["worlds"] = world_entries(overrides["worlds"])
        elif "worlds" in overrides:
            overrides["worlds"] = tuple(overrides["worlds"])
        return replace(config or cls(), **overrides)


class ExplorationEnv(gym.Env[ObsT, np.int64], Generic[ObsT]):
    """Base of the frontier_rl envs: a world per reset, one decision per step.

    Subclasses set ``observation_space`` and ``action_space`` and implement :meth:`_observe`
    and :meth:`_act`. ``reset(options={"world_seed": k})`` picks generator seed ``k`` (an
    evaluation world) instead of a random training seed; other keys, and a seed that is not a
    non-negative integer, raise :class:`~frontier_rl.errors.ConfigError`.
    """

    metadata: dict[str, Any] = {"render_modes": ["rgb_array"], "render_fps": 4}  # noqa: RUF012 (gymnasium's API)

    def __init__(self, config: EnvConfig | None = None, render_mode: str | None = None, **overrides: Any) -> None:
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ConfigError(f"render_mode must be one of {self.metadata['render_modes']}, got {render_mode!r}")
        self.config = EnvConfig.from_kwargs(config, **overrides)
        self.render_mode = render_mode
        self.rewards: RewardConfig = reward_preset(self.config.reward)
        self.source = WorldSource(self.config.worlds, self.config.resolution, self.config.world_split)
        self._sim: ExplorationSimulator | None = None
        self._decisions = 0

    @property
    def sim(self) -> ExplorationSimulator:
        """The running episode's simulator."""
        if self._sim is None:
            raise RuntimeError("call reset() before using the environment")
        return self._sim

    # ----------------------------------------------------------- gym API
    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[ObsT, dict[str, Any]]:
        """A new world, robot, map, navigator and blacklist, all drawn from the env's seed.

        Raises:
            ConfigError: ``options`` has a key other than ``world_seed`` or a value of the wrong kind
                (see :func:`~frontier_rl.envs.world_source.reset_world_seed`).
        """
        world_seed = reset_world_seed(options)  # checked before anything changes
        super().reset(seed=seed)
        for _ in range(MAX_WORLD_DRAWS):
            world = self.source.sample(self.np_random, world_seed)
            sim_rng = np.random.default_rng(int(self.np_random.integers(2**63 - 1)))
            self._sim = ExplorationSimulator(world, self.config.sim, sim_rng)
            if not self._sim.finished:
                break
            # explored from its start (a room the sensor sees whole): another start, or world, is drawn; a
            # world_seed given moves by the number of families, keeping a validation episode's family
            world_seed = None if world_seed is None else world_seed + len(self.source.families)
        else:
            raise ConfigError(
                f"each of {MAX_WORLD_DRAWS} worlds drawn from {short_repr(','.join(self.config.worlds))} had no "
                "frontier left at its start (maps the sensor sees whole from where the robot starts?)"
            )
        self._decisions = 0
        return self._observe(), self._info(None)

    def step(self, action: Any) -> tuple[ObsT, float, bool, bool, dict[str, Any]]:
        """Take one decision and simulate the drive that follows it."""
        sim = self.sim
        if sim.finished or sim.truncated or self._decisions >= self.config.max_decisions:
            raise RuntimeError("the episode has ended; call reset() before step()")
        index = self._check_action(action)
        coverage_before = sim.coverage
        leg, extra = self._act(index)
        self._decisions += 1
        terminated = sim.finished
        truncated = not terminated and (sim.truncated or self._decisions >= self.config.max_decisions)
        reward = self.rewards.leg_reward(leg, sim.coverage - coverage_before, terminated) + extra
        return self._observe(), float(reward), terminated, truncated, self._info(leg)

    def render(self) -> NDArray[np.uint8] | None:
        """An RGB picture: the true world with the path | the robot's map with the frontiers."""
        if self.render_mode != "rgb_array":
            return None
        sim = self.sim
        return rgb_array(
            FrameCanvas(sim.world.grid, scale=2).episode(sim.map(), sim.trajectory(), sim.frontiers().centers)
        )

    # ------------------------------------------------------ subclass hooks
    def _observe(self) -> ObsT:
        raise NotImplementedError

    def _act(self, action: int) -> tuple[LegResult, float]:
        """Carry out ``action``; returns the leg and any reward beyond the preset's leg reward."""
        raise NotImplementedError

    # -------------------------------------------------------------- helpers
    def _check_action(self, action: Any) -> int:
        """``action`` as an int in the action space, or a ValueError naming it."""
        value = np.asarray(action)
        real = np.issubdtype(value.dtype, np.integer) or np.issubdtype(value.dtype, np.floating)
        if value.size != 1 or not real:  # a complex number, a string, a list of several, ...
            raise ValueError(f"action must be one integer, got {action!r}")
        scalar = value.reshape(()).item()
        if not math.isfinite(scalar) or scalar != int(scalar):
            raise ValueError(f"action must be a finite integer, got {action!r}")
        index = int(scalar)
        n = int(self.action_space.n)  # type: ignore[attr-defined]
        if not 0 <= index < n:
            raise ValueError(f"action {index} is outside the action space 0..{n - 1}")
        return index

    def _info(self, leg: LegResult | None) -> dict[str, Any]:
        sim = self.sim
        info: dict[str, Any] = {
            "sim_time_s": sim.sim_time,
            "coverage": sim.coverage,
            "decisions": self._decisions,
            "world": sim.world.name,
            "frontiers": len(sim.frontiers()),
        }
        if leg is not None:
            info["outcome"] = leg.outcome.value
            info["leg_time_s"] = leg.duration_s
        return info


class MapImageEnv(ExplorationEnv[NDArray[np.uint8]]):
    """An env whose observation is the map image, with the frontier and pose channels if asked
    (the thesis's models 1 and 3) or without (models 2 and 4). Subclasses give the action space.

    Args:
        config: shared settings (:class:`EnvConfig`).
        with_frontiers_and_pose: add the frontier and pose channels.
        render_mode: None or "rgb_array".
        **overrides: fields of :class:`EnvConfig`.
    """

    def __init__(
        self,
        config: EnvConfig | None = None,
        with_frontiers_and_pose: bool = False,
        render_mode: str | None = None,
        **overrides: Any,
    ) -> None:
        super().__init__(config, render_mode, **overrides)
        self.encoder = MapEncoder(self.config.observation_size, with_frontiers_and_pose, with_frontiers_and_pose)
        self.observation_space = gym.spaces.Box(0, 255, self.encoder.shape, np.uint8)
        self.action_space = self._make_action_space()

    def _make_action_space(self) -> gym.spaces.Discrete:
        raise NotImplementedError

    def _observe(self) -> NDArray[np.uint8]:
        sim = self.sim
        cand = sim.candidates()
        return self.encoder.encode(cand.grid, sim.pose, cand.frontiers)
