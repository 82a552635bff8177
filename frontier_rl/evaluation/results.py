"""An experiment's folder: its identity, the rows and traces written as episodes finish, resume.

``OUT/experiment.json`` records what the rows depend on (:func:`~frontier_rl.evaluation.experiment.identity`);
a rerun with a different seed, worlds or settings, or a changed model file under the same method
name, is refused rather than mixed. ``OUT/episodes.csv`` gets one row per finished episode and
``OUT/traces.jsonl`` its coverage curve and weights, each line flushed to disk before the next
episode is recorded, so a run killed at any moment loses at most the episodes still running; a
torn last line is cut off on reopening. When every episode is in, :meth:`ResultStore.finalise`
rewrites both files in job order, so an interrupted and resumed run ends with the same files as
an uninterrupted one (up to the wall times).
"""

from __future__ import annotations

import csv
import io
import json
import os
from pathlib import Path
from typing import IO, Any

try:
    import fcntl
except ImportError:  # pragma: no cover - not POSIX
    fcntl = None  # type: ignore[assignment]

from frontier_rl.errors import ConfigError
from frontier_rl.evaluation.experiment import ROW_COLUMNS, EpisodeJob

Key = tuple[str, str, int]
_INT_COLUMNS = ("episode", "seed", "decisions", "aborts", "robots")
_BOOL_COLUMNS = ("done", "truncated")
_TEXT_COLUMNS = ("method", "world")
_OPTIONAL_TEXT_COLUMNS = ("end_reason",)  # an empty field is None


class ResultStore:
    """The result files of one experiment folder.

    Args:
        out: the folder (created if missing).
        identity: what the experiment's rows depend on; refused if the folder holds another.
    """

    def __init__(self, out: Path, identity: dict[str, Any]) -> None:
        self.out = Path(out)
        if self.out.exists() and not self.out.is_dir():
            raise ConfigError(f"--out {str(self.out)!r} is a file, not a folder")
        self.csv_path = self.out / "episodes.csv"
        self.trace_path = self.out / "traces.jsonl"
        self.identity_path = self.out / "experiment.json"
        self._lock = self._acquire_lock()
        self.rows: dict[Key, dict[str, Any]] = {}
        self._row_lines: dict[Key, str] = {}
        self.traces: dict[Key, dict[str, Any]] = {}
        self._trace_lines: dict[Key, str] = {}
        try:
            self._check_identity(identity)
            self._load()
        except BaseException:
            self.close()
            raise

    def _acquire_lock(self) -> IO[bytes] | None:
        """An exclusive lock on the folder for this store's lifetime: two runs appending to the
        same files would interleave their rows."""
        if fcntl is None:  # no POSIX locks here (Windows): run one experiment per folder at a time
            return None
        self.out.mkdir(parents=True, exist_ok=True)
        handle = (self.out / ".lock").open("ab")
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
    def _check_identity(self, identity: dict[str, Any]) -> None:
        identity = json.loads(json.dumps(identity))  # tuples become lists, as in the stored file
        stored: dict[str, Any] | None = None
        if self.identity_path.exists():
            try:
                stored = json.loads(self.identity_path.read_text())
            except json.JSONDecodeError as exc:
                raise ConfigError(f"{self.identity_path} is not valid JSON ({exc.msg}); choose another --out") from None
            if not isinstance(stored, dict) or not isinstance(stored.get("methods", {}), dict):
                raise ConfigError(f"{self.identity_path} is not an experiment description; choose another --out")
        elif any(path.name != ".lock" for path in self.out.iterdir()):
            raise ConfigError(f"--out {str(self.out)!r} holds other files and no experiment.json: choose another --out")
        if stored is not None:
            for part in ("seed", "worlds", "resolution", "sim"):
                if stored.get(part) != identity[part]:
                    raise ConfigError(
                        f"--out {str(self.out)!r} holds results of a different configuration ({part}: "
                        f"{_short(stored.get(part))} there, {_short(identity[part])} now); choose another --out"
                    )
            for method, fingerprint in identity["methods"].items():
                old = stored.get("methods", {}).get(method)
                if old is not None and old != fingerprint:
                    raise ConfigError(
                        f"--out {str(self.out)!r} holds results of {method!r} from a different model file; "
                        "choose another --out or rename the model"
                    )
            identity = {**identity, "methods": {**stored.get("methods", {}), **identity["methods"]}}
        self.out.mkdir(parents=True, exist_ok=True)
        _write_atomic(self.identity_path, json.dumps(identity, indent=1) + "\n")

    # ------------------------------------------------------------------ reading
    def _load(self) -> None:
        lines = _complete_lines(self.csv_path)
        if lines and lines[0] != ",".join(ROW_COLUMNS):
            raise ConfigError(
                f"{self.csv_path} has the columns of another version of frontier_rl; choose another --out"
            )
        for line in lines[1:]:  # the first is the header
            row = parse_row(line)
            key = (row["method"], row["world"], row["episode"])
            self.rows[key] = row
            self._row_lines[key] = line
        for line in _complete_lines(self.trace_path):
            try:
                trace = json.loads(line)
                key = (trace["method"], trace["world"], trace["episode"])
            except (json.JSONDecodeError, TypeError, KeyError):
                raise ConfigError(f"traces.jsonl: a line is not a trace: {line[:80]!r}") from None
            self.traces[key] = trace  # a trace of an episode rerun after a kill: the last one wins
            self._trace_lines[key] = line

    def done(self, job: EpisodeJob) -> bool:
        """Whether ``job``'s row is already recorded."""
        return job.key in self.rows

    # ------------------------------------------------------------------ writing
    def record(self, result: dict[str, Any]) -> None:
        """Append one finished episode (``run_job``'s result): the trace, then the row, each synced."""
        row, trace = result["row"], result["trace"]
        key = (row["method"], row["world"], row["episode"])
        trace_line = json.dumps(trace, separators=(",", ":"))
        row_line = format_row(row)
        _append(self.trace_path, trace_line + "\n")
        if not self.csv_path.exists() or self.csv_path.stat().st_size == 0:
            _append(self.csv_path, ",".join(ROW_COLUMNS) + "\n")
        _append(self.csv_path, row_line + "\n")
        self.rows[key] = parse_row(row_line)
        self._row_lines[key] = row_line
        self.traces[key] = trace
        self._trace_lines[key] = trace_line

    def finalise(self, jobs: list[EpisodeJob]) -> None:
        """Rewrite both files in job order (rows of other jobs after them, in their order), once
        every job is recorded; atomic, so a kill meanwhile leaves the old files."""
        order = {job.key: i for i, job in enumerate(jobs)}
        keys = sorted(self._row_lines, key=lambda k: (order.get(k, len(order)), k))
        lines = [",".join(ROW_COLUMNS), *(self._row_lines[k] for k in keys)]
        _write_atomic(self.csv_path, "\n".join(lines) + "\n")
        trace_keys = [k for k in keys if k in self._trace_lines]
        _write_atomic(self.trace_path, "".join(self._trace_lines[k] + "\n" for k in trace_keys))


def format_row(row: dict[str, Any]) -> str:
    """One CSV line (no newline) of ``row``'s :data:`ROW_COLUMNS`; None is an empty field."""
    buffer = io.StringIO()
    csv.writer(buffer, lineterminator="").writerow(["" if row[c] is None else row[c] for c in ROW_COLUMNS])
    return buffer.getvalue()


def parse_row(line: str) -> dict[str, Any]:
    """A row from one CSV line, with its numbers and booleans typed (an empty field is None)."""
    values = next(csv.reader([line]))
    if len(values) != len(ROW_COLUMNS):
        raise ConfigError(f"episodes.csv: a row has {len(values)} fields, expected {len(ROW_COLUMNS)}: {line[:80]!r}")
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
        except (ValueError, KeyError):
            raise ConfigError(f"episodes.csv: {column} {text!r} is not valid in row {line[:80]!r}") from None
    return row


def _short(value: Any) -> str:
    text = json.dumps(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _complete_lines(path: Path) -> list[str]:
    """The file's complete lines; a torn last line (no newline: the writer was killed) is cut off
    the file, so that the next append starts on a fresh line."""
    if not path.exists():
        return []
    data = path.read_bytes()
    end = data.rfind(b"\n") + 1
    if end < len(data):
        with path.open("r+b") as handle:
            handle.truncate(end)
    return [line for line in data[:end].decode().split("\n") if line.strip()]


def _append(path: Path, text: str) -> None:
    with path.open("a", encoding="utf-8") as handle:
        handle.write(text)
        handle.flush()
        os.fsync(handle.fileno())


def _write_atomic(path: Path, text: str) -> None:
    tmp = path.with_name(path.name + ".tmp")
    with tmp.open("w", encoding="utf-8") as handle:
        handle.write(text)
        handle.flush()
        os.fsync(handle.fileno())
    os.replace(tmp, path)
