"""A world's fingerprint, written as experiments and training runs store it and read back."""

from __future__ import annotations

import pytest

from frontier_rl.map_fingerprint import MapFingerprint
from frontier_rl.world_spec import world_fingerprint


@pytest.mark.parametrize(
    ("text", "spec", "digest"),
    [
        ("office", "office", ""),
        ("maps/a.yaml#sha256:0123456789abcdef", "maps/a.yaml", "0123456789abcdef"),
        # a path may hold the mark: the hash is after the last (one reader took the first)
        ("odd#sha256:dir/a.yaml#sha256:0123456789abcdef", "odd#sha256:dir/a.yaml", "0123456789abcdef"),
    ],
)
def test_a_fingerprint_reads_back_as_written(text: str, spec: str, digest: str) -> None:
    fingerprint = MapFingerprint.parse(text)
    assert (fingerprint.spec, fingerprint.digest) == (spec, digest) and str(fingerprint) == text


def test_a_map_files_fingerprint_is_its_spec_and_its_grids_hash() -> None:
    assert world_fingerprint("office", None) == "office"
    fingerprint = MapFingerprint.parse(world_fingerprint("lse_arena", None))
    assert fingerprint.spec == "lse_arena" and len(fingerprint.digest) == 16
