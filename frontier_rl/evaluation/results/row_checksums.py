"""The checksums that bind an episode's row (a line of ``episodes.csv``) to its experiment, its
method and its trace (see :mod:`frontier_rl.evaluation.results.store` for how they are used)."""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping
from dataclasses import dataclass

from frontier_rl.evaluation.results.episode_record import EpisodeKey

CHECKSUM_SCHEME = "frontier_rl episode row v1"
"""Hashed first into every row checksum: a later scheme changes it."""


@dataclass(frozen=True)
class RowChecksum:
    """A line of ``checksums.jsonl``: an episode's key, the SHA-256 (hex) of its trace's line in
    ``traces.jsonl`` and its row checksum (:func:`row_checksum`)."""

    key: EpisodeKey
    trace_sha256: str
    row_sha256: str

    @classmethod
    def of(
        cls, experiment: str, method_fingerprint: str, key: EpisodeKey, row_line: str, trace_line: str
    ) -> RowChecksum:
        """The checksum of the row ``row_line`` of episode ``key`` with the trace ``trace_line``
        (both without their line ends), in experiment ``experiment`` (its id)."""
        trace_sha256 = sha256_hex(trace_line)
        return cls(key, trace_sha256, row_checksum(experiment, method_fingerprint, row_line, trace_sha256))

    @classmethod
    def from_json(cls, key: EpisodeKey, entry: Mapping[str, object]) -> RowChecksum:
        """The checksum of episode ``key`` that a line's object holds.

        Raises:
            TypeError: a checksum that is not a string.
        """
        trace_sha256, row_sha256 = entry.get("trace_sha256"), entry.get("row_sha256")
        if not isinstance(trace_sha256, str) or not isinstance(row_sha256, str):
            raise TypeError("a checksum is not a string")
        return cls(key, trace_sha256, row_sha256)

    def line(self) -> str:
        """The line of ``checksums.jsonl`` (without its line end)."""
        method, world, episode = self.key
        entry = {
            "method": method,
            "world": world,
            "episode": episode,
            "trace_sha256": self.trace_sha256,
            "row_sha256": self.row_sha256,
        }
        return json.dumps(entry, separators=(",", ":"))


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
