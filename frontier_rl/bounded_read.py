"""Reading an untrusted file whole, bounded: only a regular file (a FIFO would block the read for
good, a device such as ``/dev/zero`` never ends), and no more than a given number of bytes (a
sparse file of gigabytes takes 4 kB on disk). The counterpart of :mod:`frontier_rl.atomic_write`."""

from __future__ import annotations

import stat
from pathlib import Path


class UnreadableFileError(Exception):
    """A file :func:`read_bounded` would not read whole.

    Attributes:
        size: its size (bytes) when it is too large; None when it is no regular file.
        limit: the most bytes allowed.
    """

    def __init__(self, path: Path, size: int | None, limit: int) -> None:
        self.path, self.size, self.limit = path, size, limit
        super().__init__(
            f"{path}: " + ("not a regular file" if size is None else f"{size:,} bytes, more than {limit:,}")
        )


def read_bounded(path: Path, limit: int) -> bytes:
    """The bytes of ``path``, a regular file (a link to one is followed) of at most ``limit`` bytes.

    Raises:
        UnreadableFileError: not a regular file, or larger than ``limit`` (``size`` is then at least
            ``limit + 1``: the file may have grown after it was looked at).
        OSError: it cannot be opened or read.
    """
    info = path.stat()
    if not stat.S_ISREG(info.st_mode):
        raise UnreadableFileError(path, None, limit)
    if info.st_size > limit:
        raise UnreadableFileError(path, info.st_size, limit)
    with path.open("rb") as handle:
        data = handle.read(limit + 1)
    if len(data) > limit:
        raise UnreadableFileError(path, len(data), limit)
    return data
