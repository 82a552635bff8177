"""A model file as an actor: the network rebuilt in plain torch from the file's metadata, its
weights loaded after every check, and its most likely action for an observation.

Running a model needs torch and this package only: not Gymnasium, not Stable-Baselines3, not the
environments. The network mirrors the module layout Stable-Baselines3's actor-critic policy saves
(shared features extractor, ``mlp_extractor``, ``action_net``, ``value_net``), so that every weight
of a model file has a place of the same name and shape; the critic is loaded and checked but
never run. A zip without this project's metadata is Stable-Baselines3's own format, read by
Stable-Baselines3 when the caller trusts it (:mod:`frontier_rl.inference.sb3_zip`).
"""

from __future__ import annotations

from pathlib import Path

import torch
from torch import nn

from frontier_rl.errors import ConfigError, model_file_label
from frontier_rl.inference.bounded_zip import first_line
from frontier_rl.inference.interface import Actor, Observation, ObservationShape
from frontier_rl.inference.model_file import ModelInfo, check_fit, read_model
from frontier_rl.inference.networks import FirstColumns, FrontierPool, FrontierScores, GridFeatures
from frontier_rl.inference.tensors import observation_tensor
from frontier_rl.observation.map_image import FRONTIER_FEATURES
from frontier_rl.observation.weight_bins import WEIGHT_BINS
from frontier_rl.registration import FRONTIER_CHOICE_MODELS, MODELS, POINT_MODELS, TABLE_MODELS, TOP_K

HIDDEN = 64
"""Width of the actor's and the critic's hidden layer (SB3's ``net_arch``)."""


def model_shape(model: int, size: int) -> ObservationShape:
    """The observation and actions of model ``model`` at map images of ``size`` pixels, as its
    registered env (:data:`~frontier_rl.registration.MODELS`) has them."""
    if model in TABLE_MODELS:
        columns = len(FRONTIER_FEATURES) + MODELS[model].tour
        actions = TOP_K if model in FRONTIER_CHOICE_MODELS else WEIGHT_BINS
        return ObservationShape((3, size, size), actions, TOP_K, TOP_K * columns)
    channels = 3 if MODELS[model].with_frontiers_and_pose else 1
    return ObservationShape((channels, size, size), size * size if model in POINT_MODELS else WEIGHT_BINS)


def _mlp(n_in: int, layers: tuple[int, ...]) -> nn.Sequential:
    """SB3's ``MlpExtractor`` branch: a tanh layer per width in ``layers``."""
    modules: list[nn.Module] = []
    for width in layers:
        modules += [nn.Linear(n_in, width), nn.Tanh()]
        n_in = width
    return nn.Sequential(*modules)


class _MlpExtractor(nn.Module):
    def __init__(self, n_in: int, pi: tuple[int, ...]) -> None:
        super().__init__()
        self.policy_net = _mlp(n_in, pi)
        self.value_net = _mlp(n_in, (HIDDEN,))


class ActorCritic(nn.Module):
    """The network of model ``model`` (1-7) for ``shape``, laid out as SB3 saves it.

    Args:
        shape: what the model reads (:func:`model_shape`).
        model: the model number.
        features_dim: the map image's feature size (the file's ``features_dim``).
    """

    def __init__(self, shape: ObservationShape, model: int, features_dim: int) -> None:
        super().__init__()
        self._shape = shape
        pointer = model in FRONTIER_CHOICE_MODELS
        extractor: GridFeatures | FrontierScores | FrontierPool
        if model in TABLE_MODELS:
            table = (shape.image[0], shape.table_rows, shape.table_length // shape.table_rows, features_dim)
            extractor = FrontierScores(*table) if pointer else FrontierPool(*table)
        else:
            extractor = GridFeatures(shape.image[0], features_dim)
        self.features_extractor = extractor  # shared by the actor and the critic, under SB3's three names
        self.pi_features_extractor = extractor
        self.vf_features_extractor = extractor
        self.mlp_extractor = _MlpExtractor(extractor.features_dim, () if pointer else (HIDDEN,))
        self.action_net: nn.Module = FirstColumns(shape.actions) if pointer else nn.Linear(HIDDEN, shape.actions)
        self.value_net = nn.Linear(HIDDEN, 1)

    @property
    def shape(self) -> ObservationShape:
        """What the model reads and answers."""
        return self._shape

    def network_input(self, observation: Observation) -> torch.Tensor | dict[str, torch.Tensor]:
        """``observation`` as a batch of one, as SB3 preprocesses it: the map image over 255, the
        rest as float32 (the same float32 division)."""
        if not isinstance(observation, dict):
            return observation_tensor(observation, self._shape.image, image=True)
        rows, length = self._shape.table_rows, self._shape.table_length
        return {
            "map": observation_tensor(observation["map"], self._shape.image, image=True),
            "frontiers": observation_tensor(observation["frontiers"], (length,), image=False),
            "mask": observation_tensor(observation["mask"], (rows,), image=False),
        }

    def act(self, observation: Observation) -> int:
        """The most likely action: the argmax of the probabilities, computed as SB3's categorical
        distribution computes them, so that ties fall as SB3's deterministic ``predict`` has them."""
        with torch.inference_mode():
            features = self.pi_features_extractor(self.network_input(observation))
            logits = self.action_net(self.mlp_extractor.policy_net(features))
            normalized = logits - logits.logsumexp(dim=-1, keepdim=True)  # as torch's Categorical keeps them
            return int(torch.argmax(torch.softmax(normalized, dim=-1), dim=1).item())


def load_actor(path: str | Path, trust: bool = False) -> tuple[Actor, ModelInfo | None]:
    """The model file at ``path`` as an actor, and its metadata.

    Args:
        path: a zip written by ``frontier-rl train``.
        trust: also load an SB3 zip without this project's metadata with SB3's own load, which
            unpickles (and can run) code from the file; its metadata is then None.
    """
    path = Path(path)
    where = model_file_label(path)
    info, state = read_model(path, trust)
    if info is None:
        from frontier_rl.inference.sb3_zip import load_sb3_actor  # SB3 and Gymnasium, only for such a file

        return load_sb3_actor(path), None
    network = ActorCritic(model_shape(info.model, info.observation_size), info.model, info.features_dim)
    check_fit(network.state_dict(), state, info, where)
    try:
        network.load_state_dict(state)
    except Exception as exc:
        raise ConfigError(f"{where} does not fit {info.env_id} ({first_line(exc)})") from None
    network.eval()
    return network, info
