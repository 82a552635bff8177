"""Model files: Stable-Baselines3 zips with a ``frontier_rl.json`` entry saying what they are.

A model file is untrusted input. Loading one without ``trust``:

1. checks the zip before anything in it is read (:mod:`frontier_rl.rl.bounded_zip`): at most
   :data:`MAX_MEMBERS` members, each stored or deflated, none over 256 MiB uncompressed, all
   together at most 1 GiB, none compressed more than 200 to 1;
2. reads ``frontier_rl.json`` (at most :data:`MAX_METADATA_BYTES`) and checks every field against
   what ``frontier-rl train`` writes: a known model number, one of the project's own Gymnasium ids
   fitting that model and image size, a known algorithm, whole numbers in range, no other keys.
   Nothing from the file reaches ``gymnasium.make`` or an import unchecked;
3. rebuilds the network from those fields and reads only ``policy.pth``, as plain tensors
   (``torch.load(weights_only=True)``, never unpickling code), after the same size checks on the
   torch archive inside it; every tensor must have the name, shape and dtype of the rebuilt network.

SB3's own ``load`` unpickles parts of the zip, which can run code from the file; it is used only
when the caller says the file is trusted (``--trust-model``), and after the same zip checks.
Every problem is one :class:`~frontier_rl.errors.ConfigError` line naming the file and the field.
"""

from __future__ import annotations

import io
import json
import pickle
import warnings
import zipfile
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import asdict, dataclass, fields
from pathlib import Path
from typing import Any

import gymnasium as gym
import torch
from stable_baselines3 import A2C, PPO
from stable_baselines3.common.base_class import BaseAlgorithm
from stable_baselines3.common.policies import ActorCriticCnnPolicy, ActorCriticPolicy

import frontier_rl.envs
from frontier_rl.atomic_write import write_bytes_atomic
from frontier_rl.errors import QUOTE_LIMIT, ConfigError, TrainingDivergedError, model_file_label, short_repr
from frontier_rl.registration import ENV_IDS, FRONTIER_CHOICE_MODELS, MODELS, OBSERVATION_SIZES, env_id
from frontier_rl.rl.bounded_zip import MAX_MEMBER_BYTES, first_line, open_checked_zip, read_member
from frontier_rl.rl.config import MAX_FEATURES_DIM, MAX_TIMESTEPS
from frontier_rl.rl.networks import PRIVILEGED_HEAD, FrontierPooling, FrontierScorer, GridCNN, PointerPolicy

METADATA_ENTRY = "frontier_rl.json"
WEIGHTS_ENTRY = "policy.pth"
FORMAT_VERSION = 1
ALGORITHMS: dict[str, type[BaseAlgorithm]] = {"a2c": A2C, "ppo": PPO, "dagger": A2C}
"""SB3 class of each ``algo``; a DAgger policy is kept in an A2C container (no optimizer of its own)."""

MAX_METADATA_BYTES = 64 * 1024
"""Largest ``frontier_rl.json`` read (bytes); ``frontier-rl train`` writes about 170."""

MAX_MEMBERS = 64
"""Most members in a model file's zip; SB3 writes 6 and ``frontier-rl train`` adds 1."""

MAX_WEIGHT_RECORDS = 4096
"""Most records in the torch archive of ``policy.pth`` (one per tensor storage, plus 6); the
shipped models have 24."""


@dataclass(frozen=True)
class ModelInfo:
    """What a model file holds.

    Attributes:
        model: model number 1-7 (:data:`~frontier_rl.registration.MODELS`).
        env_id: the Gymnasium id it was trained on.
        observation_size: map image edge (pixels).
        algo: "a2c", "ppo" or "dagger".
        features_dim: CNN feature size.
        timesteps: decisions it was trained for.
        format: version of this metadata.
    """

    model: int
    env_id: str
    observation_size: int
    algo: str
    features_dim: int
    timesteps: int
    format: int = FORMAT_VERSION


_FIELDS: tuple[str, ...] = tuple(f.name for f in fields(ModelInfo))


def policy_setup(model: int, features_dim: int) -> tuple[type[ActorCriticPolicy], dict[str, Any]]:
    """The policy class and keyword arguments of model ``model``."""
    if model in FRONTIER_CHOICE_MODELS:
        return PointerPolicy, {
            "features_extractor_class": FrontierScorer,
            "features_extractor_kwargs": {"context_dim": features_dim},
            "net_arch": {"pi": [], "vf": [64]},
        }
    if model == 6:
        return ActorCriticPolicy, {
            "features_extractor_class": FrontierPooling,
            "features_extractor_kwargs": {"context_dim": features_dim},
            "net_arch": {"pi": [64], "vf": [64]},
        }
    return ActorCriticCnnPolicy, {
        "features_extractor_class": GridCNN,
        "features_extractor_kwargs": {"features_dim": features_dim},
        "net_arch": {"pi": [64], "vf": [64]},
    }


def write_metadata(path: Path, info: ModelInfo) -> None:
    """Add (or replace) the metadata entry of the SB3 zip at ``path`` (the file is replaced whole,
    never left half written)."""
    with zipfile.ZipFile(path) as archive:
        entries = {name: archive.read(name) for name in archive.namelist() if name != METADATA_ENTRY}
    write_bytes_atomic(path, _zip_bytes(entries, info))


def check_finite_weights(model: BaseAlgorithm) -> None:
    """Raise :class:`~frontier_rl.errors.TrainingDivergedError` if a policy weight is NaN or inf."""
    if not all(bool(torch.isfinite(p).all()) for p in model.policy.parameters()):
        raise TrainingDivergedError(
            f"training diverged by decision {model.num_timesteps:,}: the policy's weights are no longer "
            "finite (NaN or inf); a smaller --learning-rate may help"
        )


def save_model(model: BaseAlgorithm, path: Path, info: ModelInfo | None = None) -> None:
    """Save ``model`` as an SB3 zip at ``path``, with the metadata ``info`` when given; the file is
    replaced whole or not at all (a full disk leaves the previous one). A policy whose weights
    are not finite is not saved (:func:`check_finite_weights`)."""
    check_finite_weights(model)
    buffer = io.BytesIO()
    model.save(buffer)
    if info is None:
        write_bytes_atomic(path, buffer.getvalue())
        return
    with zipfile.ZipFile(buffer) as archive:
        entries = {name: archive.read(name) for name in archive.namelist() if name != METADATA_ENTRY}
    write_bytes_atomic(path, _zip_bytes(entries, info))


def _zip_bytes(entries: dict[str, bytes], info: ModelInfo) -> bytes:
    """A deflated zip of ``entries`` plus the metadata entry of ``info``: a model file, whose
    weights leave out a privileged value head (training only; :class:`PointerPolicy`)."""
    if WEIGHTS_ENTRY in entries:
        entries = {**entries, WEIGHTS_ENTRY: _without_privileged_head(entries[WEIGHTS_ENTRY])}
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, data in entries.items():
            archive.writestr(name, data)
        archive.writestr(METADATA_ENTRY, json.dumps(asdict(info), indent=2))
    return buffer.getvalue()


def _without_privileged_head(weights: bytes) -> bytes:
    """``policy.pth`` as SB3 just wrote it, without the weights of the privileged value head."""
    state = torch.load(io.BytesIO(weights), map_location="cpu", weights_only=True)
    kept = {key: value for key, value in state.items() if not key.startswith(f"{PRIVILEGED_HEAD}.")}
    if len(kept) == len(state):
        return weights
    buffer = io.BytesIO()
    torch.save(kept, buffer)
    return buffer.getvalue()


@contextmanager
def _open_model(path: Path) -> Iterator[zipfile.ZipFile]:
    """The model file at ``path`` as a checked zip (:func:`~frontier_rl.rl.bounded_zip.open_checked_zip`)."""
    where = model_file_label(path)
    try:
        if not path.is_file():  # a device such as /dev/zero would never end
            problem = "is a folder" if path.is_dir() else "is not a regular file" if path.exists() else "not found"
            raise ConfigError(f"{where} {problem}")
        file = path.open("rb")
    except OSError as exc:  # also a name the file system refuses to look up (too long, ...)
        raise ConfigError(f"{where} cannot be read ({exc.strerror or first_line(exc)})") from None
    with file, open_checked_zip(file, where, MAX_MEMBERS, "a frontier_rl model") as archive:
        yield archive


# ------------------------------------------------------------------------------ metadata
def _reject_constant(name: str) -> None:
    raise ValueError(f"{name} is not a number JSON allows")


def _object_without_duplicates(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    values: dict[str, Any] = {}
    for key, value in pairs:
        if key in values:
            raise ValueError(f"key {short_repr(key)} appears twice")
        values[key] = value
    return values


def _whole(values: dict[str, Any], name: str, low: int, high: int, where: str) -> int:
    """Field ``name`` as an int in [low, high] (a bool, float or string is refused)."""
    value = values[name]
    if type(value) is not int:
        raise ConfigError(
            f"{where}: metadata field {name!r} must be a whole number, got {short_repr(value)} ({type(value).__name__})"
        )
    if not low <= value <= high:
        raise ConfigError(f"{where}: metadata field {name!r} must be in {low}..{high}, got {short_repr(value)}")
    return value


def _choice(values: dict[str, Any], name: str, choices: tuple[Any, ...], where: str) -> Any:
    """Field ``name``, which must be one of ``choices`` (of the same type: 64.0 is not 64)."""
    value = values[name]
    if not any(type(value) is type(choice) and value == choice for choice in choices):
        listed = ", ".join(str(choice) for choice in choices)
        raise ConfigError(f"{where}: metadata field {name!r} must be one of {listed}, got {short_repr(value)}")
    return value


def parse_metadata(raw: bytes, where: str) -> ModelInfo:
    """The :class:`ModelInfo` of a ``frontier_rl.json`` entry, every field checked against what
    ``frontier-rl train`` writes. ``where`` names the file in messages. Raises :class:`ConfigError`."""
    if len(raw) > MAX_METADATA_BYTES:
        raise ConfigError(f"{where}: {METADATA_ENTRY} is {len(raw)} bytes, more than the {MAX_METADATA_BYTES} allowed")
    try:
        values = json.loads(
            raw.decode("utf-8"), object_pairs_hook=_object_without_duplicates, parse_constant=_reject_constant
        )
    except (ValueError, RecursionError) as exc:  # JSONDecodeError and UnicodeDecodeError are ValueErrors
        raise ConfigError(f"{where}: {METADATA_ENTRY} is not valid JSON ({first_line(exc)})") from None
    if not isinstance(values, dict):
        raise ConfigError(f"{where}: {METADATA_ENTRY} must hold a JSON object, got a {type(values).__name__}")
    unknown = [key for key in values if key not in _FIELDS]
    if unknown:
        shown = ", ".join(short_repr(key, 40) for key in unknown[:4]) + (", …" if len(unknown) > 4 else "")
        raise ConfigError(f"{where}: unknown metadata field(s) {shown}")
    missing = [key for key in _FIELDS if key not in values]
    if missing:
        raise ConfigError(f"{where}: metadata field(s) {', '.join(map(repr, missing))} missing")
    version = _whole(values, "format", 0, 2**31, where)
    if version != FORMAT_VERSION:
        raise ConfigError(f"{where} has metadata format {version}, expected {FORMAT_VERSION}")
    model = _choice(values, "model", tuple(MODELS), where)
    size = _choice(values, "observation_size", OBSERVATION_SIZES, where)
    name = values["env_id"]
    expected = env_id(model, size)
    if not isinstance(name, str) or name not in ENV_IDS:
        raise ConfigError(
            f"{where}: metadata field 'env_id' must be a frontier_rl id such as {expected!r}, got {short_repr(name)}"
        )
    if name != expected:
        raise ConfigError(
            f"{where}: metadata field 'env_id' is {name!r}, but model {model} at {size} px runs in {expected!r}"
        )
    algo = _choice(values, "algo", tuple(ALGORITHMS), where)
    features_dim = _whole(values, "features_dim", 1, MAX_FEATURES_DIM, where)
    timesteps = _whole(values, "timesteps", 0, MAX_TIMESTEPS, where)
    return ModelInfo(model, name, size, algo, features_dim, timesteps, version)


def _metadata(archive: zipfile.ZipFile, where: str) -> ModelInfo | None:
    if METADATA_ENTRY not in archive.namelist():
        return None
    return parse_metadata(read_member(archive, METADATA_ENTRY, MAX_METADATA_BYTES, where), where)


def read_metadata(path: str | Path) -> ModelInfo | None:
    """The checked metadata of the model file at ``path`` (see :func:`parse_metadata`); None for an
    SB3 zip without it. Raises :class:`ConfigError` for a missing, unreadable, oversized or corrupt
    file, or metadata that ``frontier-rl train`` would not write."""
    path = Path(path)
    with _open_model(path) as archive:
        return _metadata(archive, model_file_label(path))


def env_spaces(env_id: str) -> tuple[gym.Space[Any], gym.Space[Any]]:
    """Observation and action spaces of one of the project's registered ids (the env is built, not
    reset); any other id is refused, so no module it names is imported."""
    if env_id not in ENV_IDS:
        raise ConfigError(f"{short_repr(env_id)} is not a frontier_rl environment id such as {ENV_IDS[-1]!r}")
    frontier_rl.envs.register_envs()
    env = gym.make(env_id)
    try:
        return env.observation_space, env.action_space
    finally:
        env.close()


# ------------------------------------------------------------------------------ weights
def _read_weights(archive: zipfile.ZipFile, where: str) -> dict[str, torch.Tensor]:
    """The tensors of ``policy.pth``: its torch archive is size-checked like the model file, then
    read with ``weights_only`` (no code runs); torch's messages and warnings become one line."""
    if WEIGHTS_ENTRY not in archive.namelist():
        raise ConfigError(f"{where} has no {WEIGHTS_ENTRY}")
    raw = io.BytesIO(read_member(archive, WEIGHTS_ENTRY, MAX_MEMBER_BYTES, where))
    inner = f"{where}: {WEIGHTS_ENTRY}"
    open_checked_zip(raw, inner, MAX_WEIGHT_RECORDS, "a torch weights file (torch's zip format)").close()
    raw.seek(0)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            state = torch.load(raw, map_location="cpu", weights_only=True)
    except pickle.UnpicklingError as exc:
        lines = str(exc).splitlines()
        detail = next((line.strip() for line in lines if "GLOBAL" in line or "Unsupported" in line), "")
        cut = f": {detail[:QUOTE_LIMIT]}" if detail else ""
        raise ConfigError(f"{inner} holds objects other than tensors, refused{cut}") from None
    except Exception as exc:
        raise ConfigError(f"{inner} is corrupt ({first_line(exc)})") from None
    if not isinstance(state, dict) or not all(
        isinstance(key, str) and isinstance(value, torch.Tensor) for key, value in state.items()
    ):
        raise ConfigError(f"{inner} does not hold a dict of named tensors")
    return dict(state)  # a plain dict: drops attributes the pickle may have set (torch reads ``_metadata``)


def _check_fit(policy: ActorCriticPolicy, state: dict[str, torch.Tensor], info: ModelInfo, where: str) -> None:
    """Refuse weights whose names, shapes or dtypes differ from the rebuilt network's, or that are
    not finite; shapes are compared before any value is touched."""
    expected = policy.state_dict()
    fit = f"{where} does not fit {info.env_id}"
    missing = [key for key in expected if key not in state]
    unexpected = [key for key in state if key not in expected]
    if missing or unexpected:
        first = f"missing {short_repr(missing[0])}" if missing else f"unexpected {short_repr(unexpected[0])}"
        raise ConfigError(f"{fit} ({len(missing)} weights missing, {len(unexpected)} unexpected; {first})")
    for key, tensor in state.items():
        want = expected[key]
        if (
            tensor.layout != torch.strided
            or tensor.device.type != "cpu"
            or tuple(tensor.shape) != tuple(want.shape)
            or tensor.dtype != want.dtype
        ):
            got = short_repr(f"{tuple(tensor.shape)} {tensor.dtype}")
            raise ConfigError(f"{fit} (weight {key!r} is {got}, expected {tuple(want.shape)} {want.dtype})")
        if tensor.is_floating_point() and not bool(torch.isfinite(tensor).all()):
            raise ConfigError(f"{where}: weight {key!r} holds values that are not finite")


def load_policy(path: str | Path, trust: bool = False) -> tuple[ActorCriticPolicy, ModelInfo | None]:
    """The policy network of a model file, in evaluation mode on the CPU.

    Args:
        path: a zip written by ``frontier-rl train``.
        trust: allow SB3's full (unpickling) load for zips without frontier_rl metadata.
    """
    path = Path(path)
    where = model_file_label(path)
    with _open_model(path) as archive:
        info = _metadata(archive, where)
        state = _read_weights(archive, where) if info is not None else {}
    if info is None:
        if not trust:
            raise ConfigError(
                f"{where} was not written by 'frontier-rl train'; loading it would unpickle "
                "(and could run) code from the file. Pass --trust-model if you trust it"
            )
        return _load_trusted(path), None
    policy_cls, kwargs = policy_setup(info.model, info.features_dim)
    obs_space, act_space = env_spaces(info.env_id)
    policy = policy_cls(obs_space, act_space, lambda _: 0.0, **kwargs)
    _check_fit(policy, state, info, where)
    try:
        policy.load_state_dict(state)
    except Exception as exc:
        raise ConfigError(f"{where} does not fit {info.env_id} ({first_line(exc)})") from None
    policy.set_training_mode(False)
    return policy, info


def check_model_zip(path: Path) -> None:
    """Refuse the zip at ``path`` (a model file or a training checkpoint) before SB3 reads it, if
    what its directory declares is too big or too compressed (:mod:`frontier_rl.rl.bounded_zip`)."""
    with _open_model(path):
        pass


def _load_trusted(path: Path) -> ActorCriticPolicy:
    """SB3's own (unpickling) load, after the zip checks; tried as A2C, then PPO."""
    check_model_zip(path)
    last: Exception | None = None
    for algo in dict.fromkeys(ALGORITHMS.values()):  # each class once (a DAgger file is an A2C one)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                policy = algo.load(str(path), device="cpu").policy
        except Exception as exc:
            last = exc
            continue
        if isinstance(policy, ActorCriticPolicy):
            policy.set_training_mode(False)
            return policy
    reason = f" ({first_line(last)})" if last is not None else ""
    raise ConfigError(f"{model_file_label(path)} could not be loaded as an SB3 A2C or PPO model{reason}")
