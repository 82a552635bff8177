"""The generated reference pages: every configuration field is documented (or the build fails, naming
it), the YAML example loads, and a regenerated folder changes only the files whose content did."""

from __future__ import annotations

import dataclasses
import os
from pathlib import Path

import pytest
from config_reference import CONFIGS, field_docs, generate, render_config
from docstrings import DocstringError, attributes_section, to_myst
from generated_pages import sync_folder

from frontier_rl.config_files import load_sim_config
from frontier_rl.core.sim.config import SimConfig


@pytest.mark.parametrize("name", sorted(CONFIGS))
def test_every_field_of_the_configuration_has_a_type_default_and_description(name: str) -> None:
    page = render_config(CONFIGS[name])
    for doc in field_docs(CONFIGS[name]):
        assert doc.description and doc.type, doc
        assert f"`{doc.key}`" in page


def test_the_simulator_fields_nested_configurations_are_listed_with_dotted_keys() -> None:
    page = render_config(SimConfig)
    for key in ("lidar.max_range", "robot.radius", "mapper.usable_range", "navigation.goal_tolerance"):
        assert f"`{key}`" in page
    assert "`max_sim_time` · `float | None` · default `None`" in page


@dataclasses.dataclass(frozen=True)
class _Documented:
    """A configuration.

    Attributes:
        speed: how fast (m/s).
        name, label: two fields described at once,
            on two lines.
    """

    speed: float = 1.0
    name: str = "a"
    label: str = "b"


@dataclasses.dataclass(frozen=True)
class _Undocumented:
    """A configuration.

    Attributes:
        speed: how fast (m/s).
    """

    speed: float = 1.0
    new_field: int = 3


@dataclasses.dataclass(frozen=True)
class _Stale:
    """A configuration.

    Attributes:
        speed: how fast (m/s).
        gone: a field since removed.
    """

    speed: float = 1.0


def test_the_attributes_section_is_read_field_by_field() -> None:
    assert attributes_section(_Documented) == {
        "speed": "how fast (m/s).",
        "name": "two fields described at once, on two lines.",
        "label": "two fields described at once, on two lines.",
    }


def test_a_field_without_a_description_fails_naming_it() -> None:
    with pytest.raises(DocstringError, match=r"no description of field\(s\) new_field"):
        field_docs(_Undocumented)


def test_a_description_of_a_field_that_does_not_exist_fails_naming_it() -> None:
    with pytest.raises(DocstringError, match=r"describes no field\(s\) gone"):
        field_docs(_Stale)


def test_roles_become_myst_roles_with_absolute_targets() -> None:
    text = to_myst("see :meth:`drop_cells` and :func:`~frontier_rl.config_files.load_config`, ``literal``", SimConfig)
    assert text == (
        "see {meth}`~frontier_rl.core.sim.config.SimConfig.drop_cells` and "
        "{func}`~frontier_rl.config_files.load_config`, `literal`"
    )


def test_the_yaml_example_is_written_and_loads(tmp_path: Path) -> None:
    generate(tmp_path)
    config = load_sim_config(tmp_path / "sim-example.yaml")
    assert config.lidar.max_range == 8.0 and config.sensor_noise is False
    assert load_sim_config(tmp_path / "sim-defaults.yaml") == SimConfig()
    assert {p.name for p in tmp_path.iterdir()} >= {f"{name}.md" for name in CONFIGS}


def test_a_folder_is_synced_file_by_file(tmp_path: Path) -> None:
    source, target = tmp_path / "new", tmp_path / "docs"
    source.mkdir()
    target.mkdir()
    (source / "same.md").write_text("same")
    (source / "changed.md").write_text("new text")
    (target / "same.md").write_text("same")
    (target / "changed.md").write_text("old text")
    (target / "stale.md").write_text("gone")
    os.utime(target / "same.md", (1, 1))
    assert sync_folder(source, target) == 2
    assert sorted(p.name for p in target.iterdir()) == ["changed.md", "same.md"]
    assert (target / "changed.md").read_text() == "new text"
    assert (target / "same.md").stat().st_mtime == 1  # untouched: Sphinx does not rebuild its page
