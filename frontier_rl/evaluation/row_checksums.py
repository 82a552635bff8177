"""An episode's row as a line of ``episodes.csv``, and the checksums that bind it to its
experiment, method and trace (see :mod:`frontier_rl.evaluation.results` for how they are used)."""

from __future__ import annotations

import csv
import hashlib
import io
import json
from typing import Any

from frontier_rl.errors import ConfigError, short_repr
from frontier_rl.evaluation.experiment import ROW_COLUMNS

Key = tuple[str, str, int]
"""A row's identity: (method, world, episode)."""

_INT_COLUMNS = ("episode", "seed", "decisions", "aborts", "robots")
_BOOL_COLUMNS = ("done", "truncated")
_TEXT_COLUMNS = ("method", "world")
_OPTIONAL_TEXT_COLUMNS = ("end_reason",)  # an empty field is None

MAX_MAGNITUDE = 1e12
"""Largest magnitude of a number in a row or a trace (s, m, ...): 30,000 years of sim time. Anyone
can re-sign an edited row, and a time of 1e308 s or NaN broke the report's plots."""
_TRACE_CURVES = (("coverage_t", "coverage", 1), ("weight_t", "weight", 0))  # times, values, least length
_TEAM_LISTS = ("robot_path_lengths_m", "robot_coverage", "failed_at_s")

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


def format_row(row: dict[str, Any]) -> str:
    """One CSV line (no newline) of ``row``'s :data:`ROW_COLUMNS`; None is an empty field."""
    buffer = io.StringIO()
    csv.writer(buffer, lineterminator="").writerow(["" if row[c] is None else row[c] for c in ROW_COLUMNS])
    return buffer.getvalue()


def parse_row(line: str) -> dict[str, Any]:
    """A row from one CSV line, with its numbers and booleans typed (an empty field is None).

    Raises:
        ConfigError: the line is not a row (wrong field count, a value of the wrong kind).
    """
    try:
        values = next(csv.reader([line]), [])
    except csv.Error as exc:
        raise ConfigError(f"not a CSV row ({exc})") from None
    if len(values) != len(ROW_COLUMNS):
        raise ConfigError(f"a row has {len(values)} fields, expected {len(ROW_COLUMNS)}: {short_repr(line)}")
    row: dict[str, Any] = {}
    for column, text in zip(ROW_COLUMNS, values, strict=True):
        try:
            if column in _TEXT_COLUMNS:
                row[column] = text
            elif text == "":
                row[column] = None
            elif column in _INT_COLUMNS:
                row[column] = int(text)
            elif column in _BOOL_COLUMNS:
                row[column] = {"True": True, "False": False}[text]
            elif column in _OPTIONAL_TEXT_COLUMNS:
                row[column] = text
            else:
                row[column] = float(text)
                if not _is_number(row[column]):
                    raise ValueError
        except (ValueError, KeyError):
            kind = (
                "an integer"
                if column in _INT_COLUMNS
                else "True or False"
                if column in _BOOL_COLUMNS
                else f"a finite number within +-{MAX_MAGNITUDE:g}"
            )
            raise ConfigError(f"{column} {short_repr(text)} is not valid (expected {kind})") from None
    return row


def _is_number(value: object, none: bool = False) -> bool:
    """A finite int or float within :data:`MAX_MAGNITUDE` (or None, when ``none``)."""
    if value is None:
        return none
    return isinstance(value, int | float) and not isinstance(value, bool) and abs(value) <= MAX_MAGNITUDE


def trace_problem(trace: dict[str, Any]) -> str:
    """What keeps ``trace`` (a line of ``traces.jsonl``) from the report, or "" if nothing: its
    curves (coverage and weight over time) must be lists of one length, the coverage curve not
    empty, and every number finite (a team's failure times may be null)."""
    for times, values, least in _TRACE_CURVES:
        t, v = trace.get(times), trace.get(values)
        if not (isinstance(t, list) and isinstance(v, list) and len(t) == len(v) >= least):
            return f"{times} and {values} must be lists of one length" + (", not empty" if least else "")
        if not all(_is_number(x) for x in (*t, *v)):
            return f"{times} and {values} must hold finite numbers within +-{MAX_MAGNITUDE:g}"
    for name in _TEAM_LISTS:
        items = trace.get(name, [])
        if not (isinstance(items, list) and all(_is_number(x, none=name == "failed_at_s") for x in items)):
            return f"{name} must be a list of finite numbers"
    return ""


def sha256_hex(text: str) -> str:
    return hashlib.sha256(text.encode("utf-8")).hexdigest()
