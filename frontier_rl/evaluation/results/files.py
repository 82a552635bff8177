"""The line files of a results folder (``episodes.csv``, ``traces.jsonl``, ``checksums.jsonl``):
read as UTF-8 with every problem named by file and line, a torn last line cut off, appends synced
to disk and cut back when they fail."""

from __future__ import annotations

import contextlib
import json
import os
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Generic, NamedTuple, TypeVar

from frontier_rl import atomic_write
from frontier_rl.atomic_write import OutputWriteError, describe_os_error
from frontier_rl.bounded_read import UnreadableFileError, read_bounded
from frontier_rl.errors import ConfigError, short_repr
from frontier_rl.evaluation.results.episode_record import EpisodeKey

_Entry = TypeVar("_Entry")

MAX_RESULT_FILE_BYTES = 1 << 30
"""Largest results file read (bytes): the traces of some 300,000 episodes (about 3 kB each). A
sparse file of gigabytes, or a link to ``/dev/zero``, filled the memory."""


def read_result_file(path: Path, limit: int = MAX_RESULT_FILE_BYTES) -> bytes:
    """The bytes of ``path``, a regular file of at most ``limit`` bytes; else a one-line error (a
    FIFO in its place blocked the run for good)."""
    try:
        return read_bounded(path, limit)
    except UnreadableFileError as exc:
        if exc.size is None:
            raise ConfigError(
                f"{path} is not a regular file (a FIFO, a device or a folder); choose another --out"
            ) from None
        raise ConfigError(f"{path} holds {exc.size:,} bytes, more than {limit:,}; choose another --out") from None
    except OSError as exc:
        raise ConfigError(f"{path} cannot be read ({describe_os_error(exc)}); choose another --out") from None


def decode_utf8(path: Path, data: bytes, first_line: int = 1) -> str:
    """``data`` as UTF-8, or a one-line error naming the line of ``path`` that is not."""
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = first_line + data.count(b"\n", 0, exc.start)
        column = exc.start - (data.rfind(b"\n", 0, exc.start) + 1) + 1
        raise ConfigError(
            f"{path} line {line} holds bytes that are not UTF-8 (at character {column}): the file was edited or "
            "damaged; fix or delete that line, or choose another --out"
        ) from None


class KeyedLine(NamedTuple, Generic[_Entry]):
    """A line of a JSON-lines file of a results folder: its number (from 1), its text and what it holds."""

    number: int
    line: str
    entry: _Entry


def keyed_lines(
    path: Path, what: str, parse: Callable[[EpisodeKey, Mapping[str, object]], _Entry]
) -> dict[EpisodeKey, KeyedLine[_Entry]]:
    """The JSON lines of ``path`` by episode key, each object read by ``parse`` (which raises
    TypeError or ValueError for one it refuses). A later line of the same episode (rerun after a
    kill) wins.

    Raises:
        ConfigError: a line that is not such an object, named by file and line.
    """
    entries: dict[EpisodeKey, KeyedLine[_Entry]] = {}
    for number, line in complete_lines(path):
        try:
            entry = json.loads(line)
            key = EpisodeKey(entry["method"], entry["world"], entry["episode"])
            hash(key)
            entries[key] = KeyedLine(number, line, parse(key, entry))
        except (ValueError, TypeError, KeyError, AttributeError, RecursionError):
            raise ConfigError(f"{path} line {number} is not {what}: {short_repr(line)}") from None
    return entries


def complete_lines(path: Path) -> list[tuple[int, str]]:
    """The file's complete, non-blank lines with their numbers (from 1; a Windows line end is
    dropped), without a torn last line (no newline: the writer was killed); the file is left as it
    is (:func:`cut_torn_line` cuts that line once the folder is taken)."""
    if not path.exists():
        return []
    data = read_result_file(path)
    end = data.rfind(b"\n") + 1
    text = decode_utf8(path, data[:end])
    return [(i, line.removesuffix("\r")) for i, line in enumerate(text.split("\n"), start=1) if line.strip()]


def cut_torn_line(path: Path) -> None:
    """Cut a torn last line (no newline: the writer was killed, its episode runs again) off the file,
    so that the next append starts on a fresh line. Only the last byte is read unless it is torn
    (the file was read whole, and checked, by :func:`complete_lines` just before)."""
    if not path.exists():
        return
    with path.open("rb") as handle:
        if handle.seek(0, os.SEEK_END) == 0:
            return
        handle.seek(-1, os.SEEK_END)
        if handle.read(1) == b"\n":
            return
    data = read_result_file(path)
    end = data.rfind(b"\n") + 1
    if end < len(data):
        with path.open("r+b") as handle:
            handle.truncate(end)


def append_synced(path: Path, text: str) -> None:
    """Append ``text`` and sync it; if that fails (a full disk), cut the file back to where it
    ended so no partial line is left, and raise :class:`OutputWriteError`."""
    data = text.encode("utf-8")
    try:
        fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT | getattr(os, "O_BINARY", 0), 0o666)
    except OSError as exc:
        raise OutputWriteError(path, describe_os_error(exc)) from None
    try:
        start = os.lseek(fd, 0, os.SEEK_END)
        try:
            atomic_write.write_all(fd, data)
            os.fsync(fd)
        except OSError as exc:
            with contextlib.suppress(OSError):
                os.ftruncate(fd, start)
            raise OutputWriteError(path, describe_os_error(exc)) from None
    finally:
        os.close(fd)
