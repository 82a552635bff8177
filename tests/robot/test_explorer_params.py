"""The explorer's settings, described once, and explore_lite's parameter file read into them."""

from __future__ import annotations

from pathlib import Path

import pytest
import typer.core
import typer.main

from frontier_rl.cli import app
from frontier_rl.errors import ConfigError, SettingError
from frontier_rl.robot.explore_lite_file import explore_lite_parameters
from frontier_rl.robot.explorer_params import ExplorerParams, Nav2Plugins, setting_help

M_EXPLORE_ROS2 = """\
explore_node:
  ros__parameters:
    robot_base_frame: base_link
    return_to_init: true
    costmap_topic: map
    costmap_updates_topic: map_updates
    visualize: true
    planner_frequency: 0.15
    progress_timeout: 30.0
    potential_scale: 3.0
    orientation_scale: 0.0
    gain_scale: 1.0
    transform_tolerance: 0.3
    min_frontier_size: 0.75
"""


def test_m_explore_ros2s_own_file_gives_the_parameters_that_mean_the_same(tmp_path: Path) -> None:
    path = tmp_path / "explore.yaml"
    path.write_text(M_EXPLORE_ROS2)
    known, ignored = explore_lite_parameters(path)
    assert known == {
        "return_to_init": True,
        "visualize": True,
        "planner_frequency": 0.15,
        "progress_timeout": 30.0,
        "min_frontier_size": 0.75,
        "robot_base_frame": "base_link",  # with the pose from tf
    }
    assert ignored == [
        "costmap_topic",
        "costmap_updates_topic",
        "gain_scale",
        "orientation_scale",
        "potential_scale",
        "transform_tolerance",
    ]
    visualize, _ = known.pop("visualize"), known.pop("robot_base_frame")
    assert visualize is True and ExplorerParams(**known).planner_frequency == 0.15


def test_a_plain_mapping_is_read_too_and_integers_are_numbers(tmp_path: Path) -> None:
    path = tmp_path / "plain.yaml"
    path.write_text("planner_frequency: 2\nprogress_timeout: 10\n")
    assert explore_lite_parameters(path) == ({"planner_frequency": 2.0, "progress_timeout": 10.0}, [])


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("return_to_init: yes please\n", "return_to_init must be true or false"),
        ("- planner_frequency\n", "must map parameter names to values"),
        ("progress_timeout: .nan\n", "progress_timeout must be a number"),
    ],
)
def test_a_bad_file_is_one_error_naming_the_value(text: str, needle: str, tmp_path: Path) -> None:
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(ConfigError, match=needle):
        explore_lite_parameters(path)


def test_the_command_line_describes_each_setting_as_the_node_does_with_its_default() -> None:
    group = typer.main.get_command(app)
    assert isinstance(group, typer.core.TyperGroup)
    context = typer.Context(group, info_name="frontier-rl")
    ros2 = group.get_command(context, "ros2")
    assert isinstance(ros2, typer.core.TyperGroup)
    explore = ros2.get_command(context, "explore")
    assert explore is not None
    options = {option.name: option for option in explore.params if isinstance(option, typer.core.TyperOption)}
    for name in ("planner_frequency", "progress_timeout", "min_frontier_size", "return_to_init", "visualize"):
        assert options[name].help == setting_help(name)
        if name != "visualize":
            assert options[name].default == getattr(ExplorerParams(), name), name
    assert options["time_cap"].help == setting_help("time_cap") and "0: never" in setting_help("time_cap")
    assert "(s)" in setting_help("progress_timeout") and "(Hz)" in setting_help("planner_frequency")
    with pytest.raises(KeyError):
        setting_help("potential_scale")  # explore_lite's, meaning nothing here


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("amcl:\n  ros__parameters: {alpha1: 0.2}\nbt:\n  ros__parameters: {x: 1}\n", "amcl, bt, none of them"),
        ("planner_frequency: -1.0\n", r"bad\.yaml: planner_frequency must be a positive number, got -1\.0"),
        ("/**:\n  ros__parameters: [1]\nexplore_node:\n  ros__parameters: {}\n", "must map parameter names"),
    ],
)
def test_a_file_of_other_nodes_or_with_a_value_out_of_range_is_refused_naming_it(
    text: str, needle: str, tmp_path: Path
) -> None:
    """An out-of-range value was named as the command line's option, which the user never gave."""
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(ConfigError, match=needle):
        explore_lite_parameters(path)


def test_the_explorers_nodes_of_a_ros2_file_are_read_in_order_and_time_cap_0_is_none(tmp_path: Path) -> None:
    path = tmp_path / "params.yaml"
    path.write_text(
        "amcl:\n  ros__parameters: {alpha1: 0.2}\n"
        "/**:\n  ros__parameters: {planner_frequency: 2.0, use_sim_time: true}\n"
        "/tb3_0/frontier_rl_explorer:\n  ros__parameters: {planner_frequency: 0.5, time_cap: 0.0}\n"
    )
    assert explore_lite_parameters(path) == ({"planner_frequency": 0.5, "time_cap": 0.0, "use_sim_time": True}, [])
    # the same, nested by namespace as ROS 2's files may be (it was read as one plain mapping, and refused nothing)
    path.write_text(
        "amcl:\n  ros__parameters: {alpha1: 0.2}\n"
        "/**:\n  ros__parameters: {planner_frequency: 2.0, use_sim_time: true}\n"
        "tb3_0:\n  frontier_rl_explorer:\n    ros__parameters: {planner_frequency: 0.5, time_cap: 0.0}\n"
    )
    assert explore_lite_parameters(path) == ({"planner_frequency": 0.5, "time_cap": 0.0, "use_sim_time": True}, [])


def test_the_nav2_plugins_goals_name_are_read_from_a_file_and_checked(tmp_path: Path) -> None:
    path = tmp_path / "params.yaml"
    path.write_text(
        "frontier_rl_explorer:\n  ros__parameters:\n"
        "    controller_id: FollowPath\n    goal_checker_id: precise_goal_checker\n"
        "    progress_checker_id: progress_checker\n    behavior_tree: /opt/bt/explore.xml\n"
    )
    known, ignored = explore_lite_parameters(path)
    assert not ignored and Nav2Plugins(**known) == Nav2Plugins(
        "/opt/bt/explore.xml", "FollowPath", "precise_goal_checker", "progress_checker"
    )
    path.write_text("controller_id: 3\n")
    with pytest.raises(ConfigError, match="controller_id must be a string, got 3"):
        explore_lite_parameters(path)
    path.write_text('goal_checker_id: "a\\nb"\n')
    with pytest.raises(ConfigError, match="goal_checker_id must be a plugin's name or ''"):
        explore_lite_parameters(path)
    with pytest.raises(SettingError, match="behavior_tree"):
        Nav2Plugins(behavior_tree=None)  # type: ignore[arg-type]
    with pytest.raises(SettingError, match=r"controller_id must be a plugin's name or '' .*' FollowPath'"):
        Nav2Plugins(controller_id=" FollowPath")  # Nav2 has none of that name
    assert "follow_path's controller" in setting_help("controller_id")


def test_the_plugins_are_picked_by_name_out_of_a_mapping_of_settings_the_rest_kept() -> None:
    base = Nav2Plugins(behavior_tree="/opt/bt/explore.xml", controller_id="FollowPath")
    picked = Nav2Plugins.of({"controller_id": "Precise", "planner_frequency": 0.5, "visualize": True}, base)
    assert picked == Nav2Plugins("/opt/bt/explore.xml", "Precise", "", "")
    assert Nav2Plugins.of({}) == Nav2Plugins() and picked.values()["controller_id"] == "Precise"
    assert set(picked.values()) == set(Nav2Plugins.names())
    with pytest.raises(SettingError, match="goal_checker_id"):
        Nav2Plugins.of({"goal_checker_id": 7})
