"""The short content digest that names a file in results and fingerprints: a model file, a policy's
source file."""

from __future__ import annotations

import hashlib
from pathlib import Path


def file_sha256(path: Path) -> str:
    """The first 16 hex digits of the SHA-256 of the content of the file at ``path``, read in chunks
    (a model file padded to gigabytes filled the memory when read whole)."""
    with path.open("rb") as handle:
        return hashlib.file_digest(handle, "sha256").hexdigest()[:16]
