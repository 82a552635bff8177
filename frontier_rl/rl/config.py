"""The training run's settings: one frozen, documented dataclass, dumped into every run directory."""

from __future__ import annotations

import shlex
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

from frontier_rl.checked_values import coerce, enum_member
from frontier_rl.config_files import dump_config, from_dict, load_config, to_dict
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.world.scale import checked_resolution
from frontier_rl.envs.rewards import REWARD_PRESETS, reward_preset
from frontier_rl.errors import ConfigError, FrontierRLError, short_repr, short_text
from frontier_rl.inference.model_file import MAX_FEATURES_DIM, MAX_TIMESTEPS
from frontier_rl.registration import FRONTIER_CHOICE_MODELS, MODELS, Algorithm, env_id
from frontier_rl.world_spec import parse_world_mix

MAX_ENVS = 64
"""Most parallel environments: each is a process of about 400 MB with a map and a model."""

MAX_LEARNING_RATE = 1.0
"""Largest ``learning_rate``: far above any that trains (the defaults are 7e-4 and 3e-4)."""

MAX_LOSS_COEF = 100.0
"""Largest ``vf_coef`` and ``ent_coef`` (the defaults are 0.5 and 0.001)."""

MAX_ROLLOUT_PIXELS = 2**28
"""Most map pixels one rollout may hold (``n_steps`` × ``n_envs`` observations of
``observation_size`` × ``observation_size`` pixels, float32: 1 GiB); 65,536 decisions at 64², 4,294 at 250²."""

#: Longest error message passed on from a check of ``worlds`` (characters).
_MESSAGE_LIMIT = 300


_CLI_OPTIONS = (
    "model",
    "worlds",
    "timesteps",
    "n_envs",
    "algo",
    "observation_size",
    "reward",
    "learning_rate",
    "n_steps",
    "gamma",
    "ent_coef",
    "seed",
    "eval_every",
    "checkpoint_every",
    "init",
    "privileged_critic",
    "privileged_map",
    "resolution",
)
"""The fields ``frontier-rl train`` sets by an option of the same name."""


@dataclass(frozen=True)
class TrainConfig:
    """What ``frontier-rl train`` does.

    Attributes:
        model: model 1-7: the thesis's 1-4, its future work 5, and 6 and 7 (see
            :data:`frontier_rl.registration.MODELS`).
        worlds: comma-separated generator names, map files, folders and catalogue maps or
            collections (``frontier-rl maps``), each optionally with a sampling weight
            ("office=2,dungeon/train=3"), drawn per episode; a folder's or a collection's
            validation files (one in ten) are never trained on.
        timesteps: decisions to train for (one env step = one decision).
        n_envs: parallel environments (subprocesses when > 1).
        algo: a2c (the thesis), ppo, or dagger (models 5 and 7: imitation of a teacher that
            looks ahead on copies of the simulator, :mod:`frontier_rl.rl.imitation`).
        observation_size: map image edge, 64 (Niroui et al., the default: 15× fewer pixels) or 250.
        reward: reward preset, "normalised" (trains well) or "thesis" (tables 3.1 / 3.2).
        learning_rate: optimizer step size; SB3's A2C default 7e-4 (RMSprop), 3e-4 for PPO (Adam).
        n_steps: decisions per env between updates; A2C's default is 5, 8 spreads a batch over
            more of an episode (~100 decisions on the office world).
        gamma: discount per decision.
        vf_coef: value-loss weight, 0.5 as in the thesis.
        ent_coef: entropy bonus, 0.001 as in the thesis.
        features_dim: size of the CNN's feature vector.
        max_decisions: an episode is truncated after this many decisions (an untrained point
            model can choose useless cells for a long time).
        eval_every: decisions between evaluations on held-out validation worlds (0: never).
        eval_episodes: validation episodes per evaluation.
        checkpoint_every: decisions between checkpoints (0: only the final model).
        seed: seeds the envs, the network and the update order.
        init: a model file (written by ``frontier-rl train``, same model, observation size and
            ``features_dim``) whose policy weights start the run; "" starts from random weights.
            Only the weights are taken, never an optimizer state or a step count.
        privileged_critic: models 5 and 7 with "a2c" or "ppo" only: the critic also reads what only the
            simulator knows (the unseen share and area of the true map), through a value head the
            model file leaves out (:class:`~frontier_rl.rl.networks.PointerPolicy`).
        privileged_map: with ``privileged_critic``: that head also sees the true map's explorable
            space not yet seen, as an image over the map window (a CNN of its own).
        sim: the simulator trained on (robot, LiDAR, map update, navigation, time cap), the
            defaults unless ``frontier-rl train --config`` names a SimConfig file.
        resolution: cell size (m) of every map file trained on, a ROS YAML's own replaced; None: each
            file's own (a ROS YAML's) or its format's default (DungeonMaps 0.04375 m, HouseExpo and
            bitmaps 0.05 m). Generated worlds keep theirs.
    """

    model: int = 4
    worlds: str = "office"
    timesteps: int = 100_000
    n_envs: int = 2
    algo: Algorithm = Algorithm.A2C
    observation_size: int = 64
    reward: str = "normalised"
    learning_rate: float = 7e-4
    n_steps: int = 8
    gamma: float = 0.99
    vf_coef: float = 0.5
    ent_coef: float = 0.001
    features_dim: int = 128
    max_decisions: int = 1000
    eval_every: int = 10_000
    eval_episodes: int = 6
    checkpoint_every: int = 10_000
    seed: int = 0
    init: str = ""
    privileged_critic: bool = False
    privileged_map: bool = False
    sim: SimConfig = field(default_factory=SimConfig)
    resolution: float | None = None

    def __post_init__(self) -> None:  # noqa: C901 (a validator: one check per field)
        if self.model not in MODELS:
            raise ConfigError(f"unknown model {short_repr(self.model)}; choose one of {', '.join(map(str, MODELS))}")
        if not isinstance(self.algo, Algorithm):  # a2c given as text, in Python
            object.__setattr__(self, "algo", enum_member(Algorithm, self.algo, "algo"))
        if self.algo is Algorithm.DAGGER and self.model not in FRONTIER_CHOICE_MODELS:
            raise ConfigError(
                f"algorithm 'dagger' trains models 5 and 7 (frontier choice) only, got model {self.model!r}"
            )
        if not isinstance(self.sim, SimConfig):
            raise ConfigError(f"sim must be a SimConfig, got {short_repr(self.sim)}")
        self._check_privileged()
        if not isinstance(self.observation_size, int) or isinstance(self.observation_size, bool):
            raise ConfigError(f"observation_size must be an integer, got {short_repr(self.observation_size)}")
        env_id(self.model, self.observation_size)  # checks the size
        for name in ("worlds", "init"):
            if not isinstance(getattr(self, name), str):
                raise ConfigError(f"{name} must be a string, got {short_repr(getattr(self, name))}")
        if self.resolution is not None:
            checked_resolution(coerce(float, self.resolution, "resolution"), "resolution")
        try:
            parse_world_mix(self.worlds)  # checks every world now, not in a subprocess later
        except FrontierRLError as exc:  # it quotes the whole list: keep the message bounded
            raise type(exc)(short_text(str(exc), _MESSAGE_LIMIT)) from None
        except OSError as exc:  # a name the file system refuses to look up (too long, ...)
            raise ConfigError(f"worlds: cannot look up {short_repr(self.worlds)}: {exc.strerror or exc}") from None
        if not isinstance(self.reward, str) or self.reward not in REWARD_PRESETS:
            raise ConfigError(
                f"unknown reward preset {short_repr(self.reward)}; choose one of {', '.join(REWARD_PRESETS)}"
            )
        reward_preset(self.reward)
        for name in ("timesteps", "n_envs", "n_steps", "features_dim", "max_decisions", "eval_episodes"):
            value = coerce(int, getattr(self, name), name)
            if value < 1:
                raise ConfigError(f"{name} must be >= 1, got {value!r}")
        for name in ("eval_every", "checkpoint_every", "seed"):
            value = coerce(int, getattr(self, name), name)
            if value < 0:
                raise ConfigError(f"{name} must be >= 0, got {value!r}")
        # what a model file may hold (inference/model_file.py refuses more), and NumPy's legacy seeding
        for name, high in (("features_dim", MAX_FEATURES_DIM), ("timesteps", MAX_TIMESTEPS), ("seed", 2**32 - 1)):
            if getattr(self, name) > high:
                raise ConfigError(f"{name} must be <= {high}, got {short_repr(getattr(self, name))}")
        if self.n_envs > MAX_ENVS:
            raise ConfigError(f"n_envs must be <= {MAX_ENVS} (a process each), got {short_repr(self.n_envs)}")
        self._check_rollout()
        for name in ("learning_rate", "gamma", "vf_coef", "ent_coef"):
            coerce(float, getattr(self, name), name)
        if not 0 < self.learning_rate <= MAX_LEARNING_RATE:
            raise ConfigError(f"learning_rate must be in (0, {MAX_LEARNING_RATE:g}], got {self.learning_rate!r}")
        if not 0 < self.gamma <= 1:
            raise ConfigError(f"gamma must be in (0, 1], got {self.gamma!r}")
        for name in ("vf_coef", "ent_coef"):
            if not 0 <= getattr(self, name) <= MAX_LOSS_COEF:
                raise ConfigError(f"{name} must be in [0, {MAX_LOSS_COEF:g}], got {getattr(self, name)!r}")

    def _check_privileged(self) -> None:
        """The privileged critic: booleans, the image a part of it, for models 5 and 7 with A2C or PPO."""
        for name in ("privileged_critic", "privileged_map"):
            if not isinstance(getattr(self, name), bool):
                raise ConfigError(f"{name} must be true or false, got {short_repr(getattr(self, name))}")
        if self.privileged_map and not self.privileged_critic:
            raise ConfigError("privileged_map is a part of the privileged critic: set privileged_critic too")
        if self.privileged_critic and (self.model not in FRONTIER_CHOICE_MODELS or self.algo is Algorithm.DAGGER):
            raise ConfigError(
                "a privileged critic is for models 5 and 7 with a2c or ppo, "
                f"got model {self.model!r} with {self.algo.value}"
            )

    def _check_rollout(self) -> None:
        """A2C's and PPO's rollouts (``n_steps`` × ``n_envs`` decisions; DAgger has none): they fit
        in memory and in the run, and PPO's minibatches hold two decisions or more."""
        if self.algo is Algorithm.DAGGER:
            return
        rollout = self.n_steps * self.n_envs
        what = f"one rollout (n_steps {self.n_steps:,} x n_envs {self.n_envs} = {rollout:,} decisions)"
        if rollout * self.observation_size**2 > MAX_ROLLOUT_PIXELS:
            most = MAX_ROLLOUT_PIXELS // self.observation_size**2
            raise ConfigError(f"{what} is more than {most:,} maps of {self.observation_size}² pixels can fill in 1 GiB")
        if rollout > self.timesteps:
            raise ConfigError(f"{what} is more than timesteps {self.timesteps:,}: SB3 always finishes a rollout")
        if self.algo is Algorithm.PPO and rollout < 2:
            raise ConfigError(f"{what} is too few for PPO: its minibatches need 2 decisions or more")

    @property
    def env_id(self) -> str:
        """The Gymnasium id trained on."""
        return env_id(self.model, self.observation_size)

    def to_dict(self) -> dict[str, Any]:
        """Plain values, for YAML."""
        return to_dict(self)

    @classmethod
    def from_dict(cls, values: dict[str, Any]) -> TrainConfig:
        """A config from plain values; unknown keys and values of the wrong type are errors."""
        return from_dict(cls, values)

    def command(self) -> str:
        """The ``frontier-rl train`` options that give this config (without ``--out``): the model,
        worlds and timesteps always, every other option only where it differs from its default;
        fields the command line has no option for are added as ``(also name=value)``."""
        default = TrainConfig()
        parts = ["frontier-rl train"]
        for name in _CLI_OPTIONS:
            value = getattr(self, name)
            if name in ("model", "worlds", "timesteps") or value != getattr(default, name):
                option = f"--{name.replace('_', '-')}"
                parts.append(option if value is True else f"{option} {shlex.quote(str(value))}")
        other = [
            f"{f.name}={getattr(self, f.name)}"
            for f in fields(self)
            if f.name not in _CLI_OPTIONS and f.name != "sim" and getattr(self, f.name) != getattr(default, f.name)
        ]
        other += _differences("sim", to_dict(self.sim), to_dict(default.sim))  # set by --config, a file
        return " ".join(parts) + (f" (also {', '.join(other)})" if other else "")

    def dump(self, path: Path) -> None:
        """Write the config as YAML."""
        dump_config(self, path)

    @classmethod
    def load(cls, path: Path) -> TrainConfig:
        """Read a config written by :meth:`dump` (:func:`~frontier_rl.config_files.load_config`); an
        empty file is an error, not the defaults: it would claim a training run never made."""
        return load_config(cls, path, "training config", allow_empty=False)


def _differences(prefix: str, values: dict[str, Any], defaults: dict[str, Any]) -> list[str]:
    """``prefix.field=value`` for every (nested) field of ``values`` that differs from ``defaults``."""
    found: list[str] = []
    for name, value in values.items():
        if isinstance(value, dict):
            found += _differences(f"{prefix}.{name}", value, defaults[name])
        elif value != defaults[name]:
            found.append(f"{prefix}.{name}={value}")
    return found
