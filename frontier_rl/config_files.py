"""Frozen-dataclass configuration to and from YAML, with unknown keys rejected by name.

YAML is read by :mod:`frontier_rl.safe_yaml` (size-bounded, no aliases, YAML-1.2 numbers: ``6e2`` is
a float); values quoted in errors are cut to a bounded length.
"""

from __future__ import annotations

import dataclasses
import typing
from pathlib import Path
from typing import Any, TypeVar

from frontier_rl.atomic_write import write_text_atomic
from frontier_rl.checked_values import coerce
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.errors import ConfigError, FrontierRLError, short_repr
from frontier_rl.safe_yaml import dump_yaml, load_yaml_file

T = TypeVar("T")


def from_dict(cls: type[T], data: Any, where: str = "") -> T:
    """Build dataclass ``cls`` from a (nested) mapping; missing fields keep their defaults.

    Args:
        cls: a (frozen) dataclass; fields that are dataclasses are built from nested mappings.
        data: the mapping, as read from YAML.
        where: the dotted name errors give ``cls`` ("SimConfig": "SimConfig.lidar.max_range
            must be a number"); fields are named bare when empty.

    Raises:
        ConfigError: not a mapping, a key that is not a field (named, with the valid keys), or a
            value of the wrong type (:func:`coerce`).
    """
    if not isinstance(data, dict):
        raise ConfigError(f"{where or cls.__name__} must be a mapping, got {type(data).__name__}")
    if not dataclasses.is_dataclass(cls):
        raise TypeError(f"{cls!r} is not a dataclass")
    hints = typing.get_type_hints(cls)
    fields = {f.name: f for f in dataclasses.fields(cls)}
    unknown = sorted((key for key in data if key not in fields), key=str)
    if unknown:
        raise ConfigError(
            f"unknown key {short_repr(unknown[0])} in {where or cls.__name__}; valid keys: {', '.join(fields)}"
        )
    kwargs: dict[str, Any] = {}
    for key, value in data.items():
        hint, name = hints[key], f"{where}.{key}" if where else key
        if dataclasses.is_dataclass(hint) and isinstance(hint, type):
            kwargs[key] = from_dict(hint, value, name)
        else:
            kwargs[key] = coerce(hint, value, name)
    return cls(**kwargs)


def to_dict(config: Any) -> dict[str, Any]:
    """A dataclass as a plain nested dict (YAML- and JSON-ready)."""
    return dataclasses.asdict(config)


def load_config(cls: type[T], path: str | Path, what: str, where: str = "", *, allow_empty: bool = True) -> T:
    """Read dataclass ``cls`` from a YAML file: any subset of its fields, an empty file for the
    defaults unless ``allow_empty`` is false (see :mod:`frontier_rl.safe_yaml` for the limits on
    the file).

    Raises:
        ConfigError: an unreadable file or a bad field (:func:`from_dict`), prefixed with ``what``
            and the path ("config file sim.yaml: ...").
    """
    data = load_yaml_file(path, ConfigError, what)
    if data is None and not allow_empty:
        raise ConfigError(f"{what} {path} is empty")
    try:
        return from_dict(cls, {} if data is None else data, where)
    except FrontierRLError as exc:
        raise type(exc)(f"{what} {path}: {exc}") from None


def load_sim_config(path: str | Path) -> SimConfig:
    """Read a :class:`SimConfig` from a YAML file (:func:`load_config`)."""
    return load_config(SimConfig, path, "config file", "SimConfig")


def dump_config(config: Any, path: str | Path) -> Path:
    """Write a dataclass config as YAML to ``path`` (atomically: a reader never sees half a file)."""
    path = Path(path)
    write_text_atomic(path, dump_yaml(to_dict(config)))
    return path
