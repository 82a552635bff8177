"""How the ``frontier-rl`` command line talks to its user: every message on one line, as plain
text (user text such as ``[/x]`` is never read as Rich markup), usage errors and bad input as one
``error:`` line with exit code 2, and the warnings of a command gathered and printed after it."""

from __future__ import annotations

import re
import sys
import warnings
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from functools import wraps
from typing import TYPE_CHECKING, Any, TypeVar

import typer
from typer.core import TyperGroup

from frontier_rl.errors import ConfigError, FrontierRLError, caused_by_interrupt, short_repr

if TYPE_CHECKING:  # rich loads when a command prints: help and argument checks need none of it
    from rich.console import Console
    from rich.table import Table

#: Longest message the error printer writes (characters); the rest is cut.
MESSAGE_LIMIT = 600
#: Most distinct warnings printed at the end of a command (one line each).
MAX_WARNINGS = 5

F = TypeVar("F", bound=Callable[..., Any])
_LINE_BREAKS = re.compile(r"[ \t]*[\r\n\t\v\f]+[ \t]*")
_CONTROL = re.compile(r"[\x00-\x1f\x7f-\x9f]")
# Click's exception base, found through a public Typer class: recent Typer vendors Click as
# typer._click, older Typer uses the click package itself.
_CLICK_EXCEPTION: type[Exception] = next(c for c in typer.BadParameter.__mro__ if c.__name__ == "ClickException")


def err_console() -> Console:
    """Standard error, for messages: they carry user text (paths, names, values) and are printed as
    plain text, Rich markup and emoji codes off, so "[/x]" or "[red]" in a name is printed as it is."""
    from rich.console import Console

    return Console(stderr=True, soft_wrap=True, markup=False, emoji=False, highlight=False)


def stdout_console() -> Console:
    """Standard output, with Rich markup and emoji codes off (names and paths print as they are)."""
    from rich.console import Console

    return Console(markup=False, emoji=False)


def print_line(text: str) -> None:
    """``text`` on standard output as it is, never wrapped: a pipe or a file gets one line (Rich
    wrapped at 80 columns where no terminal gave a width), a terminal wraps it itself."""
    stdout_console().print(text, soft_wrap=True)


def print_table(table: Table) -> None:
    """``table`` on standard output: at a terminal's width; whole to a pipe or a file (Rich cut its
    columns, a long method name among them, to 80 columns where no terminal gave a width)."""
    console = stdout_console()
    if not console.is_terminal:
        console.width = max(console.width, whole_width(console, table))
    console.print(table)


def whole_width(console: Console, table: Table) -> int:
    """The columns ``table`` takes on ``console`` with no column cut or folded."""
    return console.measure(table, options=console.options.update_width(10_000)).maximum


def one_line(text: str, limit: int = MESSAGE_LIMIT) -> str:
    """``text`` as one line of at most ``limit`` characters: line breaks become spaces, other
    control characters escapes (``\\x1b``), and a longer text is cut (an ellipsis marks the cut)."""
    text = _CONTROL.sub(lambda m: f"\\x{ord(m.group()):02x}", _LINE_BREAKS.sub(" ", text.strip()))
    return text if len(text) <= limit else text[: limit - 1] + "…"


def comma_list(text: str) -> list[str]:
    """The items of a comma-separated option, stripped, empty ones dropped."""
    return [part.strip() for part in text.split(",") if part.strip()]


def policy_list(text: str) -> list[str]:
    """The policies of ``--methods``, each once; none (an empty shell variable, say) is an error:
    a run of the baseline alone would compare nothing."""
    names = list(dict.fromkeys(comma_list(text)))
    if not names:
        raise ConfigError(f"--methods names no policy: {short_repr(text)}")
    return names


def int_list(option: str, text: str) -> list[int]:
    """The whole numbers of a comma list given to ``option``.

    Raises:
        ConfigError: a part that is not a whole number, or no part at all.
    """
    try:
        values = [int(part) for part in comma_list(text)]
    except ValueError:
        raise ConfigError(f"{option} must be a comma list of whole numbers, got {text!r}") from None
    if not values:
        raise ConfigError(f"{option} needs at least one value, got {text!r}")
    return values


def print_error(message: str) -> None:
    """``error: MESSAGE`` on standard error, on one line, as plain text (never Rich markup)."""
    _print_labelled(("error:", "red"), message)


def print_note(message: str) -> None:
    """``MESSAGE`` on standard error, on one line, as plain text (never Rich markup)."""
    err_console().print(one_line(message))


def print_warning(message: str) -> None:
    """``warning: MESSAGE`` on standard error, on one line, as plain text (never Rich markup)."""
    _print_labelled(("warning:", "yellow"), message)


def _print_labelled(label: tuple[str, str], message: str) -> None:
    """``LABEL MESSAGE`` on standard error, the label in its colour (text, colour), the message on
    one line as plain text."""
    from rich.text import Text

    err_console().print(Text.assemble(label, " ", one_line(message)))


def os_message(exc: OSError) -> str:
    """What went wrong and with which file(s), from an OSError."""
    what = exc.strerror or str(exc) or type(exc).__name__
    names = [str(name) for name in (exc.filename, exc.filename2) if name is not None]
    return f"{what}: {' -> '.join(names)}" if names else what


def _print_warnings(caught: Sequence[warnings.WarningMessage]) -> None:
    """Each distinct warning once, one line each, at most :data:`MAX_WARNINGS`."""
    texts = list(dict.fromkeys(f"{w.category.__name__}: {w.message}" for w in caught))
    for text in texts[:MAX_WARNINGS]:
        print_warning(text)
    if len(texts) > MAX_WARNINGS:
        print_warning(f"{len(texts) - MAX_WARNINGS} more warning(s) not shown")


@contextmanager
def _interrupt_ends_command() -> Iterator[None]:
    """A Ctrl-C ends the command with the line ``interrupted`` and exit code 130."""
    try:
        yield
    except (KeyboardInterrupt, SystemError) as error:  # a SystemError: numba's, of a Ctrl-C in a kernel's callback
        if not caused_by_interrupt(error):
            raise
        print_note("interrupted")
        raise typer.Exit(130) from None


class OneLineGroup(TyperGroup):
    """Typer's command group with a usage error (an unknown option, a value that is not a number)
    printed as one ``error:`` line, exit code 2, instead of a usage panel; warnings raised while a
    command runs are gathered and printed after it, one line each (none after an error: the error
    is the one line). A Ctrl-C ends the command with the line ``interrupted`` and exit code 130,
    where typer would end it without a word."""

    def make_context(self, *args: Any, **kwargs: Any) -> Any:
        """The group's click context (parses its options)."""
        with _interrupt_ends_command():
            return super().make_context(*args, **kwargs)

    def invoke(self, ctx: Any) -> Any:
        """Parse and run the command ``ctx`` (a click context: typer's own copy of click's, or
        click's in older typer) names."""
        with _interrupt_ends_command():
            return super().invoke(ctx)

    def main(
        self,
        args: Sequence[str] | None = None,
        prog_name: str | None = None,
        complete_var: str | None = None,
        standalone_mode: bool = True,
        windows_expand_args: bool = True,
        **extra: Any,
    ) -> Any:
        """Run the command line; in standalone mode, exit with its code (see the class)."""
        if not standalone_mode:
            return super().main(args, prog_name, complete_var, False, windows_expand_args, **extra)
        with warnings.catch_warnings(record=True) as caught:
            try:
                result = super().main(args, prog_name, complete_var, False, windows_expand_args, **extra)
                code = result if isinstance(result, int) else 0
            except _CLICK_EXCEPTION as exc:
                code = int(getattr(exc, "exit_code", 2))
                if type(exc).__name__ != "NoArgsIsHelpError":
                    print_error(_usage_message(exc, sys.argv[1:] if args is None else args))
                elif str(exc).strip():  # the help as text, where click prints it (a rich layout printed itself)
                    print(str(exc), file=sys.stderr)
            except typer.Abort:
                print_error("aborted")
                code = 1
        if code == 0:
            _print_warnings(caught)
        sys.exit(code)


def _usage_message(exc: Exception, args: Sequence[str]) -> str:
    """A usage error's message, with the value given where it names none (typer 0.29's pydantic
    messages named only the option; those of the typer this package requires name the value) and
    where to find the command's help."""
    message = getattr(exc, "format_message", exc.__str__)()
    given = _given(args, getattr(getattr(exc, "param", None), "opts", []))
    if given is not None and given not in message:
        message += f", got {short_repr(given)}"
    command = getattr(getattr(exc, "ctx", None), "command_path", None)
    return f"{message} (see '{command} --help')" if command else message


def _given(args: Sequence[str], options: Sequence[str]) -> str | None:
    """The value the command line gave last to one of ``options`` (``--opt VALUE`` or
    ``--opt=VALUE``), if any."""
    given = None
    for i, arg in enumerate(args):
        for option in options:
            if arg == option and i + 1 < len(args):
                given = args[i + 1]
            elif arg.startswith(f"{option}="):
                given = arg[len(option) + 1 :]
    return given


def friendly_errors(func: F) -> F:
    """Bad input ends the command with a one-line message and exit code 2, never a traceback."""

    @wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return func(*args, **kwargs)
        except FrontierRLError as exc:
            print_error(str(exc))
            raise typer.Exit(2) from None
        except OSError as exc:
            print_error(os_message(exc))
            raise typer.Exit(2) from None

    return wrapper  # type: ignore[return-value]
