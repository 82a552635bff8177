"""Model files: Stable-Baselines3 zips with a ``frontier_rl.json`` entry saying what they are,
read without Stable-Baselines3 or Gymnasium (torch only, for the weights).

A model file is untrusted input. Reading one:

1. checks the zip before anything in it is read (:mod:`frontier_rl.inference.bounded_zip`): at most
   :data:`MAX_MEMBERS` members, each stored or deflated, none over 256 MiB uncompressed, all
   together at most 1 GiB, none compressed more than 200 to 1;
2. reads ``frontier_rl.json`` (at most :data:`MAX_METADATA_BYTES`) and checks every field against
   what ``frontier-rl train`` writes: a known model number, one of the project's own Gymnasium ids
   fitting that model and image size, a known algorithm, whole numbers in range, no other keys.
   Nothing from the file reaches an import unchecked;
3. reads only ``policy.pth``, as plain tensors (``torch.load(weights_only=True)``, never
   unpickling code), after the same size checks on the torch archive inside it; every tensor must
   have the name, shape and dtype of the network rebuilt from those fields (:func:`check_fit`).

Every problem is one :class:`~frontier_rl.errors.ConfigError` line naming the file and the field.
Writing model files is training's job (:mod:`frontier_rl.rl.model_file`).
"""

from __future__ import annotations

import io
import json
import pickle
import re
import warnings
import zipfile
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

import torch

from frontier_rl.errors import QUOTE_LIMIT, ConfigError, model_file_label, short_repr
from frontier_rl.inference.bounded_zip import MAX_MEMBER_BYTES, first_line, open_checked_zip, read_member
from frontier_rl.registration import ENV_IDS, MODELS, OBSERVATION_SIZES, Algorithm, env_id

METADATA_ENTRY = "frontier_rl.json"
WEIGHTS_ENTRY = "policy.pth"
FORMAT_VERSION = 1


MAX_FEATURES_DIM = 8192
"""Largest ``features_dim`` a run may use and a model file may hold (the shipped models use 128)."""

MAX_TIMESTEPS = 10**12
"""Largest ``timesteps`` a run may use and a model file may hold (decisions; 10¹² is ~30 years at 1000 per second)."""

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
        algo: what trained it.
        features_dim: CNN feature size.
        timesteps: decisions it was trained for.
        format: version of this metadata.
    """

    model: int
    env_id: str
    observation_size: int
    algo: Algorithm
    features_dim: int
    timesteps: int
    format: int = FORMAT_VERSION


_FIELDS: tuple[str, ...] = tuple(f.name for f in fields(ModelInfo))


@contextmanager
def open_model(path: Path) -> Iterator[zipfile.ZipFile]:
    """The model file at ``path`` as a checked zip (:func:`~frontier_rl.inference.bounded_zip.open_checked_zip`)."""
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
    algo = Algorithm(_choice(values, "algo", tuple(member.value for member in Algorithm), where))
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
    with open_model(path) as archive:
        return _metadata(archive, model_file_label(path))


# ------------------------------------------------------------------------------ weights
def read_weights(archive: zipfile.ZipFile, where: str) -> dict[str, torch.Tensor]:
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


def check_fit(
    expected: Mapping[str, torch.Tensor], state: dict[str, torch.Tensor], info: ModelInfo, where: str
) -> None:
    """Refuse weights ``state`` whose names, shapes or dtypes differ from ``expected`` (the
    rebuilt network's ``state_dict()``), or that are not finite; shapes are compared before any
    value is touched."""
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


CHECKPOINT_NAME = re.compile(r"model_(\d+)_steps\.zip$")
"""The name of a training checkpoint ``frontier-rl train`` writes (``model_<steps>_steps.zip``):
the whole training state, for ``--resume``, not a model file."""


def checkpoint_name(steps: int) -> str:
    """The file name of the checkpoint at ``steps`` decisions (:data:`CHECKPOINT_NAME` reads it)."""
    return f"model_{steps}_steps.zip"


def read_model(path: Path, trust: bool = False) -> tuple[ModelInfo | None, dict[str, torch.Tensor]]:
    """The checked metadata and weights of the model file at ``path``. An SB3 zip without this
    project's metadata is refused unless ``trust`` (SB3's format pickles its contents, and loading
    them can run code from the file); then (None, {}), its weights left to SB3."""
    where = model_file_label(path)
    with open_model(path) as archive:
        info = _metadata(archive, where)
        if info is not None:
            return info, read_weights(archive, where)
    if not trust and CHECKPOINT_NAME.fullmatch(path.name):
        raise ConfigError(
            f"{where} is a checkpoint of 'frontier-rl train' (its state for --resume), not a model file: "
            "use the run's model.zip or best_model.zip (or pass --trust-model to load it all the same)"
        )
    if not trust:
        raise ConfigError(
            f"{where} was not written by 'frontier-rl train'; loading it would unpickle "
            "(and could run) code from the file. Pass --trust-model if you trust it"
        )
    return None, {}
