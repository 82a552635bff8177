"""The configuration reference, generated from the frozen dataclasses: every field with its type,
default and the description of its class's "Attributes:" section, and a YAML example that is
loaded back at build time.

A field without a description, or a description of a field that does not exist, fails the build.
"""

from __future__ import annotations

import dataclasses
import enum
import tempfile
import types
import typing
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from docstrings import DocstringError, attributes_section, to_myst

from frontier_rl.config_files import load_sim_config, to_dict
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.envs.base import EnvConfig
from frontier_rl.evaluation.running.experiment import ExperimentConfig
from frontier_rl.rl.config import TrainConfig
from frontier_rl.safe_yaml import dump_yaml
from frontier_rl.swarm.config import TeamConfig

CONFIGS: dict[str, type[Any]] = {
    "sim": SimConfig,
    "env": EnvConfig,
    "train": TrainConfig,
    "team": TeamConfig,
    "experiment": ExperimentConfig,
}
"""Each documented configuration by the name of its fragment (``_generated/config/NAME.md``)."""

LABELS: dict[type[Any], str] = {SimConfig: "config-sim"}
"""The configuration page's targets of classes that other classes' fields hold whole."""

SIM_EXAMPLE: dict[str, Any] = {
    "max_sim_time": 1800.0,
    "sensor_noise": False,
    "robot": {"radius": 0.18, "max_linear_speed": 0.5},
    "lidar": {"max_range": 8.0, "num_beams": 720},
    "mapper": {"usable_range": 6.0},
}
"""The ``--config sim.yaml`` example: a few fields of the SimConfig, the rest left at their defaults."""


@dataclasses.dataclass(frozen=True)
class FieldDoc:
    """One configuration field as the page shows it."""

    key: str
    type: str
    default: str
    description: str


def generate(out_dir: Path) -> None:
    """Write ``NAME.md`` (the field list of each of :data:`CONFIGS`), ``sim-example.yaml`` and
    ``sim-defaults.yaml`` into ``out_dir``."""
    for name, cls in CONFIGS.items():
        (out_dir / f"{name}.md").write_text(render_config(cls))
    (out_dir / "sim-example.yaml").write_text(_checked_example())
    (out_dir / "sim-defaults.yaml").write_text(dump_yaml(to_dict(SimConfig())))


def render_config(cls: type[Any]) -> str:
    """The Markdown of ``cls``'s fields: its own first, then a section per nested configuration
    (unless the page documents that one on its own)."""
    lines = _field_list(cls, "")
    for field, nested in _nested(cls):
        if nested in LABELS:
            continue
        lines += [f"### `{field.name}`: {{py:class}}`~{_path(nested)}`", "", *_field_list(nested, f"{field.name}.")]
    return "\n".join(lines)


def _field_list(cls: type[Any], prefix: str) -> list[str]:
    lines = [to_myst(_summary(cls), cls), ""]
    for doc in field_docs(cls, prefix):
        lines += [f"`{doc.key}` · `{doc.type}` · {doc.default}", f": {doc.description}", ""]
    return lines


def field_docs(cls: type[Any], prefix: str = "") -> list[FieldDoc]:
    """The fields of dataclass ``cls``, keys prefixed with ``prefix``.

    Raises:
        DocstringError: a field has no description in the "Attributes:" section, or the section
            describes a field ``cls`` does not have.
    """
    described = attributes_section(cls)
    fields = dataclasses.fields(cls)
    missing = [f.name for f in fields if not described.get(f.name)]
    if missing:
        raise DocstringError(f"{_path(cls)}: no description of field(s) {', '.join(missing)} in its Attributes section")
    stale = sorted(set(described) - {f.name for f in fields})
    if stale:
        raise DocstringError(f"{_path(cls)}: its Attributes section describes no field(s) {', '.join(stale)}")
    hints = typing.get_type_hints(cls)
    docs = []
    for field in fields:
        hint = hints[field.name]
        text = to_myst(described[field.name], cls)
        if isinstance(hint, type) and issubclass(hint, enum.Enum):
            text += " One of " + ", ".join(f"`{member.value}`" for member in hint) + "."
        docs.append(FieldDoc(prefix + field.name, type_name(hint), _default(field, hint), text))
    return docs


def type_name(hint: Any) -> str:
    """``hint`` as a reader writes it: ``float | None``, ``tuple[str, ...]``; an enum is a ``str``."""
    if isinstance(hint, type) and issubclass(hint, enum.Enum):
        return "str"
    if isinstance(hint, types.UnionType) or typing.get_origin(hint) is typing.Union:
        return " | ".join(type_name(arg) for arg in typing.get_args(hint))
    origin = typing.get_origin(hint)
    if origin is not None:
        args = ", ".join("..." if arg is Ellipsis else type_name(arg) for arg in typing.get_args(hint))
        return f"{origin.__name__}[{args}]"
    return "None" if hint is type(None) else getattr(hint, "__name__", str(hint))


def _default(field: dataclasses.Field[Any], hint: Any) -> str:
    if isinstance(hint, type) and dataclasses.is_dataclass(hint):
        label = LABELS.get(hint)
        return f"see {{ref}}`{hint.__name__} <{label}>`" if label else "see below"
    if field.default is not dataclasses.MISSING:
        value = field.default
    elif field.default_factory is not dataclasses.MISSING:
        value = field.default_factory()
    else:
        return "required"
    return f"default `{format_value(value)}`"


def format_value(value: Any) -> str:
    """A default as the reader reads it: an enum by its value, a float in at most 6 digits."""
    if isinstance(value, enum.Enum):
        return str(value.value)
    if isinstance(value, float):
        return format(value, ".6g")
    return repr(value)


def _nested(cls: type[Any]) -> Iterator[tuple[dataclasses.Field[Any], type[Any]]]:
    hints = typing.get_type_hints(cls)
    for field in dataclasses.fields(cls):
        if dataclasses.is_dataclass(hints[field.name]):
            yield field, hints[field.name]


def _summary(cls: type[Any]) -> str:
    """The first paragraph of ``cls``'s docstring."""
    return " ".join((cls.__doc__ or "").strip().split("\n\n")[0].split())


def _path(cls: type[Any]) -> str:
    return f"{cls.__module__}.{cls.__qualname__}"


def _checked_example() -> str:
    """:data:`SIM_EXAMPLE` as YAML, after checking that ``--config`` reads it back as those fields."""
    text = "# sim.yaml: any subset of the SimConfig's fields; the others keep their defaults\n" + dump_yaml(SIM_EXAMPLE)
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "sim.yaml"
        path.write_text(text)
        loaded = to_dict(load_sim_config(path))
    expected = to_dict(SimConfig())
    for key, value in SIM_EXAMPLE.items():
        if isinstance(value, dict):
            expected[key].update(value)
        else:
            expected[key] = value
    if loaded != expected:
        raise DocstringError("the SimConfig YAML example does not load as the fields it sets")
    return text
