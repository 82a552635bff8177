"""An experiment's folder: its identity, the rows and traces written as episodes finish, resume.

``OUT/experiment.json`` records what the rows depend on (:func:`~frontier_rl.evaluation.running.fingerprints.identity`);
a rerun with a different seed, worlds or settings, or a changed model file under the same method
name, is refused rather than mixed, and the refusal lists each setting that differs with its
value there and now. ``OUT/episodes.csv`` gets one row per finished episode,
``OUT/traces.jsonl`` its coverage curve and weights and ``OUT/checksums.jsonl`` the row's
checksum, each line flushed to disk before the next episode is recorded, so a run killed at any
moment loses at most the episodes still running; a torn last line is cut off on reopening. When
every episode is in, :meth:`ResultStore.finalise` rewrites the three files in job order, so an
interrupted and resumed run ends with the same ``episodes.csv`` and ``traces.jsonl`` as an
uninterrupted one (up to the wall times, and so the checksums).

Row checksums: each line of ``checksums.jsonl`` holds a row's key (method, world, episode), the
SHA-256 of its trace line in ``traces.jsonl`` and the SHA-256 of (the scheme's name
:data:`~frontier_rl.evaluation.results.row_checksums.CHECKSUM_SCHEME`, the experiment id, the method's
fingerprint, the row's CSV line as written, the trace's SHA-256). The experiment id is the SHA-256
of ``experiment.json`` without its methods (seed, worlds with their map hashes, resolution,
simulator and team settings), so a row binds to this experiment's
configuration, its method's model file and its trace. Reopening a folder checks every row: a row
that was edited (a changed time, a renamed method, a changed seed), copied from another
experiment or repeated, a row without a checksum and a trace that was edited are refused with an
error naming the file and line. The checksums detect careless edits and mixed-up files; they are
not a signature (anyone can recompute them). A folder written before row checksums existed (rows,
no ``checksums.jsonl``) is refused with a message asking to rerun into a new folder, or to adopt
its rows as they are with :func:`adopt_rows` where they are trusted.

Writing never destroys what is there: appends that fail (a full disk) are cut back to the
previous end of the file, and rewrites go through a temporary file renamed into place
(:mod:`frontier_rl.atomic_write`); either raises
:class:`~frontier_rl.atomic_write.OutputWriteError` naming the file.
"""

from __future__ import annotations

import csv
import json
from collections.abc import Mapping
from pathlib import Path
from typing import IO

try:
    import fcntl
except ImportError:  # pragma: no cover - not POSIX
    fcntl = None  # type: ignore[assignment]

from frontier_rl.atomic_write import write_text_atomic
from frontier_rl.errors import ConfigError, short_repr, short_text
from frontier_rl.evaluation.results.episode_record import (
    ROW_COLUMNS,
    EpisodeKey,
    EpisodeOutcome,
    EpisodeRow,
    EpisodeTrace,
)
from frontier_rl.evaluation.results.files import (
    KeyedLine,
    append_synced,
    complete_lines,
    cut_torn_line,
    decode_utf8,
    keyed_lines,
    read_result_file,
)
from frontier_rl.evaluation.results.identity import ExperimentIdentity, merged_identity
from frontier_rl.evaluation.results.row_checksums import RowChecksum, row_checksum, sha256_hex
from frontier_rl.evaluation.running.experiment import EpisodeJob
from frontier_rl.run_folders import RunKind, refuse_other_runs

_QUOTE_CHARS = 60
"""Values from files are quoted in messages up to this many characters."""

_MAX_DEPTH = 32
"""``experiment.json`` nests no deeper than this (the simulator's settings nest 3 levels)."""


class ResultStore:
    """The result files of one experiment folder.

    Args:
        out: the folder (created if missing).
        identity: what the experiment's rows depend on; refused if the folder holds another.
        adopt_unchecked: in a folder written before row checksums (no ``checksums.jsonl``),
            take its rows as they are and write their checksums (see :func:`adopt_rows`).

    Raises:
        ConfigError: the folder holds another experiment, another run holds it, or its files
            were edited or damaged (the message names the file and line).
        OutputWriteError: ``experiment.json`` could not be written.
    """

    def __init__(self, out: Path, identity: ExperimentIdentity, *, adopt_unchecked: bool = False) -> None:
        self.out = Path(out)
        if self.out.exists() and not self.out.is_dir():
            raise ConfigError(f"--out {str(self.out)!r} is a file, not a folder")
        refuse_other_runs(self.out, RunKind.EVALUATION)
        self.out.mkdir(parents=True, exist_ok=True)
        self.csv_path = self.out / "episodes.csv"
        self.trace_path = self.out / "traces.jsonl"
        self.checksum_path = self.out / "checksums.jsonl"
        self.identity_path = self.out / "experiment.json"
        self._lock = self._acquire_lock()
        self.rows: dict[EpisodeKey, EpisodeRow] = {}
        self._row_lines: dict[EpisodeKey, str] = {}
        self.traces: dict[EpisodeKey, EpisodeTrace] = {}
        self._trace_lines: dict[EpisodeKey, str] = {}
        self._checksum_lines: dict[EpisodeKey, str] = {}
        self.identity = identity
        self.experiment_id = identity.experiment_id
        try:
            csv_lines = complete_lines(self.csv_path)  # read once: the identity's check and the rows need it
            self._check_identity(identity, csv_lines)
            self._load(csv_lines, adopt_unchecked)
            for path in (self.csv_path, self.trace_path, self.checksum_path):
                cut_torn_line(path)
            # written once the rows are checked: a refused folder keeps its experiment.json as it was
            write_text_atomic(self.identity_path, json.dumps(self.identity.to_json(), indent=1) + "\n")
        except BaseException:
            self.close()
            raise

    @staticmethod
    def _methods_with_rows(csv_lines: list[tuple[int, str]]) -> set[str]:
        """The methods of the rows of ``episodes.csv`` (its numbered lines; each row read and
        checked by :meth:`_load`)."""
        column = ROW_COLUMNS.index("method")
        rows = csv.reader(line for _, line in csv_lines[1:])  # the first: the header
        return {row[column] for row in rows if len(row) > column}

    def _acquire_lock(self) -> IO[bytes] | None:
        """An exclusive lock on the folder for this store's lifetime: two runs appending to the
        same files would interleave their rows."""
        if fcntl is None:  # no POSIX locks here (Windows): run one experiment per folder at a time
            return None
        lock = self.out / ".lock"
        if lock.exists() and not lock.is_file():  # opening a FIFO to write waits for a reader for good
            raise ConfigError(f"{lock} is not a regular file (a FIFO, a device or a folder); choose another --out")
        handle = lock.open("ab")
        try:
            fcntl.flock(handle.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            handle.close()
            raise ConfigError(
                f"another run is writing to --out {str(self.out)!r}; wait for it or choose another"
            ) from None
        return handle

    def close(self) -> None:
        """Release the folder's lock (also released when the process ends)."""
        if self._lock is not None:
            self._lock.close()
            self._lock = None

    # ------------------------------------------------------------------ identity
    def _check_identity(self, identity: ExperimentIdentity, csv_lines: list[tuple[int, str]]) -> None:
        if self.identity_path.exists():
            try:
                stored = read_identity_json(self.identity_path)
            except ConfigError as problem:
                raise ConfigError(f"{problem}; choose another --out") from None
            identity = merged_identity(self.out, stored, identity, self._methods_with_rows(csv_lines))
        elif any(not _ours(path.name) for path in self.out.iterdir()):
            raise ConfigError(f"--out {str(self.out)!r} holds other files and no experiment.json: choose another --out")
        self.identity = identity
        self.experiment_id = identity.experiment_id

    # ------------------------------------------------------------------ reading
    def _load(self, lines: list[tuple[int, str]], adopt_unchecked: bool = False) -> None:
        if lines and lines[0][1] != ",".join(ROW_COLUMNS):
            raise ConfigError(
                f"{self.csv_path} has the columns of another version of frontier_rl; choose another --out"
            )
        row_numbers: dict[EpisodeKey, int] = {}
        for number, line in lines[1:]:  # the first is the header
            try:
                row = EpisodeRow.from_csv_line(line)
            except ConfigError as exc:
                raise ConfigError(f"{self.csv_path} line {number}: {exc}; {_FIX_ROW}") from None
            key = row.key
            if key in row_numbers:
                raise ConfigError(
                    f"{self.csv_path} line {number} repeats the episode of line {row_numbers[key]} "
                    f"({_describe(key)}); {_FIX_ROW}"
                )
            row_numbers[key] = number
            self.rows[key] = row
            self._row_lines[key] = line
        traces = keyed_lines(self.trace_path, "a trace", _as_read)
        checksums = keyed_lines(self.checksum_path, "a row checksum", RowChecksum.from_json)
        if self.rows and not self.checksum_path.exists():
            if adopt_unchecked:
                checksums = self._adopt(row_numbers, traces)
            else:
                raise ConfigError(
                    f"{self.csv_path} holds {len(self.rows)} episodes but {self.checksum_path.name} is missing: the "
                    "folder was written by a frontier_rl without row checksums (or the file was deleted), so its "
                    "rows cannot be checked; choose another --out and run the experiment again (or, if you trust "
                    "these rows, adopt them once with frontier_rl.evaluation.results.store.adopt_rows)"
                )
        for key in self.rows:
            self._verify(key, row_numbers[key], traces.get(key), checksums.get(key))
            try:
                self.traces[key] = EpisodeTrace.from_json(traces[key].entry)
            except ConfigError as problem:  # signed, so written by a run or re-signed after an edit (anyone can)
                raise ConfigError(
                    f"{self.trace_path} line {traces[key].number} (the trace of {_describe(key)}): {problem}; delete "
                    f"the episode's line in {self.csv_path.name} to run it again, or choose another --out"
                ) from None
            self._trace_lines[key] = traces[key].line
            self._checksum_lines[key] = checksums[key].line

    def _adopt(
        self, row_numbers: dict[EpisodeKey, int], traces: dict[EpisodeKey, KeyedLine[Mapping[str, object]]]
    ) -> dict[EpisodeKey, KeyedLine[RowChecksum]]:
        """Write ``checksums.jsonl`` for the rows as they are (each needs a method of this
        experiment and a trace); returns the entries as :meth:`_load` reads them."""
        entries: dict[EpisodeKey, KeyedLine[RowChecksum]] = {}
        for number, key in enumerate(self.rows, start=1):
            fingerprint = self.identity.methods.get(key.method)
            if fingerprint is None or key not in traces:
                what = "is not a method of this experiment" if fingerprint is None else "has no trace"
                raise ConfigError(f"{self.csv_path} line {row_numbers[key]} ({_describe(key)}) {what}; {_FIX_ROW}")
            checksum = RowChecksum.of(self.experiment_id, fingerprint, key, self._row_lines[key], traces[key].line)
            entries[key] = KeyedLine(number, checksum.line(), checksum)
        write_text_atomic(self.checksum_path, "".join(entry.line + "\n" for entry in entries.values()))
        return entries

    def _verify(
        self,
        key: EpisodeKey,
        number: int,
        trace: KeyedLine[Mapping[str, object]] | None,
        checksum: KeyedLine[RowChecksum] | None,
    ) -> None:
        """Refuse the row at line ``number`` unless its checksum and its trace's match."""
        where = f"{self.csv_path} line {number} ({_describe(key)})"
        fingerprint = self.identity.methods.get(key.method)
        if fingerprint is None:
            raise ConfigError(
                f"{where}: {short_repr(key.method)} is not a method of this experiment ({self.identity_path.name}); "
                f"the row was edited or copied from another experiment; {_FIX_ROW}"
            )
        if checksum is None:
            raise ConfigError(
                f"{where} has no checksum in {self.checksum_path.name}: the row was edited or copied from another "
                f"experiment; {_FIX_ROW}"
            )
        entry = checksum.entry
        expected = row_checksum(self.experiment_id, fingerprint, self._row_lines[key], entry.trace_sha256)
        if entry.row_sha256 != expected:
            raise ConfigError(
                f"{where} does not match its checksum ({self.checksum_path.name} line {checksum.number}): the row was "
                f"edited or copied from another experiment; {_FIX_ROW}"
            )
        if trace is None:
            raise ConfigError(f"{where} has no trace in {self.trace_path.name}; {_FIX_ROW}")
        if sha256_hex(trace.line) != entry.trace_sha256:
            raise ConfigError(
                f"{self.trace_path} line {trace.number} (the trace of {_describe(key)}) does not match its checksum: "
                f"it was edited or copied from another experiment; delete it and line {number} of "
                f"{self.csv_path.name} to run that episode again, or choose another --out"
            )

    def done(self, job: EpisodeJob) -> bool:
        """Whether ``job``'s row is already recorded."""
        return job.key in self.rows

    # ------------------------------------------------------------------ writing
    def record(self, outcome: EpisodeOutcome) -> None:
        """Append one finished episode (``run_job``'s outcome): the trace, the checksum, then the
        row, each synced; a kill between them leaves an episode that is simply run again.

        Raises:
            OutputWriteError: a file could not be appended to (cut back to its previous end).
        """
        row, trace = outcome.row, outcome.trace
        key = row.key
        fingerprint = self.identity.methods.get(row.method)
        if fingerprint is None:
            raise ConfigError(f"method {short_repr(row.method)} is not in {self.identity_path}")
        trace_line = json.dumps(trace.to_json(), separators=(",", ":"))
        row_line = row.csv_line()
        checksum_line = RowChecksum.of(self.experiment_id, fingerprint, key, row_line, trace_line).line()
        append_synced(self.trace_path, trace_line + "\n")
        append_synced(self.checksum_path, checksum_line + "\n")
        if not self.csv_path.exists() or self.csv_path.stat().st_size == 0:
            append_synced(self.csv_path, ",".join(ROW_COLUMNS) + "\n")
        append_synced(self.csv_path, row_line + "\n")
        self.rows[key] = EpisodeRow.from_csv_line(row_line)  # as a resumed run reads it back
        self._row_lines[key] = row_line
        self.traces[key] = trace
        self._trace_lines[key] = trace_line
        self._checksum_lines[key] = checksum_line

    def finalise(self, jobs: list[EpisodeJob]) -> None:
        """Rewrite the three files in job order (rows of other jobs after them, in their order),
        once every job is recorded; traces and checksums of episodes without a row are dropped.
        Each file is replaced atomically, so a kill or a full disk meanwhile leaves the old one.

        Raises:
            OutputWriteError: a file could not be written (it is unchanged).
        """
        order = {job.key: i for i, job in enumerate(jobs)}
        keys = sorted(self._row_lines, key=lambda k: (order.get(k, len(order)), k))
        self.traces = {k: self.traces[k] for k in keys if k in self.traces}
        lines = [",".join(ROW_COLUMNS), *(self._row_lines[k] for k in keys)]
        write_text_atomic(self.checksum_path, "".join(self._checksum_lines[k] + "\n" for k in keys))
        write_text_atomic(self.trace_path, "".join(self._trace_lines[k] + "\n" for k in keys))
        write_text_atomic(self.csv_path, "\n".join(lines) + "\n")


def adopt_rows(out: Path) -> int:
    """Write ``checksums.jsonl`` for a results folder written before row checksums existed, taking
    its rows and traces as they are (only for rows you trust: nothing can check them now); from
    then on they are checked like any other. Returns how many rows were adopted.

    Raises:
        ConfigError: ``out`` has no readable experiment.json, already has checksums, or a row
            that does not parse, repeats another or has no trace.
    """
    out = Path(out)
    if (out / "checksums.jsonl").exists():
        raise ConfigError(f"{out / 'checksums.jsonl'} exists: the rows of {str(out)!r} are checked already")
    path = out / "experiment.json"
    if not path.is_file():
        raise ConfigError(f"{str(out)!r} has no experiment.json: it is not a results folder")
    store = ResultStore(out, ExperimentIdentity.from_json(read_identity_json(path)), adopt_unchecked=True)
    store.close()
    return len(store.rows)


# ---------------------------------------------------------------------- files
_FIX_ROW = "delete that line to run the episode again, or choose another --out"
_MAX_IDENTITY_BYTES = 16 * 1024 * 1024  # experiment.json: the settings and one fingerprint per method


def _describe(key: EpisodeKey) -> str:
    return f"{_clip(str(key.method))} on {_clip(str(key.world))}, episode {_clip(str(key.episode))}"


def _clip(text: str) -> str:
    return short_text(text, _QUOTE_CHARS)


def _depth(value: object) -> int:
    """How deeply lists and dicts nest in ``value`` (0 for a scalar), without recursion."""
    deepest, stack = 0, [(value, 0)]
    while stack:
        item, level = stack.pop()
        deepest = max(deepest, level)
        if isinstance(item, dict | list) and level <= _MAX_DEPTH:
            stack.extend((child, level + 1) for child in (item.values() if isinstance(item, dict) else item))
    return deepest


def _as_read(key: EpisodeKey, entry: Mapping[str, object]) -> Mapping[str, object]:
    """A trace's line as read (checked against its checksum before it is parsed)."""
    return entry


def read_identity_json(path: Path) -> Mapping[str, object]:
    """The object of the ``experiment.json`` at ``path``, checked to describe an experiment
    (:meth:`ExperimentIdentity.from_json` reads it).

    Raises:
        ConfigError: unreadable, not UTF-8 or too large, not valid JSON, nested too deeply, or not
            an experiment description: named, with the path.
    """
    text = decode_utf8(path, read_result_file(path, _MAX_IDENTITY_BYTES))  # their errors say what is wrong
    try:
        stored = json.loads(text)
    except json.JSONDecodeError as exc:
        raise ConfigError(f"{path} is not valid JSON ({exc.msg} at line {exc.lineno})") from None
    except (RecursionError, ValueError):  # nested too deeply; an integer of more than 4300 digits
        raise ConfigError(f"{path} is not an experiment description (too deeply nested or too long a number)") from None
    if _depth(stored) > _MAX_DEPTH:
        raise ConfigError(f"{path} is not an experiment description (nested more than {_MAX_DEPTH} levels)")
    try:
        ExperimentIdentity.from_json(stored)
    except ValueError as problem:
        raise ConfigError(f"{path} is not an experiment description ({problem})") from None
    return stored  # type: ignore[no-any-return]  # from_json read it: an object


def _ours(name: str) -> bool:
    """Files the store itself leaves in a folder before experiment.json: the lock and the
    temporary file of a write that was killed."""
    return name == ".lock" or (name.startswith(".") and name.endswith(".tmp"))
