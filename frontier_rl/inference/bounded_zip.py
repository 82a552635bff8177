"""Zip files read with bounds: what a zip's directory declares is checked before any member is read.

A zip is untrusted input: a member that inflates to 16 GiB, a directory that declares a million
entries, or a compression method that :mod:`zipfile` unpacks in unbounded chunks would take the
machine's memory. :func:`open_checked_zip` sizes the central directory from its end record before
:mod:`zipfile` parses it, then refuses members that are too many, too big, too compressed,
duplicated, or neither stored nor deflated; :func:`read_member` reads one member with a size limit.
Every refusal is one :class:`~frontier_rl.errors.ConfigError` line naming the file.
"""

from __future__ import annotations

import io
import struct
import zipfile
from typing import IO

from frontier_rl.errors import ConfigError, short_repr, short_text

MAX_MEMBER_BYTES = 256 * 1024**2
"""Largest zip member, uncompressed (bytes). The largest network the metadata admits
(:data:`~frontier_rl.inference.model_file.MAX_FEATURES_DIM` features) has ~40 MB of weights and an
optimizer state of one to two times that; the shipped ``policy.pth`` files are ~0.75 MB."""

MAX_ARCHIVE_BYTES = 1024**3
"""Largest sum of a zip's members, uncompressed (bytes): the zip of a model file, or the torch
archive inside its ``policy.pth``. The shipped model files hold ~1.6 MB."""

MAX_COMPRESSION_RATIO = 200
"""Most a member over :data:`RATIO_FLOOR_BYTES` may be compressed (uncompressed / compressed).
Weights deflate to ~1.1:1 and SB3's JSON ``data`` to ~12:1; only long runs of one byte (a zip
bomb) go beyond ~200:1 (deflate's limit is ~1030:1)."""

RATIO_FLOOR_BYTES = 1024**2
"""Members up to this size (bytes, uncompressed) are exempt from :data:`MAX_COMPRESSION_RATIO`."""


_STORED_OR_DEFLATED = (zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED)
_END_RECORD = struct.Struct("<4s4H2LH")  # end of central directory: signature ... comment length
_ZIP64_LOCATOR = struct.Struct("<4sLQL")
_ZIP64_END_RECORD = struct.Struct("<4sQ2H2L4Q")


def first_line(exc: BaseException, limit: int = 120) -> str:
    """The first line of an exception's message, cut to ``limit`` characters."""
    lines = [line.strip() for line in str(exc).splitlines() if line.strip()]
    return short_text(lines[0] if lines else type(exc).__name__, limit)


def _directory_size(file: IO[bytes]) -> tuple[int, int] | None:
    """(entries, bytes) of a zip's central directory, from its end record; None where there is no
    end record (then :mod:`zipfile` says the file is not a zip)."""
    file.seek(0, io.SEEK_END)
    size = file.tell()
    tail_start = max(0, size - _END_RECORD.size - 0xFFFF)
    file.seek(tail_start)
    tail = file.read()
    at = tail.rfind(b"PK\x05\x06")
    if at < 0 or len(tail) - at < _END_RECORD.size:
        return None
    *_, entries, directory_bytes, _offset, _comment = _END_RECORD.unpack_from(tail, at)
    if entries != 0xFFFF and directory_bytes != 0xFFFFFFFF:
        return entries, directory_bytes
    locator_at = tail_start + at - _ZIP64_LOCATOR.size
    if locator_at < 0:
        return entries, directory_bytes
    file.seek(locator_at)
    signature, _disk, record_at, _disks = _ZIP64_LOCATOR.unpack(file.read(_ZIP64_LOCATOR.size))
    if signature != b"PK\x06\x07" or record_at > size - _ZIP64_END_RECORD.size:
        return entries, directory_bytes
    file.seek(record_at)
    record = _ZIP64_END_RECORD.unpack(file.read(_ZIP64_END_RECORD.size))
    if record[0] != b"PK\x06\x06":
        return entries, directory_bytes
    return record[7], record[8]


def check_members(archive: zipfile.ZipFile, where: str, max_members: int) -> None:
    """Refuse a zip whose members, as its directory declares them, are too many, too big, too
    compressed, duplicated, or compressed other than stored or deflated; nothing is read."""
    members = archive.infolist()
    if len(members) > max_members:
        raise ConfigError(f"{where} has {len(members)} members, more than the {max_members} allowed")
    names: set[str] = set()
    total = 0
    for member in members:
        name = short_repr(member.filename)
        if member.filename in names:
            raise ConfigError(f"{where} holds member {name} twice")
        names.add(member.filename)
        if member.compress_type not in _STORED_OR_DEFLATED:
            raise ConfigError(
                f"{where}: member {name} uses compression method {member.compress_type}, not stored or deflated"
            )
        if member.file_size > MAX_MEMBER_BYTES:
            raise ConfigError(
                f"{where}: member {name} unpacks to {member.file_size} bytes, more than the {MAX_MEMBER_BYTES} allowed"
            )
        if member.file_size > RATIO_FLOOR_BYTES and member.file_size > MAX_COMPRESSION_RATIO * member.compress_size:
            raise ConfigError(
                f"{where}: member {name} unpacks {member.compress_size} bytes to {member.file_size}, "
                f"more than {MAX_COMPRESSION_RATIO} times (a zip bomb?)"
            )
        total += member.file_size
    if total > MAX_ARCHIVE_BYTES:
        raise ConfigError(f"{where} unpacks to {total} bytes, more than the {MAX_ARCHIVE_BYTES} allowed")


def open_checked_zip(file: IO[bytes], where: str, max_members: int, kind: str) -> zipfile.ZipFile:
    """``file`` as a checked zip (:func:`check_members`); its central directory is sized from the
    end record before :mod:`zipfile` parses it. ``kind`` says what the file should be, in messages."""
    directory = _directory_size(file)
    if directory is not None:
        entries, directory_bytes = directory
        if entries > max_members or directory_bytes > 1024 * max_members:
            raise ConfigError(
                f"{where} declares {entries} members in {directory_bytes} bytes of directory, "
                f"more than the {max_members} allowed"
            )
    file.seek(0)
    try:
        archive = zipfile.ZipFile(file)
    except Exception as exc:  # BadZipFile, or what a malformed directory makes zipfile raise
        raise ConfigError(f"{where} is corrupt or not {kind} ({first_line(exc)})") from None
    try:
        check_members(archive, where, max_members)
    except BaseException:
        archive.close()
        raise
    return archive


def read_member(archive: zipfile.ZipFile, name: str, limit: int, where: str) -> bytes:
    """Member ``name`` of a checked zip, refused if it unpacks to more than ``limit`` bytes."""
    member = archive.getinfo(name)
    if member.file_size > limit:
        raise ConfigError(f"{where}: {name} unpacks to {member.file_size} bytes, more than the {limit} allowed")
    try:
        with archive.open(member) as stream:
            data = stream.read(limit + 1)
    except Exception as exc:  # BadZipFile (CRC), zlib.error, EOFError, encrypted members, ...
        raise ConfigError(f"{where}: {name} is corrupt ({first_line(exc)})") from None
    if len(data) > limit:
        raise ConfigError(f"{where}: {name} unpacks to more than the {limit} bytes allowed")
    return data
