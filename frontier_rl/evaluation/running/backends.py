"""Where an experiment's episodes run: in this process, in a process pool, or as Ray tasks.

Every backend calls :func:`~frontier_rl.evaluation.running.experiment.run_job` with the same arguments,
so the rows are the same whichever ran them (only ``wall_time_s`` is a measurement of the machine).
Results are handed to ``on_result`` as episodes finish, in completion order.
"""

from __future__ import annotations

import contextlib
import os
import socket
import sys
import warnings
from collections.abc import Callable, Generator
from dataclasses import dataclass
from enum import StrEnum
from typing import Any

from frontier_rl.checked_values import enum_member
from frontier_rl.errors import ConfigError, FrontierRLError, MapWarning, caused_by_interrupt
from frontier_rl.evaluation.results.episode_record import EpisodeOutcome
from frontier_rl.evaluation.running.experiment import EpisodeJob, EpisodeSettings, run_job
from frontier_rl.evaluation.running.worker_pool import WorkerPool


class Backend(StrEnum):
    """Where an experiment's episodes run."""

    SERIAL = "serial"  # one after another, in this process
    PROCESS = "process"  # a pool of processes on this machine
    RAY = "ray"  # Ray tasks, on this machine or a Ray cluster


ResultHandler = Callable[[EpisodeOutcome], None]
Outcomes = Generator[tuple[EpisodeJob, Any], None, None]
"""Each episode with its row, or the exception it raised, as episodes finish."""
Caught = list[tuple[str, str, str]]
"""Warnings an episode raised in another process: (category's module, category's name, message).
The category travels by name, not pickled: a user policy's own category may not unpickle here."""


MAX_WORKERS = 256
"""Most parallel episodes: each is a process with a world, a map and perhaps a model (an office
episode peaks at 0.2 GB with ``nearest``, 0.5 GB with model 7)."""


def default_workers() -> int:
    """The cores this process may use (at most :data:`MAX_WORKERS`)."""
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1
    return min(cores, MAX_WORKERS)


def check_workers(workers: int | None) -> None:
    """A clear error for a worker count that is not a positive integer or is more than
    :data:`MAX_WORKERS` (None: every core, :func:`default_workers`)."""
    if workers is None:
        return
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ConfigError(f"--workers must be a positive integer, got {workers!r}")
    if workers > MAX_WORKERS:
        raise ConfigError(f"--workers must be at most {MAX_WORKERS} (a process each), got {workers!r}")


def check_backend(backend: Backend | str, workers: int, ray_address: str | None) -> Backend:
    """The backend named ``backend``; a clear error for an unknown one, a bad worker count or Ray
    options without Ray."""
    chosen = enum_member(Backend, backend, "--backend")
    check_workers(workers)
    if ray_address is not None and chosen is not Backend.RAY:
        raise ConfigError(f"--ray-address {ray_address!r} needs --backend ray")
    if chosen is Backend.RAY:
        try:
            import ray  # noqa: F401
        except ImportError:
            raise ConfigError("--backend ray needs Ray: pip install 'frontier_rl[ray]'") from None
        if ray_address is not None:
            check_ray_address(ray_address)
    return chosen


@dataclass(frozen=True)
class RunTarget:
    """Where an experiment's episodes run, checked (:meth:`checked`).

    Attributes:
        backend: in this process, a process pool or Ray tasks.
        workers: parallel episodes (processes or Ray tasks).
        ray_address: the Ray head (host:port) of :attr:`Backend.RAY`; None: a local Ray.
    """

    backend: Backend
    workers: int
    ray_address: str | None = None

    @classmethod
    def checked(cls, backend: Backend | str, workers: int | None, ray_address: str | None = None) -> RunTarget:
        """The target the options name (``workers`` None: one per core); a clear error for an unknown
        backend, a bad worker count, Ray options without Ray, or a Ray head that does not answer."""
        workers = default_workers() if workers is None else workers
        return cls(check_backend(backend, workers, ray_address), workers, ray_address)


def check_ray_address(address: str, timeout_s: float = 5.0) -> None:
    """Fail fast when a Ray head does not answer at ``address`` ("host:port" or "ray://host:port";
    "auto" and "local" are left to Ray): Ray itself retries for minutes."""
    if address in ("auto", "local"):
        return
    host, sep, port_text = address.removeprefix("ray://").rpartition(":")
    if not sep or not host or not port_text.isdigit():
        raise ConfigError(f"Ray address must be 'host:port' or 'ray://host:port', got {address!r}")
    try:
        with socket.create_connection((host, int(port_text)), timeout=timeout_s):
            pass
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise ConfigError(f"Ray address {address!r} does not answer ({reason})") from None


class EpisodeFailedError(FrontierRLError):
    """Episodes raised; every other episode ran and was handed on, and a rerun retries these.

    Attributes:
        first_error: what the first failed episode raised (None where not known).
    """

    def __init__(self, message: str, first_error: BaseException | None = None) -> None:
        super().__init__(message)
        self.first_error = first_error


def run_jobs(jobs: list[EpisodeJob], settings: EpisodeSettings, on_result: ResultHandler, target: RunTarget) -> None:
    """Run ``jobs`` where ``target`` says (checked by :meth:`RunTarget.checked`, which probes a Ray
    address: once, by the caller). An episode that raises does not stop the others: once all have
    run, :class:`EpisodeFailedError` names the failures."""
    if not jobs:
        return
    failures: list[tuple[EpisodeJob, BaseException]] = []
    if target.backend is Backend.SERIAL:
        outcomes: Outcomes = _serial(jobs, settings)
    elif target.backend is Backend.PROCESS:
        outcomes = _process_pool(jobs, settings, target.workers)
    else:
        outcomes = _ray_tasks(jobs, settings, target.workers, target.ray_address)
    with contextlib.closing(outcomes):  # an error or Ctrl-C in on_result ends the workers at once
        for job, outcome in outcomes:
            if isinstance(outcome, BaseException):
                failures.append((job, outcome))
            else:
                on_result(outcome)
    if failures:
        job, exc = failures[0]
        lines = [line for line in str(exc).splitlines() if line.strip()]
        raise EpisodeFailedError(
            f"{len(failures)} of {len(jobs)} episodes failed, the first {job.method} on {job.world} episode "
            f"{job.episode} ({type(exc).__name__}: {lines[-1] if lines else ''})",
            exc,
        )


def _serial(jobs: list[EpisodeJob], settings: EpisodeSettings) -> Outcomes:
    for job in jobs:
        try:
            yield job, run_job(job, settings)
        except Exception as exc:  # handed on: the other episodes still run
            if caused_by_interrupt(exc):  # a Ctrl-C numba turned into an error: not the episode's failure
                raise KeyboardInterrupt from None
            yield job, exc


def run_job_catching_warnings(job: EpisodeJob, settings: EpisodeSettings) -> tuple[EpisodeOutcome, Caught]:
    """:func:`run_job` in a worker, with the warnings it raised, to be raised again in the parent
    (:func:`_warn_again`): a worker's stderr is not the command's, so they would go past the
    command line's one-line warnings."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")
        outcome = run_job(job, settings)
    return outcome, [(w.category.__module__, w.category.__qualname__, str(w.message)) for w in caught]


def _warn_again(outcome: tuple[EpisodeOutcome, Caught]) -> EpisodeOutcome:
    """The episode of a worker's outcome, its warnings raised again here in their own category (a
    UserWarning naming it where this process has not loaded it). A map's warnings are not: this
    process read every map of the experiment for its identity before any episode ran, and raised
    them then (a worker names the file by its absolute path, so they would print twice)."""
    episode, caught = outcome
    for module, name, message in caught:
        category = getattr(sys.modules.get(module), name, None)
        if not (isinstance(category, type) and issubclass(category, Warning)):
            category, message = UserWarning, f"{name}: {message}"
        if not issubclass(category, MapWarning):
            warnings.warn(message, category, stacklevel=2)
    return episode


def _process_pool(jobs: list[EpisodeJob], settings: EpisodeSettings, workers: int) -> Outcomes:
    tasks = [(run_job_catching_warnings, (job, settings)) for job in jobs]
    with WorkerPool(min(workers, len(jobs))) as pool, contextlib.closing(pool.imap_unordered(tasks)) as outcomes:
        for index, outcome in outcomes:
            yield jobs[index], outcome if isinstance(outcome, BaseException) else _warn_again(outcome)


def _ray_tasks(jobs: list[EpisodeJob], settings: EpisodeSettings, workers: int, address: str | None) -> Outcomes:
    import ray

    started_here = not ray.is_initialized()
    if started_here:
        try:
            if address is None:  # a local instance with this many CPUs
                ray.init(num_cpus=workers, include_dashboard=False, log_to_driver=False, configure_logging=False)
            else:
                ray.init(address=address, log_to_driver=False, configure_logging=False)
        except Exception as exc:  # Ray's own: a bare Exception when its node does not start within 30 s
            with contextlib.suppress(Exception):
                ray.shutdown()
            where = address or "a local instance"
            lines = str(exc).strip().splitlines()
            raise ConfigError(
                f"Ray could not start or reach {where}: {lines[0] if lines else type(exc).__name__}"
            ) from None
    try:
        remote_job = ray.remote(num_cpus=1, max_retries=2)(run_job_catching_warnings)
        settings_ref = ray.put(settings)
        pending = {remote_job.remote(job, settings_ref): job for job in jobs}
        while pending:
            finished, _ = ray.wait(list(pending), num_returns=1)
            for ref in finished:
                job = pending.pop(ref)
                try:
                    yield job, _warn_again(ray.get(ref))
                except Exception as exc:  # a task's error (RayTaskError): handed on like the others
                    yield job, exc
    finally:
        if started_here:
            ray.shutdown()
