"""The top-level group's commands, each built when it is used, not on every start.

Typer builds a command by reading its function's signature and evaluating every parameter's
annotation (twice); for the ten commands of ``frontier-rl`` that took about 30 ms of every process
here, whichever command ran. Here the group starts with each command's name and help text only
(what its help lists) and builds a command when it is run, its own help is shown, or a tool asks
the group for it (:meth:`LazyGroup.get_command`).
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, ClassVar

import typer
import typer.main
from typer.core import MarkupMode, TyperCommand, TyperGroup

from frontier_rl.cli.output import OneLineGroup


@dataclass(frozen=True)
class Subcommand:
    """A command of the group: a command function, or a Typer application of commands (a sub-group).

    Attributes:
        name: what the command line calls it.
        target: the function (as ``app.command()`` takes it) or the Typer application.
    """

    name: str
    target: Callable[..., Any] | typer.Typer

    @property
    def help(self) -> str | None:
        """The command's help text, as Typer takes it: the application's ``help``, else the
        function's docstring."""
        if isinstance(self.target, typer.Typer):
            given = self.target.info.help
            return given if isinstance(given, str) else None
        return inspect.getdoc(self.target)

    def summary(self) -> TyperCommand:
        """A stand-in that carries the name and the help text, all a group's help lists of it."""
        return TyperCommand(self.name, help=self.help)

    def build(self, rich_markup_mode: MarkupMode) -> TyperCommand | TyperGroup:
        """The command as Typer builds it inside a group whose help uses ``rich_markup_mode``."""
        holder = typer.Typer(add_completion=False, rich_markup_mode=rich_markup_mode)
        if isinstance(self.target, typer.Typer):
            holder.add_typer(self.target, name=self.name)
        else:
            holder.command(self.name)(self.target)
        command = typer.main.get_group(holder).commands[self.name]
        assert isinstance(command, TyperCommand | TyperGroup)
        return command


class LazyGroup(OneLineGroup):
    """A command group whose :attr:`subcommands` are built when used: its help lists them by name
    and help text alone. A subclass names its commands."""

    subcommands: ClassVar[tuple[Subcommand, ...]] = ()

    def __init__(self, **attrs: Any) -> None:
        super().__init__(**attrs)
        self._listing = False
        self._unbuilt = {subcommand.name: subcommand for subcommand in self.subcommands}
        for subcommand in self.subcommands:
            self.add_command(subcommand.summary())

    def get_command(self, ctx: Any, cmd_name: str) -> Any:
        """The command named ``cmd_name`` (a click command of Typer's), built on first use; while
        the group's help is written, a stand-in if it is not built yet."""
        subcommand = self._unbuilt.get(cmd_name)
        if subcommand is not None and not self._listing:
            del self._unbuilt[cmd_name]
            self.commands[cmd_name] = subcommand.build(self.rich_markup_mode)
        return super().get_command(ctx, cmd_name)

    def format_help(self, ctx: Any, formatter: Any) -> None:
        """The group's help, listing the commands not built yet by their stand-ins."""
        self._listing = True
        try:
            super().format_help(ctx, formatter)
        finally:
            self._listing = False
