"""Writing output files so that a failure never destroys the previous version.

Every output (a report, a figure, a summary, a rewritten results file) is written to a temporary
file in the same folder, flushed to disk, and renamed over the target with :func:`os.replace`,
which is atomic on POSIX and Windows: a full disk, a kill or any other error mid-write leaves
the old file as it was (or no file, if there was none), never a truncated one. The temporary
file is removed on failure; a process killed mid-write may leave a hidden ``.NAME.*.tmp`` beside
the target, which nothing reads.

A failed write raises :class:`OutputWriteError`, whose message names the path that could not
be written and why ("No space left on device").
"""

from __future__ import annotations

import contextlib
import io
import os
from pathlib import Path
from typing import Any

from frontier_rl.errors import FrontierRLError


class OutputWriteError(FrontierRLError, OSError):
    """An output file could not be written; the previous version of the file is unchanged.

    Attributes:
        path: the file that could not be written.
        reason: why, as the operating system put it ("No space left on device").
        note: what the caller adds (what was kept, what to do), or "".
    """

    def __init__(self, path: Path | str, reason: str, note: str = "") -> None:
        message = f"could not write {str(path)!r} ({reason}); its previous version, if any, is unchanged"
        super().__init__(f"{message}; {note}" if note else message)
        self.path = Path(path)
        self.reason = reason
        self.note = note

    def with_note(self, note: str) -> OutputWriteError:
        """The same error with ``note`` (replacing any earlier one)."""
        return OutputWriteError(self.path, self.reason, note)


def describe_os_error(exc: OSError) -> str:
    """The operating system's words for ``exc`` ("No space left on device"), or its class name."""
    return exc.strerror or str(exc) or type(exc).__name__


def write_bytes_atomic(path: Path | str, data: bytes) -> None:
    """Replace ``path`` with ``data``, all or nothing.

    Raises:
        OutputWriteError: the file could not be written (``path`` is then unchanged).
    """
    path = Path(path)
    # os.urandom is what the secrets module draws from; importing secrets (hashlib, hmac) costs 6 ms
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{os.urandom(4).hex()}.tmp")
    try:
        # O_EXCL: never write through a file (or link) that is already there; 0o666 under the umask,
        # the permissions a plain open() gives a new file
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0), 0o666)
    except OSError as exc:
        raise OutputWriteError(path, describe_os_error(exc)) from None
    try:
        try:
            write_all(fd, data)
            os.fsync(fd)
        finally:
            os.close(fd)
        os.replace(tmp, path)
    except OSError as exc:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise OutputWriteError(path, describe_os_error(exc)) from None
    except BaseException:  # KeyboardInterrupt and the like: no temporary file left behind
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise
    _sync_folder(path.parent)


def write_all(fd: int, data: bytes) -> None:
    """Write every byte of ``data`` to the open file descriptor ``fd`` (``os.write`` may write
    fewer); an error (a full disk) propagates as the :class:`OSError` it is."""
    view = memoryview(data)
    while view:
        view = view[os.write(fd, view) :]


def write_text_atomic(path: Path | str, text: str) -> None:
    """Replace ``path`` with ``text`` encoded as UTF-8, all or nothing (see :func:`write_bytes_atomic`)."""
    write_bytes_atomic(path, text.encode("utf-8"))


def save_figure_atomic(figure: Any, path: Path | str, **savefig_kwargs: Any) -> Path:
    """Render a Matplotlib ``figure`` in memory and replace ``path`` with it, all or nothing; the
    format follows the file's suffix (PNG if it has none). Returns ``path``.

    Raises:
        OutputWriteError: the file could not be written (``path`` is then unchanged).
    """
    path = Path(path)
    buffer = io.BytesIO()
    figure.savefig(buffer, format=path.suffix.lstrip(".").lower() or "png", **savefig_kwargs)
    write_bytes_atomic(path, buffer.getvalue())
    return path


def _sync_folder(folder: Path) -> None:
    """Flush the folder's entry of a renamed file to disk where the platform allows it."""
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:  # not possible on this platform (Windows) or this file system
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)
