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


def test_the_help_builds_no_command_and_lists_each_as_when_all_are_built() -> None:
    group, context = _group()
    listed = group.get_help(context)
    assert not any(command.params for command in group.commands.values())  # listed, none built
    for name in group.list_commands(context):
        assert group.get_command(context, name) is not None
    assert group.get_help(context) == listed
    assert all(f"  {s.name}  " in listed for s in FrontierRLGroup.subcommands)


def _first_sentences_listed(group: typer.core.TyperGroup, context: typer.Context) -> None:
    listed = group.get_help(context)
    for name in group.list_commands(context):
        command = group.get_command(context, name)
        assert command is not None and command.help
        assert f"{command.help.split('.')[0]}." in listed, name
        if isinstance(command, typer.core.TyperGroup):
            _first_sentences_listed(command, typer.Context(command, info_name=name, parent=context))


def test_the_help_gives_each_command_its_whole_first_sentence() -> None:
    _first_sentences_listed(*_group())


@pytest.mark.parametrize("subcommand", FrontierRLGroup.subcommands, ids=lambda s: s.name)
def test_a_stand_in_carries_the_built_commands_name_and_help(subcommand: Subcommand) -> None:
    group, _ = _group()
    stand_in, built = subcommand.summary(), subcommand.build(group.rich_markup_mode)
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


@pytest.mark.parametrize("args", [[], ["ros2"]], ids=["program", "group"])
def test_a_bare_group_prints_its_help_and_exits_2(args: list[str]) -> None:
    result = runner.invoke(app, args, prog_name="frontier-rl")
    assert result.exit_code == 2
    assert result.stderr.startswith(" ".join(["Usage: frontier-rl", *args, "[OPTIONS] COMMAND"]))
    assert "Commands:" in result.stderr and not result.stdout
