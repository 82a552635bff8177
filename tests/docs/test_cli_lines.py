"""Every ``frontier-rl`` command line in the ```bash / ```console blocks of README.md and of the
site's pages parses against the real command line (Click's parser, every option and value checked,
the command not run): a renamed option or a removed command cannot stay in the documentation."""

from __future__ import annotations

import shlex
from dataclasses import dataclass
from pathlib import Path

import pytest
import typer
import typer.main

from frontier_rl.cli import app
from tests.docs.markdown_pages import CodeBlock, code_blocks, pages

PROGRAM = "frontier-rl"
SHELLS = ("bash", "sh", "shell", "console", "shell-session")
_OPERATORS = frozenset({"|", "||", "&", "&&", ";", ">", ">>", "<", "<<", "(", ")", ">&"})


@dataclass(frozen=True)
class CommandLine:
    """One ``frontier-rl`` invocation found on a page: its arguments after the program name."""

    where: str
    args: tuple[str, ...]


def shell_lines(block: CodeBlock) -> list[str]:
    """The command lines of a shell block, continuation lines joined; in a console block only the
    lines after a ``$`` prompt."""
    lines, pending = [], ""
    for raw in block.code.splitlines():
        line = raw.rstrip()
        if block.language in ("console", "shell-session") and not pending:
            if not line.lstrip().startswith("$ "):
                continue
            line = line.lstrip()[2:]
        if line.endswith("\\"):
            pending += line[:-1] + " "
            continue
        lines.append(pending + line)
        pending = ""
    return lines


def invocations(line: str) -> list[tuple[str, ...]]:
    """The arguments of every ``frontier-rl`` command in shell line ``line`` (a pipeline or a list
    of commands may hold several); environment assignments before it and redirections after it
    are left out."""
    lexer = shlex.shlex(line, posix=True, punctuation_chars=True)
    lexer.whitespace_split = True
    lexer.commenters = "#"
    words, found = list(lexer), []
    start = 0
    while start < len(words):
        end = next((i for i in range(start, len(words)) if words[i] in _OPERATORS), len(words))
        segment = words[start:end]
        while segment and "=" in segment[0] and not segment[0].startswith("-"):
            segment = segment[1:]  # VAR=value before the command
        if segment and (segment[0] == PROGRAM or segment[0].endswith("/" + PROGRAM)):
            args = segment[1:]
            if end < len(words) and words[end] in (">", ">>", "<", ">&") and args and args[-1].isdigit():
                args = args[:-1]  # the 2 of 2>
            found.append(tuple(args))
        start = end + 1
    return found


def command_lines() -> list[CommandLine]:
    found = []
    for page in pages():
        for block in code_blocks(page):
            if block.language not in SHELLS:
                continue
            for line in shell_lines(block):
                found += [CommandLine(f"{block.name}: {line.strip()[:80]}", args) for args in invocations(line)]
    return found


def parse(args: tuple[str, ...]) -> None:
    """Parse ``frontier-rl ARGS`` down to the command it names, as the program would before running it.

    Raises:
        click's UsageError (Typer's copy): an unknown command or option, a bad or missing value.
    """
    command = typer.main.get_command(app)
    context = command.make_context(PROGRAM, list(args), resilient_parsing=False)
    while hasattr(context.command, "resolve_command"):  # a group: on to the command it names
        rest = [*getattr(context, "_protected_args", []), *context.args]
        if not rest:
            return
        name, sub, rest = context.command.resolve_command(context, rest)
        assert sub is not None and name is not None
        context = sub.make_context(name, rest, parent=context)


@pytest.mark.parametrize("line", command_lines(), ids=lambda c: c.where)
def test_the_command_line_parses(line: CommandLine, capsys: pytest.CaptureFixture[str]) -> None:
    try:
        parse(line.args)
    except typer.Exit as done:  # --help prints and exits
        assert done.exit_code == 0
    except Exception as exc:
        if type(exc).__name__ == "NoArgsIsHelpError":  # the bare program (or group): its help
            return
        pytest.fail(f"{line.where}\n{PROGRAM} {shlex.join(line.args)}\n{type(exc).__name__}: {exc}")


def test_a_drifted_option_or_value_fails_to_parse() -> None:
    parse(("explore", "--world", "office", "--seed", "3", "--policy", "tour", "--json"))
    parse(("benchmark", "ariadne", "--limit", "2"))
    for bad in (
        ("explore", "--wrld", "office"),
        ("explore", "--seed", "three"),
        ("evaluate", "--methods", "x"),
        ("no-such-command",),
    ):
        with pytest.raises(Exception, match=r"(?i)no such|valid int|missing") as caught:
            parse(bad)
        assert "UsageError" in [c.__name__ for c in type(caught.value).__mro__]


def test_command_lines_are_found_in_shell_and_console_blocks(tmp_path: Path) -> None:
    page = tmp_path / "page.md"
    page.write_text(
        "# Page\n\n```bash\nPYTHONPATH=. frontier-rl explore --world office \\\n    --seed 3  # a comment\n"
        "make docs && .venv/bin/frontier-rl maps --json | head 2> /dev/null\n```\n\n"
        "```console\n$ frontier-rl train --out runs/x\nmodel: runs/x/model.zip\n```\n"
    )
    lines = [line for block in code_blocks(page) if block.language in SHELLS for line in shell_lines(block)]
    found = [args for line in lines for args in invocations(line)]
    assert found == [
        ("explore", "--world", "office", "--seed", "3"),
        ("maps", "--json"),
        ("train", "--out", "runs/x"),
    ]
