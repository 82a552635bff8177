"""Netpbm (PGM/PBM/PPM) headers against their data, and image size limits (issue 14): a header that
claims fewer or more rows or columns than the file holds, a bad maxval or an absurd size is a one-line
MapError naming the file, the header's values and the data's actual size; never a cropped map."""

from __future__ import annotations

import struct
import time
import zlib
from pathlib import Path

import numpy as np
import pytest

from frontier_rl.errors import MapError
from frontier_rl.io import MAX_MAP_PIXELS, load_map
from frontier_rl.io._image import read_image
from frontier_rl.io.netpbm import read_netpbm_header

FREE = 254


def p5(width: int, height: int, data: bytes, maxval: int = 255, magic: bytes = b"P5") -> bytes:
    return magic + f"\n{width} {height}\n{maxval}\n".encode() + data


def p2(width: int, height: int, values: list[int], maxval: int = 255) -> bytes:
    rows = [" ".join(map(str, values[i : i + width])) for i in range(0, len(values), width)]
    return f"P2\n{width} {height}\n{maxval}\n".encode() + "\n".join(rows).encode() + b"\n"


def refused(tmp_path: Path, data: bytes, name: str = "map.pgm") -> str:
    """The one-line MapError of loading a map image holding ``data``."""
    path = tmp_path / name
    path.write_bytes(data)
    start = time.perf_counter()
    with pytest.raises(MapError) as info:
        load_map(path)
    assert time.perf_counter() - start < 5
    message = str(info.value)
    assert "\n" not in message and len(message) < 600, message
    assert name in message
    return message


# --------------------------------------------------------------------------- header vs data
@pytest.mark.parametrize(
    ("data", "needles"),
    [
        # a header claiming fewer rows than the file holds: not cut without a word
        (p5(10, 5, bytes([FREE]) * 100), ["too much", "10 x 5", "50 bytes", "holds 100 bytes", "10 rows"]),
        (p5(10, 1, bytes([FREE]) * 100), ["too much", "10 x 1", "holds 100 bytes"]),
        # a header claiming more rows than the data: not blamed on anything else
        (p5(10, 20, bytes([FREE]) * 100), ["too little", "10 x 20", "200 bytes", "holds 100 bytes", "10 rows"]),
        (p5(10, 10, bytes([FREE]) * 99), ["too little", "10 x 10", "holds 99 bytes", "9 rows and 9 bytes"]),
        (p5(10, 10, b""), ["too little", "holds 0 bytes"]),
        # columns that do not match
        (p5(9, 10, bytes([FREE]) * 100), ["too much", "9 x 10", "90 bytes", "holds 100 bytes"]),
        (p5(11, 10, bytes([FREE]) * 100), ["too little", "11 x 10", "110 bytes", "holds 100 bytes"]),
        # 16-bit samples: two bytes each
        (p5(4, 4, bytes([255, 254]) * 15, maxval=65535), ["too little", "maxval 65535", "32 bytes", "holds 30"]),
        (p5(4, 4, bytes([255, 254]) * 17, maxval=65535), ["too much", "maxval 65535", "32 bytes", "holds 34"]),
        (p5(4, 4, bytes([FREE]) * 32, maxval=255), ["too much", "maxval 255", "16 bytes", "holds 32"]),
        # one trailing byte is data too
        (p5(10, 10, bytes([FREE]) * 100 + b"\n"), ["too much", "holds 101 bytes", "10 rows and 1 byte"]),
        # plain (ASCII) PGM
        (p2(3, 2, [FREE] * 9), ["too much", "P2", "3 x 2", "6 values", "holds 9 values", "3 rows"]),
        (p2(3, 3, [FREE] * 6), ["too little", "P2", "3 x 3", "9 values", "holds 6 values", "2 rows"]),
        (p2(4, 2, [FREE] * 6), ["too little", "4 x 2", "holds 6 values", "1 row and 2 values"]),
        # bitmaps and colour
        (b"P4\n10 2\n" + bytes(3), ["too little", "PBM", "P4", "10 x 2", "4 bytes", "holds 3 bytes"]),
        (b"P4\n10 2\n" + bytes(6), ["too much", "P4", "holds 6 bytes"]),
        (b"P1\n3 2\n0 0 0\n0000\n", ["too much", "P1", "6 values", "holds 7 values"]),
        (p5(2, 2, bytes([FREE]) * 11, magic=b"P6"), ["too little", "PPM", "P6", "12 bytes", "holds 11 bytes"]),
        (b"P3\n1 1\n255\n254 254 254 254\n", ["too much", "P3", "3 values", "holds 4 values"]),
    ],
    ids=["rows-fewer", "rows-one", "rows-more", "one-byte-short", "no-data", "cols-fewer", "cols-more", "16-bit-short",
         "16-bit-long", "8-bit-double", "trailing-newline", "p2-rows-fewer", "p2-rows-more", "p2-cols", "p4-short",
         "p4-long", "p1-long", "p6-short", "p3-long"],
)  # fmt: skip
def test_header_and_data_sizes_must_match(tmp_path: Path, data: bytes, needles: list[str]) -> None:
    message = refused(tmp_path, data)
    assert "header" in message
    for needle in needles:
        assert needle in message, message


@pytest.mark.parametrize(
    ("data", "needle"),
    [
        (p5(10, 10, bytes([FREE]) * 100, maxval=0), "maxval must be a whole number >= 1, got '0'"),
        (p5(10, 10, bytes([FREE]) * 100, maxval=65536), "maxval must be 1..65535, got 65536"),
        (p5(10, 10, bytes([FREE]) * 100, maxval=70000), "maxval must be 1..65535, got 70000"),
        (b"P5\n-10 10\n255\n" + bytes(100), "width must be a whole number >= 1, got '-10'"),
        (b"P5\n10 -10\n255\n" + bytes(100), "height must be a whole number >= 1, got '-10'"),
        (b"P5\n0 10\n255\n", "width must be a whole number >= 1, got '0'"),
        (b"P5\n10 0\n255\n", "height must be a whole number >= 1, got '0'"),
        (b"P5\n1e3 10\n255\n" + bytes(100), "width must be a whole number >= 1, got '1e3'"),
        (b"P5\n99999999999 10\n255\n", "width '99999999999' is absurd"),
        (b"P5\n" + b"9" * 5000 + b" 10\n255\n", "is absurd"),
        (b"P5\n10 10\n", "the file ends before its maxval"),
        (b"P5\n10 10\n255", "the file ends after its maxval"),
        (b"P5\n# only a comment", "the file ends before its width"),
        (b"P5\n#" + b"x" * 70_000 + b"\n10 10\n255\n", "longer than 65536 bytes"),
        (b"P5\n10 10\n255#c\n" + bytes(100), "a comment right after its maxval"),
        (p5(3, 1, bytes([1, 2, 200]), maxval=100), "pixel value 200 exceeds the maxval"),
        (p5(2, 1, bytes([0x03, 0xE9, 0, 0]), maxval=1000), "pixel value 1001 exceeds the maxval"),
        (p2(3, 1, [1, 2, 600], maxval=100), "Channel value too large"),
    ],
    ids=["maxval-0", "maxval-65536", "maxval-70000", "width-negative", "height-negative", "width-0", "height-0",
         "width-float", "width-11-digits", "width-5000-digits", "no-maxval", "ends-after-maxval", "only-comment",
         "long-comment", "comment-after-maxval", "sample-above-maxval", "16-bit-above-maxval", "p2-above-maxval"],
)  # fmt: skip
def test_bad_headers_are_named(tmp_path: Path, data: bytes, needle: str) -> None:
    message = refused(tmp_path, data)
    assert needle in message, message


def test_a_header_claiming_fewer_rows_is_not_read_through_a_ros_yaml_either(tmp_path: Path) -> None:
    (tmp_path / "map.pgm").write_bytes(p5(10, 5, bytes([FREE]) * 100))
    (tmp_path / "lab.yaml").write_text(
        "image: map.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.2\n"
    )
    with pytest.raises(MapError, match=r"map\.pgm: too much pixel data: .* 10 x 5 .* holds 100 bytes"):
        load_map(tmp_path / "lab.yaml")


def test_too_little_data_keeps_the_decoders_error_as_its_cause(tmp_path: Path) -> None:
    (tmp_path / "map.pgm").write_bytes(p5(10, 20, bytes([FREE]) * 100))
    with pytest.raises(MapError, match="too little") as info:
        read_image(tmp_path / "map.pgm")
    assert info.value.__cause__ is not None


# --------------------------------------------------------------------------- what still reads
@pytest.mark.parametrize(
    ("data", "shape"),
    [
        (p5(10, 10, bytes([FREE]) * 100), (10, 10)),
        (b"P5\n# CREATOR: map_saver.cpp 0.050 m/pix\n4 3\n255\n" + bytes([FREE]) * 12, (3, 4)),
        (b"P5 4\t3\r\n255\r" + bytes([FREE]) * 12, (3, 4)),  # any whitespace, CR line ends
        (b"P5\n4 #width\n3 #height\n255\n" + bytes([FREE]) * 12, (3, 4)),
        (b"P5\n4 3#\n3\n255\n" + bytes([FREE]) * 132, (33, 4)),  # a comment inside a token: 3#..\n3 is 33
        (p5(2, 2, bytes([0xFF, 0xFE]) * 4, maxval=65535), (2, 2)),
        (p5(2, 2, bytes([0x03, 0xE8]) * 4, maxval=1000), (2, 2)),
        (p5(3, 1, bytes([100, 100, 100]), maxval=100), (1, 3)),
        (p2(3, 2, [FREE] * 6), (2, 3)),
        (b"P2\n3 2\n255\n254 254 # a comment 1 2 3\n254\n254 254 254", (2, 3)),
        (b"P1\n3 2\n000\n0 0 0\n", (2, 3)),
        (b"P4\n10 2\n" + bytes(4), (2, 10)),
        (p5(2, 2, bytes([FREE]) * 12, magic=b"P6"), (2, 2)),
    ],
    ids=["p5", "comment", "whitespace", "comments-between", "comment-in-token", "16-bit", "maxval-1000", "maxval-100",
         "p2", "p2-comment", "p1", "p4", "p6"],
)  # fmt: skip
def test_well_formed_files_still_load(tmp_path: Path, data: bytes, shape: tuple[int, int]) -> None:
    path = tmp_path / "map.pgm"
    path.write_bytes(data)
    assert load_map(path).grid.shape == shape


def test_real_maps_pass_the_limits(real_maps: Path) -> None:
    images = sorted(p for p in real_maps.rglob("*") if p.suffix in (".pgm", ".png") and "dungeon" not in p.parts)
    images += sorted((real_maps / "dungeon").rglob("*.png"))[:3]
    assert len(images) >= 10
    largest = 0
    for path in images:
        image = read_image(path)
        largest = max(largest, image.shape[0] * image.shape[1])
        header = read_netpbm_header(path)
        if header is not None:
            assert (header.height, header.width) == image.shape
    assert largest == 1985 * 1536  # ipa_plant, the largest map the package ships
    assert largest * 5 < MAX_MAP_PIXELS  # the limit keeps a margin over every real map


# --------------------------------------------------------------------------- absurd sizes
def png_header(width: int, height: int) -> bytes:
    """A PNG with a valid IHDR claiming ``width`` x ``height`` and (almost) no pixel data."""

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    ihdr = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(b"")) + chunk(b"IEND", b"")


@pytest.mark.parametrize(
    ("name", "data", "needle"),
    [
        ("huge.pgm", p5(100_000, 100_000, b""), "100000 x 100000 pixels"),
        ("wide.pgm", p5(MAX_MAP_PIXELS + 1, 1, b""), f"{MAX_MAP_PIXELS + 1} x 1 pixels"),
        ("plain.pgm", b"P2\n50000 50000\n255\n1 2 3\n", "50000 x 50000 pixels"),
        ("huge.png", png_header(100_000, 100_000), "10000000000 pixels"),  # past Pillow's own bomb limit
        ("big.png", png_header(10_000, 10_000), "10000 x 10000 pixels"),  # past Pillow's warning
        ("over.png", png_header(4097, 4096), "4097 x 4096 pixels"),  # just past ours
        ("tall.png", png_header(1, MAX_MAP_PIXELS + 1), f"1 x {MAX_MAP_PIXELS + 1} pixels"),
    ],
)
def test_absurd_sizes_are_refused_before_decoding(tmp_path: Path, name: str, data: bytes, needle: str) -> None:
    message = refused(tmp_path, data, name)
    assert needle in message and f"at most {MAX_MAP_PIXELS}" in message, message


def test_a_map_at_the_limit_is_read(tmp_path: Path) -> None:
    path = tmp_path / "limit.pgm"
    side = int(np.sqrt(MAX_MAP_PIXELS))
    path.write_bytes(p5(side, side, bytes([FREE]) * (side * side)))
    assert read_image(path).shape == (side, side)


def test_a_huge_sparse_file_is_refused_without_reading_it(tmp_path: Path) -> None:
    path = tmp_path / "sparse.pgm"
    path.write_bytes(p5(100, 100, b""))
    with path.open("r+b") as stream:
        stream.truncate(8 << 30)  # 8 GiB of zeros after a header announcing 10 000 bytes
    start = time.perf_counter()
    with pytest.raises(MapError, match=rf"too much pixel data: .* 100 x 100 .* holds {(8 << 30) - 15} bytes"):
        load_map(path)
    assert time.perf_counter() - start < 5
