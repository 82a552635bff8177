"""The learning curve of a run: exploration time per training episode and on validation worlds."""

from __future__ import annotations

import csv
import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from frontier_rl.atomic_write import save_figure_atomic
from frontier_rl.rl.validation_log import VALIDATION_FILE, read_validations

_MONITOR = re.compile(r"monitor_(\d+)\.monitor\.csv$")
"""A monitor file's name (:func:`monitor_prefix` and SB3's suffix), with the segment's start."""

_TIME_KEY = "sim_time_s"
"""The entry of the env's step ``info`` with the episode's exploration time (s), which the curve reads."""

MONITOR_KEYWORDS = (_TIME_KEY, "coverage")
"""The entries of the env's step ``info`` the monitor writes for each training episode."""


def monitor_prefix(start: int) -> str:
    """The name SB3's monitor writes the episodes of a run's segment started at ``start`` decisions
    under (it appends ``.monitor.csv``; :func:`training_episodes` reads them)."""
    return f"monitor_{start}"


def training_episodes(run: Path) -> tuple[np.ndarray, np.ndarray]:
    """(end step, exploration time (s)) of every training episode in ``run``'s monitor files; of a
    resumed run, the episodes after the checkpoint it resumed from are taken from the newer file."""
    segments = []
    for path in run.glob("monitor_*.monitor.csv"):
        match = _MONITOR.search(path.name)
        if match:
            segments.append((int(match.group(1)), path))
    segments.sort()
    steps: list[float] = []
    times: list[float] = []
    for i, (start, path) in enumerate(segments):
        limit = segments[i + 1][0] if i + 1 < len(segments) else float("inf")
        lines = [line for line in path.read_text().splitlines() if not line.startswith("#")]
        done = float(start)
        for row in csv.DictReader(lines):
            done += float(row["l"])  # per env; only the order of episodes matters for the curve
            if done > limit:
                break
            steps.append(done)
            times.append(float(row[_TIME_KEY]))
    return np.asarray(steps), np.asarray(times)


def plot_learning_curve(run: Path, title: str = "") -> Path:
    """Write ``run/learning_curve.png``: training episodes (raw and a running mean) and the
    validation mean, as exploration time against training decisions."""
    steps, times = training_episodes(run)
    fig, ax = plt.subplots(figsize=(7, 4), dpi=110)
    if len(times):
        ax.scatter(steps, times, s=4, alpha=0.25, color="tab:blue", label="training episode")
        window = max(1, min(50, len(times) // 5))
        smooth = np.convolve(times, np.ones(window) / window, mode="valid")
        ax.plot(steps[window - 1 :], smooth, color="tab:blue", label=f"running mean of {window}")
    if validations := read_validations(run / VALIDATION_FILE):
        ax.plot(
            [v.timesteps for v in validations],
            [v.mean_time_s for v in validations],
            "o-",
            color="tab:red",
            label="validation worlds (deterministic)",
        )
    ax.set_xlabel("training decisions (env steps)")
    ax.set_ylabel("exploration time (s, simulated)")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    if ax.has_data():
        ax.legend(loc="upper right")
    fig.tight_layout()
    out = run / "learning_curve.png"
    save_figure_atomic(fig, out)
    plt.close(fig)
    return out
