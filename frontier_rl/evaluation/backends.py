"""Where an experiment's episodes run: in this process, in a process pool, or as Ray tasks.

Every backend calls :func:`~frontier_rl.evaluation.experiment.run_job` with the same arguments,
so the rows are the same whichever ran them (only ``wall_time_s`` is a measurement of the machine).
Results are handed to ``on_result`` as episodes finish, in completion order.
"""

from __future__ import annotations

import multiprocessing
import os
import socket
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from typing import Any

from frontier_rl.errors import ConfigError
from frontier_rl.evaluation.experiment import EpisodeJob, EpisodeSettings, run_job

BACKENDS = ("serial", "process", "ray")
ResultHandler = Callable[[dict[str, Any]], None]


def default_workers() -> int:
    """The cores this process may use."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1


def check_backend(backend: str, workers: int, ray_address: str | None) -> None:
    """A clear error for an unknown backend, a bad worker count or Ray options without Ray."""
    if backend not in BACKENDS:
        raise ConfigError(f"unknown backend {backend!r}; choose one of {', '.join(BACKENDS)}")
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ConfigError(f"--workers must be a positive integer, got {workers!r}")
    if ray_address is not None and backend != "ray":
        raise ConfigError(f"--ray-address {ray_address!r} needs --backend ray")
    if backend == "ray":
        try:
            import ray  # noqa: F401
        except ImportError:
            raise ConfigError("--backend ray needs Ray: pip install 'frontier_rl[ray]'") from None
        if ray_address is not None:
            check_ray_address(ray_address)


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


def run_jobs(
    jobs: list[EpisodeJob],
    settings: EpisodeSettings,
    on_result: ResultHandler,
    backend: str = "process",
    workers: int | None = None,
    ray_address: str | None = None,
) -> None:
    """Run ``jobs`` on ``backend`` with ``workers`` parallel episodes (default: every core)."""
    workers = default_workers() if workers is None else workers
    check_backend(backend, workers, ray_address)
    if not jobs:
        return
    if backend == "serial":
        for job in jobs:
            on_result(run_job(job, settings))
    elif backend == "process":
        for result in _process_pool(jobs, settings, workers):
            on_result(result)
    else:
        for result in _ray_tasks(jobs, settings, workers, ray_address):
            on_result(result)


def _process_pool(jobs: list[EpisodeJob], settings: EpisodeSettings, workers: int) -> Iterator[dict[str, Any]]:
    # spawn: the parent may hold torch's and numba's threads, which fork does not copy safely
    context = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(min(workers, len(jobs)), mp_context=context) as pool:
        pending: set[Future[dict[str, Any]]] = {pool.submit(run_job, job, settings) for job in jobs}
        try:
            while pending:
                finished, pending = wait(pending, return_when=FIRST_COMPLETED)
                for future in finished:
                    yield future.result()
        finally:
            for future in pending:
                future.cancel()


def _ray_tasks(
    jobs: list[EpisodeJob], settings: EpisodeSettings, workers: int, address: str | None
) -> Iterator[dict[str, Any]]:
    import ray

    started_here = not ray.is_initialized()
    if started_here:
        try:
            if address is None:  # a local instance with this many CPUs
                ray.init(num_cpus=workers, include_dashboard=False, log_to_driver=False, configure_logging=False)
            else:
                ray.init(address=address, log_to_driver=False, configure_logging=False)
        except (ConnectionError, RuntimeError) as exc:
            where = address or "a local instance"
            raise ConfigError(f"Ray could not start or reach {where}: {str(exc).splitlines()[0]}") from None
    try:
        remote_job = ray.remote(num_cpus=1, max_retries=2)(run_job)
        settings_ref = ray.put(settings)
        pending = [remote_job.remote(job, settings_ref) for job in jobs]
        while pending:
            finished, pending = ray.wait(pending, num_returns=1)
            for ref in finished:
                yield ray.get(ref)
    finally:
        if started_here:
            ray.shutdown()
