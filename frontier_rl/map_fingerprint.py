"""A world's fingerprint as an experiment's identity and a training run's ``map_files.txt`` write
it: a generator by its name; a map file by its spec as given (a path or a catalogue name) and a
hash of the grid it loads as, ``SPEC#sha256:HASH``."""

from __future__ import annotations

from dataclasses import dataclass

HASH_MARK = "#sha256:"
"""What separates a map file's spec from its hash in the written form."""


@dataclass(frozen=True)
class MapFingerprint:
    """A world's fingerprint.

    Attributes:
        spec: the world as given (a generator's name, a map file's path or catalogue name).
        digest: the hash of the grid a map file loads as (hex); "" for a generator.
    """

    spec: str
    digest: str = ""

    @classmethod
    def parse(cls, text: str) -> MapFingerprint:
        """The fingerprint written as ``text`` (the hash after the last mark: a path may hold one)."""
        spec, mark, digest = text.rpartition(HASH_MARK)
        return cls(spec, digest) if mark else cls(text)

    def __str__(self) -> str:
        return f"{self.spec}{HASH_MARK}{self.digest}" if self.digest else self.spec
