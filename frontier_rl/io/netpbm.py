"""Netpbm (PBM, PGM, PPM: ``P1``-``P6``) headers read as Pillow, which decodes the pixels, reads
them (:func:`read_netpbm_header`), and the data checked against its header: exactly the pixel data
it announces (:func:`data_size_mismatch`), no sample above its maxval (:func:`sample_above_maxval`).
A map image is never cropped or padded to fit a header that lies about its size."""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

import numpy as np

from frontier_rl.errors import MapError, short_repr

#: Longest Netpbm header read (bytes), comments included.
_NETPBM_HEADER_BYTES = 1 << 16
#: Longest number in a Netpbm header (digits); Pillow refuses longer tokens too.
_NETPBM_TOKEN_DIGITS = 10
_NETPBM_KINDS = {b"P1": "PBM", b"P2": "PGM", b"P3": "PPM", b"P4": "PBM", b"P5": "PGM", b"P6": "PPM"}
_NETPBM_WHITESPACE = b" \t\n\r\x0b\x0c"
_WHITESPACE_CODES = np.frombuffer(_NETPBM_WHITESPACE, dtype=np.uint8)
_PLAIN_CHUNK_BYTES = 1 << 20
#: Plain (ASCII) Netpbm data is refused beyond this many bytes per sample (digits and separators).
_PLAIN_BYTES_PER_SAMPLE = 16


@dataclass(frozen=True)
class NetpbmHeader:
    """The header of a PBM/PGM/PPM file.

    Attributes:
        magic: "P1" .. "P6" (P1-P3 plain text, P4-P6 binary).
        width: pixels per row.
        height: rows.
        maxval: largest sample value (1 for a bitmap).
        data_offset: bytes from the start of the file to the first byte of pixel data.
    """

    magic: str
    width: int
    height: int
    maxval: int
    data_offset: int

    @property
    def kind(self) -> str:
        """The format's name: "PBM", "PGM" or "PPM"."""
        return _NETPBM_KINDS[self.magic.encode()]

    @property
    def plain(self) -> bool:
        """Whether the samples are written as text (P1, P2, P3)."""
        return self.magic in ("P1", "P2", "P3")

    @property
    def channels(self) -> int:
        """Samples per pixel: 3 for a PPM, else 1."""
        return 3 if self.magic in ("P3", "P6") else 1

    @property
    def sample_bytes(self) -> int:
        """Bytes per sample of a binary file: 2 when maxval > 255, else 1."""
        return 2 if self.maxval > 255 else 1

    @property
    def samples(self) -> int:
        """Samples the header announces (width x height x channels)."""
        return self.width * self.height * self.channels

    @property
    def row_bytes(self) -> int:
        """Bytes per row of a binary file (a P4 row is padded to whole bytes)."""
        if self.magic == "P4":
            return (self.width + 7) // 8
        return self.width * self.channels * self.sample_bytes

    def describe(self) -> str:
        """The header's values, for messages."""
        maxval = "" if self.magic in ("P1", "P4") else f", maxval {self.maxval}"
        return f"{self.kind} header ({self.magic}) says {self.width} x {self.height} pixels (width x height){maxval}"


def _header_error(path: Path, magic: bytes, problem: str) -> MapError:
    return MapError(f"{path}: bad {_NETPBM_KINDS[magic]} header ({magic.decode()}): {problem}")


def read_netpbm_header(path: Path) -> NetpbmHeader | None:  # noqa: C901 (a tokenizer: one branch per header rule, each with its own error)
    """The header of the Netpbm file at ``path``, or None when it is not one (PNG, ...).

    Raises:
        MapError: a Netpbm file whose header is malformed or incomplete, whose width or height is not
            a positive whole number, or whose maxval is outside 1..65535.
    """
    with path.open("rb") as stream:
        head = stream.read(_NETPBM_HEADER_BYTES)
    magic = head[:2]
    if magic not in _NETPBM_KINDS or len(head) < 3 or head[2] not in _NETPBM_WHITESPACE:
        return None
    pos = 3  # after the magic number and one whitespace
    names = ("width", "height") if magic in (b"P1", b"P4") else ("width", "height", "maxval")
    values: list[int] = []
    for index, name in enumerate(names):
        # Read as Pillow (the decoder) does: a token ends at a whitespace, which is consumed; a comment
        # runs from "#" through the next CR or LF and is dropped, even in the middle of a token.
        token = b""
        while pos < len(head):
            char = head[pos : pos + 1]
            pos += 1
            if char in _NETPBM_WHITESPACE:
                if token:
                    break
            elif char == b"#":
                if token and index == len(names) - 1:
                    raise _header_error(
                        path, magic, f"a comment right after its {name} (the data must follow one whitespace)"
                    )
                line_end = re.compile(rb"[\r\n]").search(head, pos)
                pos = len(head) if line_end is None else line_end.end()
            else:
                token += char
                if len(token) > _NETPBM_TOKEN_DIGITS:  # refused below, whatever follows
                    break
        else:
            if len(head) == _NETPBM_HEADER_BYTES:
                raise _header_error(path, magic, f"longer than {_NETPBM_HEADER_BYTES} bytes")
            raise _header_error(path, magic, f"the file ends {'after' if token else 'before'} its {name}")
        if not token.isdigit() or int(token[: _NETPBM_TOKEN_DIGITS + 1]) < 1:
            text = short_repr(token.decode("ascii", "replace"), 24)
            raise _header_error(path, magic, f"{name} must be a whole number >= 1, got {text}")
        if len(token) > _NETPBM_TOKEN_DIGITS:
            text = short_repr(token.decode("ascii"), 24)
            raise _header_error(path, magic, f"{name} {text} is absurd: more than {_NETPBM_TOKEN_DIGITS} digits")
        values.append(int(token))
    width, height = values[0], values[1]
    maxval = values[2] if len(values) == 3 else 1
    if maxval > 65535:
        raise _header_error(path, magic, f"maxval must be 1..65535, got {maxval}")
    # The data starts after the one whitespace that ends the header (consumed above).
    return NetpbmHeader(magic.decode(), width, height, maxval, pos)


def _count_plain_samples(stream: BinaryIO, bitmap: bool) -> int:
    """Samples in plain Netpbm data read from ``stream`` (comments skipped; in a P1 bitmap every
    ``0`` or ``1`` is a sample, with or without whitespace between them)."""
    count = 0
    in_comment = False
    in_token = False
    line_end = re.compile(rb"[\r\n]")
    while block := stream.read(_PLAIN_CHUNK_BYTES):
        kept = bytearray()
        pos = 0
        while pos < len(block):
            if in_comment:
                end = line_end.search(block, pos)
                if end is None:
                    break
                pos, in_comment = end.start(), False
            hash_at = block.find(b"#", pos)
            if hash_at < 0:
                kept += block[pos:]
                break
            kept += block[pos:hash_at] + b" "  # a comment separates tokens
            pos, in_comment = hash_at, True
        data = np.frombuffer(bytes(kept), dtype=np.uint8)
        if data.size == 0:
            continue
        if bitmap:
            count += int(np.count_nonzero((data == ord("0")) | (data == ord("1"))))
            continue
        solid = ~np.isin(data, _WHITESPACE_CODES)
        before = np.concatenate(([in_token], solid[:-1]))
        count += int(np.count_nonzero(solid & ~before))
        in_token = bool(solid[-1])
    return count


def _plural(count: int, noun: str) -> str:
    return f"{count} {noun}" if count == 1 else f"{count} {noun}s"


def data_size_mismatch(path: Path, header: NetpbmHeader) -> str | None:
    """The message when the data in ``path`` does not match ``header``'s size, else None."""
    data_bytes = os.stat(path).st_size - header.data_offset
    if not header.plain:
        expected = header.height * header.row_bytes
        if data_bytes == expected:
            return None
        rows, rest = divmod(data_bytes, header.row_bytes)
        extra = f" and {_plural(rest, 'byte')}" if rest else ""
        verdict = "too little" if data_bytes < expected else "too much"
        return (
            f"{path}: {verdict} pixel data: the {header.describe()}, {expected} bytes ({header.height} rows of "
            f"{header.row_bytes} bytes), but the file holds {data_bytes} bytes after the header "
            f"({_plural(rows, 'row')}{extra})"
        )
    byte_limit = header.samples * _PLAIN_BYTES_PER_SAMPLE + _NETPBM_HEADER_BYTES
    if data_bytes > byte_limit:
        return (
            f"{path}: too much pixel data: the {header.describe()}, {header.samples} values, but the file holds "
            f"{data_bytes} bytes of text after the header (at most {byte_limit} would be expected)"
        )
    with path.open("rb") as stream:
        stream.seek(header.data_offset)
        found = _count_plain_samples(stream, header.magic == "P1")
    if found == header.samples:
        return None
    per_row = header.width * header.channels
    rows, rest = divmod(found, per_row)
    extra = f" and {_plural(rest, 'value')}" if rest else ""
    verdict = "too little" if found < header.samples else "too much"
    return (
        f"{path}: {verdict} pixel data: the {header.describe()}, {header.samples} values ({header.height} rows of "
        f"{per_row}), but the file holds {found} values ({_plural(rows, 'row')}{extra})"
    )


def sample_above_maxval(path: Path, header: NetpbmHeader) -> str | None:
    """The message when a binary PGM/PPM sample exceeds the header's maxval (else None)."""
    if header.plain or header.magic == "P4" or header.maxval in (255, 65535):
        return None  # the plain decoder checks its samples; 255 and 65535 cannot be exceeded
    dtype = np.dtype(">u2") if header.sample_bytes == 2 else np.dtype(np.uint8)
    samples = np.fromfile(path, dtype=dtype, count=header.samples, offset=header.data_offset)
    largest = int(samples.max(initial=0))
    if largest <= header.maxval:
        return None
    return f"{path}: pixel value {largest} exceeds the maxval: the {header.describe()}"
