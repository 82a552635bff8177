"""The checksums that bind an episode's row (a line of ``episodes.csv``) to its experiment, its
method and its trace (see :mod:`frontier_rl.evaluation.results.store` for how they are used)."""

from __future__ import annotations

import hashlib
import json
from typing import Any

CHECKSUM_SCHEME = "frontier_rl episode row v1"
"""Hashed first into every row checksum: a later scheme changes it."""


def experiment_id(identity: dict[str, Any]) -> str:
    """The SHA-256 (hex) of an experiment's identity without its methods: what rows of every
    method share (seed, worlds and their map hashes, resolution, simulator and team settings)."""
    parts = {part: value for part, value in identity.items() if part != "methods"}
    return sha256_hex(json.dumps(parts, sort_keys=True, separators=(",", ":")))


def row_checksum(experiment: str, method_fingerprint: str, row_line: str, trace_sha256: str) -> str:
    """The SHA-256 (hex) binding a row's CSV line to its experiment id, its method's fingerprint
    (the model file's hash for learned methods) and its trace's SHA-256."""
    digest = hashlib.sha256()
    for part in (CHECKSUM_SCHEME, experiment, method_fingerprint, row_line, trace_sha256):
        data = part.encode("utf-8")
        digest.update(f"{len(data)}:".encode())  # length-prefixed: no two part lists hash alike
        digest.update(data)
    return digest.hexdigest()


def sha256_hex(text: str) -> str:
    """The SHA-256 (hex) of ``text`` as UTF-8."""
    return hashlib.sha256(text.encode("utf-8")).hexdigest()
