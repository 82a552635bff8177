"""The site's Sphinx extensions that read the package's docstrings: napoleon fitted to the shared
"a, b: ..." attribute entries, and references resolved relative to the code that holds them."""

from __future__ import annotations

from attribute_docstrings import split_shared_entries
from code_references import candidates
from docstrings import absolute_target, exists

from frontier_rl.core.sim.config import SimConfig


def test_an_attribute_entry_for_several_fields_is_given_to_each() -> None:
    lines = [
        "What one episode did.",
        "",
        "Attributes:",
        "    t90_s, t99_s: sim time at which coverage reached 90 % / 99 %",
        "        (s); None if never.",
        "    done: the map is explored.",
        "",
        "Args:",
        "    a, b: left alone outside Attributes.",
    ]
    assert split_shared_entries(lines) == [
        "What one episode did.",
        "",
        "Attributes:",
        "    t90_s: sim time at which coverage reached 90 % / 99 %",
        "        (s); None if never.",
        "    t99_s: sim time at which coverage reached 90 % / 99 %",
        "        (s); None if never.",
        "    done: the map is explored.",
        "",
        "Args:",
        "    a, b: left alone outside Attributes.",
    ]


def test_a_relative_reference_is_tried_in_the_class_and_module_that_define_it() -> None:
    names = candidates(
        "drop_cells_at", "frontier_rl", "SimConfig", "config.py:docstring of frontier_rl.core.sim.config.SimConfig"
    )
    assert "frontier_rl.core.sim.config.drop_cells_at" in names
    assert [name for name in names if exists(name)] == ["frontier_rl.core.sim.config.drop_cells_at"]


def test_only_code_that_exists_is_found() -> None:
    assert exists("frontier_rl.core.sim.config.SimConfig.max_sim_time")  # a field whose default is None
    assert exists("frontier_rl.evaluation.running.experiment.ExperimentConfig.methods")  # a field without a default
    assert not exists("frontier_rl.core.sim.config.SimConfig.no_such_field")
    assert not exists("numpy.ndarray")
    assert absolute_target("mapping_range", SimConfig) == "~frontier_rl.core.sim.config.SimConfig.mapping_range"
    assert absolute_target("no_such_name", SimConfig) == "no_such_name"
