"""The program's commands are built when used: its help lists them as their built selves would, a
command is built when it runs, and the others are left as they were."""

from __future__ import annotations

import pytest
import typer
import typer.main
from typer.testing import CliRunner

from frontier_rl.cli import app
from frontier_rl.cli.app import FrontierRLGroup
from frontier_rl.cli.subcommands import LazyGroup, Subcommand

runner = CliRunner()


def _group() -> tuple[LazyGroup, typer.Context]:
    group = typer.main.get_command(app)
    assert isinstance(group, LazyGroup)
    return group, typer.Context(group, info_name="frontier-rl")


def test_the_help_builds_no_command_and_lists_each_as_when_all_are_built(capsys: pytest.CaptureFixture[str]) -> None:
    group, context = _group()
    group.get_help(context)
    listed = capsys.readouterr().out
    assert not any(command.params for command in group.commands.values())  # listed, none built
    for name in group.list_commands(context):
        assert group.get_command(context, name) is not None
    group.get_help(context)
    assert capsys.readouterr().out == listed
    assert all(f" {s.name} " in listed for s in FrontierRLGroup.subcommands)


@pytest.mark.parametrize("subcommand", FrontierRLGroup.subcommands, ids=lambda s: s.name)
def test_a_stand_in_carries_the_built_commands_name_and_help(subcommand: Subcommand) -> None:
    stand_in, built = subcommand.summary(), subcommand.build()
    assert (stand_in.name, stand_in.help) == (built.name, built.help)
    assert built.help and not stand_in.params and (built.params or hasattr(built, "commands"))


def test_a_command_is_built_when_used_and_the_others_are_not() -> None:
    group, context = _group()
    explore = group.get_command(context, "explore")
    assert explore is not None and "world" in {p.name for p in explore.params}
    assert group.get_command(context, "explore") is explore  # built once
    assert all(not group.commands[s.name].params for s in FrontierRLGroup.subcommands if s.name != "explore")
    assert group.get_command(context, "no-such-command") is None


def test_a_sub_group_is_built_with_its_commands() -> None:
    group, context = _group()
    ros2 = group.get_command(context, "ros2")
    assert isinstance(ros2, typer.core.TyperGroup)
    assert set(ros2.list_commands(context)) == {"sim", "rank", "explore"}


def test_a_mistyped_command_is_still_named_with_a_suggestion() -> None:
    result = runner.invoke(app, ["explor"])
    assert result.exit_code == 2
    assert "No such command 'explor'" in result.output and "'explore'" in result.output
