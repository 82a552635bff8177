"""SimConfig from and to YAML: partial files, unknown keys and wrong types are named."""

from __future__ import annotations

from pathlib import Path

import pytest

from frontier_rl.config_files import dump_config, from_dict, load_sim_config
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.errors import ConfigError


def test_partial_yaml_keeps_the_other_defaults(tmp_path: Path) -> None:
    path = tmp_path / "sim.yaml"
    path.write_text("max_sim_time: 120\nlidar:\n  num_beams: 180\nmapper:\n  usable_range: 2.5\n")
    config = load_sim_config(path)
    assert config.max_sim_time == 120.0
    assert config.lidar.num_beams == 180
    assert config.lidar.max_range == SimConfig().lidar.max_range
    assert config.mapper.usable_range == 2.5
    assert config.robot == SimConfig().robot


def test_dump_then_load_round_trips(tmp_path: Path) -> None:
    config = from_dict(SimConfig, {"navigation": {"progress_timeout": 12.5}, "sensor_noise": False})
    path = dump_config(config, tmp_path / "config.yaml")
    assert load_sim_config(path) == config


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("bogus: 1\n", "bogus"),
        ("lidar:\n  bogus: 1\n", "bogus"),
        ("lidar:\n  num_beams: 1.5\n", "num_beams"),
        ("sensor_noise: 3\n", "sensor_noise"),
        ("max_sim_time: fast\n", "max_sim_time"),
        ("max_sim_time: -5\n", "-5"),
        ("robot: 3\n", "robot"),
        ("- a list\n", "mapping"),
        ("lidar: {min_range: 4.0}\n", "min_range"),
        ("navigation: {inflation_radius: 1.0e7}\n", "inflation_radius must be at most 10 m"),  # was a MemoryError
        ("min_frontier_cells: 9223372036854775808\n", "min_frontier_cells must be 0 to 1,000,000"),  # OverflowError
        ("min_frontier_cells: -1\n", "min_frontier_cells"),
    ],
)
def test_bad_values_raise_config_error_naming_them(tmp_path: Path, text: str, needle: str) -> None:
    path = tmp_path / "sim.yaml"
    path.write_text(text)
    with pytest.raises(ConfigError, match=needle):
        load_sim_config(path)


def test_missing_and_malformed_files(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match=r"nothing\.yaml"):
        load_sim_config(tmp_path / "nothing.yaml")
    broken = tmp_path / "broken.yaml"
    broken.write_text("lidar: [1, 2\n")
    with pytest.raises(ConfigError, match=r"broken\.yaml"):
        load_sim_config(broken)
