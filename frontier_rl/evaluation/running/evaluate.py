"""``frontier-rl evaluate`` as a function: run what is missing of a paired experiment, then report."""

from __future__ import annotations

import math
import numbers
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np
from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn

from frontier_rl.atomic_write import OutputWriteError
from frontier_rl.errors import ConfigError, short_repr
from frontier_rl.evaluation.report.run_pictures import AnimatedRun, draw_runs
from frontier_rl.evaluation.report.writer import write_report
from frontier_rl.evaluation.results.episode_record import EpisodeOutcome
from frontier_rl.evaluation.results.store import ResultStore
from frontier_rl.evaluation.running.backends import Backend, EpisodeFailedError, RunTarget, run_jobs
from frontier_rl.evaluation.running.experiment import ExperimentConfig
from frontier_rl.evaluation.running.fingerprints import identity
from frontier_rl.evaluation.running.methods import check_methods
from frontier_rl.evaluation.statistics.paired import THESIS_OUTLIERS_S

DEFAULT_OUTLIERS_S = THESIS_OUTLIERS_S
"""The outlier thresholds (s) of an evaluation: the thesis's."""

DEFAULT_PICTURE_WORLDS = 3
"""The report draws each method's first episode on this many worlds (the first ones)."""


def parse_thresholds(text: str) -> tuple[float, ...]:
    """Outlier thresholds from "1000,2000" (s, positive); "" gives none."""
    values = []
    for part in (p.strip() for p in text.split(",")):
        if not part:
            continue
        try:
            values.append(float(part))
        except ValueError:
            raise ConfigError(f"outlier thresholds must be seconds like '1000,2000', got {text!r}") from None
    return checked_thresholds(values, "outlier thresholds")


def checked_thresholds(values: object, what: str = "outliers") -> tuple[float, ...]:
    """Outlier thresholds (s), checked: a list of positive, finite numbers.

    Raises:
        ConfigError: anything else, named with ``what``.
    """
    if isinstance(values, np.ndarray) and values.ndim == 1:
        values = values.tolist()  # NumPy's numbers as Python's
    if isinstance(values, str) or not isinstance(values, Sequence):
        raise ConfigError(f"{what} must be a list of seconds, got {short_repr(values)}")
    for value in values:
        real = isinstance(value, numbers.Real) and not isinstance(value, bool | np.bool_)
        if not real or not 0 < value < math.inf:
            raise ConfigError(f"{what} must be positive numbers of seconds, got {short_repr(value)}")
    return tuple(float(value) for value in values)


def evaluate(
    config: ExperimentConfig,
    out: Path,
    backend: str = "process",
    workers: int | None = None,
    ray_address: str | None = None,
    outliers: tuple[float, ...] = DEFAULT_OUTLIERS_S,
    progress: bool = True,
    command: str = "",
    pictures: int = DEFAULT_PICTURE_WORLDS,
    animate: AnimatedRun | None = None,
) -> Path:
    """Run the episodes of ``config`` not yet in ``out``, then write ``out``'s summary, figures and
    reports; returns the Markdown report's path. Each finished episode is on disk before the next
    is recorded, so an interrupted run resumes where it stopped when called again. The report
    shows the first episode of every method on the first ``pictures`` worlds, drawn again, and
    ``animate`` adds a GIF of that episode.

    Raises:
        ConfigError: bad settings, or ``out`` holds another experiment or edited or damaged rows.
        EpisodeFailedError: episodes raised (every other one is recorded).
        OutputWriteError: a file could not be written (a full disk); the message names it and
            says that the finished episodes are kept.
    """
    target = checked_run(config, backend, workers, ray_address)
    try:
        store = ResultStore(out, identity(config))
    except OutputWriteError as exc:
        raise exc.with_note(f"the results already in {str(out)!r} are unchanged") from None
    try:
        _run_missing(store, config, target, progress)
        store.finalise(config.jobs())
        drawn = draw_runs(config, out, pictures, animate)
        return write_report(store, config, outliers, command, drawn)
    except OutputWriteError as exc:  # a full disk: say what could not be written and what is kept
        raise exc.with_note(
            f"the {len(store.rows)} finished episodes are kept in {str(store.csv_path)!r}; mend that (free some "
            "space, or move what stands in the file's place) and rerun the same command: it resumes and writes "
            "the report"
        ) from None
    finally:
        store.close()


def checked_run(
    config: ExperimentConfig, backend: Backend | str, workers: int | None, ray_address: str | None
) -> RunTarget:
    """Where a run of ``config`` goes (``workers`` None: one per core), checked with its methods (a
    bad method or model file fails before anything is written).

    Raises:
        ConfigError: an unknown backend, a bad worker count, Ray options without Ray, a bad method.
    """
    target = RunTarget.checked(backend, workers, ray_address)
    check_methods(config)
    return target


def _run_missing(store: ResultStore, config: ExperimentConfig, target: RunTarget, progress: bool) -> None:
    """Run the jobs of ``config`` that ``store`` does not hold yet, recording each as it finishes."""
    jobs = config.jobs()
    todo = [job for job in jobs if not store.done(job)]
    with _progress_bar(len(todo), len(jobs) - len(todo), progress) as advance:

        def record(outcome: EpisodeOutcome) -> None:
            store.record(outcome)
            advance()

        try:
            run_jobs(todo, config.settings(), record, target)
        except EpisodeFailedError as exc:
            raise EpisodeFailedError(
                f"{exc}; the {len(store.rows)} finished episodes are saved in {store.csv_path}; "
                "rerun the command to retry the failed ones",
                exc.first_error,
            ) from None


@contextmanager
def _progress_bar(total: int, done_before: int, enabled: bool) -> Iterator[Any]:
    if not enabled or total == 0:
        yield lambda: None
        return
    columns = (TextColumn("episodes"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(), TimeRemainingColumn())
    with Progress(*columns, console=Console(stderr=True)) as bar:
        if done_before:
            bar.console.print(f"{done_before} episodes already in the results folder; running the other {total}")
        task = bar.add_task("episodes", total=total)
        yield lambda: bar.advance(task)
