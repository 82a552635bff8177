"""Frozen-dataclass configuration to and from YAML, with unknown keys rejected by name."""

from __future__ import annotations

import dataclasses
import math
import typing
from pathlib import Path
from typing import Any, TypeVar

import yaml

from frontier_rl.core.simulator import SimConfig
from frontier_rl.errors import ConfigError

T = TypeVar("T")


def from_dict(cls: type[T], data: Any, where: str = "") -> T:
    """Build dataclass ``cls`` from a (nested) mapping; missing fields keep their defaults."""
    name = where or cls.__name__
    if not isinstance(data, dict):
        raise ConfigError(f"{name} must be a mapping, got {type(data).__name__}")
    if not dataclasses.is_dataclass(cls):
        raise TypeError(f"{cls!r} is not a dataclass")
    hints = typing.get_type_hints(cls)
    fields = {f.name: f for f in dataclasses.fields(cls)}
    unknown = sorted(set(data) - set(fields))
    if unknown:
        raise ConfigError(f"unknown key {unknown[0]!r} in {name}; valid keys: {', '.join(fields)}")
    kwargs: dict[str, Any] = {}
    for key, value in data.items():
        hint = hints[key]
        if dataclasses.is_dataclass(hint) and isinstance(hint, type):
            kwargs[key] = from_dict(hint, value, f"{name}.{key}")
        else:
            kwargs[key] = _coerce(hint, value, f"{name}.{key}")
    return cls(**kwargs)


def _coerce(hint: Any, value: Any, where: str) -> Any:
    if hint is bool:
        if not isinstance(value, bool):
            raise ConfigError(f"{where} must be true or false, got {value!r}")
        return value
    if hint is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise ConfigError(f"{where} must be an integer, got {value!r}")
        return value
    if hint == float | None:
        return None if value is None else _coerce(float, value, where)
    if hint is float:
        if isinstance(value, bool) or not isinstance(value, int | float) or math.isnan(value):
            raise ConfigError(f"{where} must be a number, got {value!r}")
        return float(value)
    return value


def to_dict(config: Any) -> dict[str, Any]:
    """A dataclass as a plain nested dict (YAML- and JSON-ready)."""
    return dataclasses.asdict(config)


def load_sim_config(path: str | Path) -> SimConfig:
    """Read a :class:`SimConfig` from a YAML file (any subset of its fields)."""
    path = Path(path)
    try:
        data = yaml.safe_load(path.read_text()) or {}
    except OSError as exc:
        raise ConfigError(f"cannot read config file {str(path)!r}: {exc.strerror}") from exc
    except yaml.YAMLError as exc:
        raise ConfigError(f"config file {str(path)!r} is not valid YAML: {exc}".splitlines()[0]) from exc
    return from_dict(SimConfig, data, "SimConfig")


def dump_config(config: Any, path: str | Path) -> Path:
    """Write a dataclass config as YAML to ``path``."""
    path = Path(path)
    path.write_text(yaml.safe_dump(to_dict(config), sort_keys=False))
    return path
