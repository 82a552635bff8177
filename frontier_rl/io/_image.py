"""Decoding of map images (PGM, PNG, any Pillow mode) into plain NumPy arrays.

Every failure (missing file, truncated or corrupt data, not an image) becomes a one-line
:class:`~frontier_rl.errors.MapError` that names the file. Before any pixel is decoded:

* an image larger than :data:`MAX_MAP_PIXELS` is refused (from its header, before allocating);
* a Netpbm file (PBM/PGM/PPM, ``P1``-``P6``) must hold exactly the pixel data its header
  announces: a header claiming fewer rows (or columns) than the data holds, or more, is an error
  naming the header's width, height and maxval and the data's actual size, never a cropped or
  padded map. Its maxval must be 1..65535 and no sample may exceed it.
"""

from __future__ import annotations

import os
import re
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

import numpy as np
from numpy.typing import NDArray
from PIL import Image

from frontier_rl.errors import MapError, short_repr, short_text

#: Largest map image accepted (pixels, width x height): 4096 x 4096 or the same area in any shape,
#: about 5 times the largest map the package ships (ipa_plant, 1985 x 1536 = 3.0 Mpx).
#: Decoding one takes about 32 bytes of memory per pixel (0.5 GiB at the limit).
MAX_MAP_PIXELS = 4096 * 4096
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
#: Divisor that maps 16-bit samples (0..65535) onto the 8-bit scale (0..255).
_SIXTEEN_TO_EIGHT_BIT = 257.0
_GREY_MODES = frozenset({"1", "L", "LA", "La"})
_ALPHA_MODES = frozenset({"RGBA", "RGBa", "LA", "La", "PA"})


@dataclass(frozen=True)
class RasterImage:
    """A decoded image in image order (row 0 is the top row).

    Attributes:
        colour: float64 array (rows, cols, n) of colour samples on the 0..255 scale; n is 1 for a
            greyscale image and 3 (R, G, B) for a colour one.
        alpha: float64 array (rows, cols) of opacities on the 0..255 scale (0 = fully transparent),
            or None when the image carries no transparency.
    """

    colour: NDArray[np.float64]
    alpha: NDArray[np.float64] | None

    @property
    def shape(self) -> tuple[int, int]:
        """(rows, cols) of the image in pixels."""
        return (int(self.colour.shape[0]), int(self.colour.shape[1]))

    @property
    def shade(self) -> NDArray[np.float64]:
        """Brightness (0..255): the mean of the colour channels, as ROS ``map_server`` computes it."""
        return np.asarray(self.colour.mean(axis=2), dtype=np.float64)

    @property
    def transparent(self) -> NDArray[np.bool_]:
        """Mask of the fully transparent pixels (alpha 0)."""
        if self.alpha is None:
            return np.zeros(self.shape, dtype=np.bool_)
        return np.asarray(self.alpha == 0)


def _decode(image: Image.Image) -> RasterImage:
    """Arrays of an open Pillow image of any mode."""
    if image.mode.startswith("I"):  # 16/32-bit integer greyscale (16-bit PNG or PGM)
        grey = np.clip(np.asarray(image, dtype=np.float64) / _SIXTEEN_TO_EIGHT_BIT, 0.0, 255.0)
        return RasterImage(colour=grey[:, :, np.newaxis], alpha=None)
    has_alpha = image.mode in _ALPHA_MODES or "transparency" in image.info
    target = ("L" if image.mode in _GREY_MODES else "RGB") + ("A" if has_alpha else "")
    pixels = np.asarray(image.convert(target), dtype=np.float64)
    if pixels.ndim == 2:
        pixels = pixels[:, :, np.newaxis]
    if has_alpha:
        return RasterImage(colour=pixels[:, :, :-1], alpha=pixels[:, :, -1])
    return RasterImage(colour=pixels, alpha=None)


def _too_large(path: Path, width: int, height: int) -> str | None:
    """The message refusing an image of ``width`` x ``height`` pixels, or None when it is allowed."""
    if width * height <= MAX_MAP_PIXELS:
        return None
    return (
        f"{path}: the image is {width} x {height} pixels (width x height), {width * height} in all; "
        f"at most {MAX_MAP_PIXELS} are allowed"
    )


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
            a positive whole number, whose maxval is outside 1..65535, or larger than :data:`MAX_MAP_PIXELS`.
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
    too_large = _too_large(path, width, height)
    if too_large is not None:
        raise MapError(too_large)
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


def _data_size_mismatch(path: Path, header: NetpbmHeader) -> str | None:
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


def _sample_above_maxval(path: Path, header: NetpbmHeader) -> str | None:
    """The message when a binary PGM/PPM sample exceeds the header's maxval (else None)."""
    if header.plain or header.magic == "P4" or header.maxval in (255, 65535):
        return None  # the plain decoder checks its samples; 255 and 65535 cannot be exceeded
    dtype = np.dtype(">u2") if header.sample_bytes == 2 else np.dtype(np.uint8)
    samples = np.fromfile(path, dtype=dtype, count=header.samples, offset=header.data_offset)
    largest = int(samples.max(initial=0))
    if largest <= header.maxval:
        return None
    return f"{path}: pixel value {largest} exceeds the maxval: the {header.describe()}"


def _bomb_size(exc: Exception) -> str:
    match = re.search(r"\((\d+) pixels\)", str(exc))
    return f"{match.group(1)} pixels" if match else "too many pixels"


def read_image(path: Path) -> RasterImage:
    """Decode the image file at ``path`` (PGM, PNG or anything Pillow reads).

    Raises:
        MapError: the file is missing or is not an image; it has more than :data:`MAX_MAP_PIXELS`
            pixels; its data is truncated or corrupt; a PBM/PGM/PPM header does not match its data.
    """
    if not path.is_file():
        raise MapError(f"map image not found: {path}")
    try:
        header = read_netpbm_header(path)
    except OSError as exc:
        raise MapError(f"cannot read map image {path}: {exc.strerror or exc}") from exc
    try:
        with warnings.catch_warnings():
            # the limit here is MAX_MAP_PIXELS, well below the size that Pillow warns about
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)
            opened = Image.open(path)
        with opened as image:
            too_large = _too_large(path, *image.size)
            if too_large is not None:
                raise MapError(too_large)
            if header is not None and image.size != (header.width, header.height):  # never expected
                raise MapError(f"{path}: unsupported {header.kind} header: read as {image.size[0]} x {image.size[1]}")
            image.load()
            raster = _decode(image)
    except MapError:
        raise
    except Image.DecompressionBombError as exc:
        raise MapError(
            f"{path}: the image's header claims {_bomb_size(exc)}; at most {MAX_MAP_PIXELS} are allowed"
        ) from None
    # Pillow's decoders raise many unrelated types on corrupt input (OSError, SyntaxError,
    # ValueError, struct.error, IndexError, ...): every one of them means "bad image file".
    except Exception as exc:
        mismatch = _data_size_mismatch(path, header) if header is not None else None
        raise MapError(mismatch or f"cannot read map image {path}: {short_text(str(exc), 200)}") from exc
    if header is not None:
        problem = _data_size_mismatch(path, header) or _sample_above_maxval(path, header)
        if problem is not None:
            raise MapError(problem)
    return raster
