"""A training run's validation log (``validation.csv``): at each validation, the decisions the
policy had trained on, the mean exploration time of the validation episodes and each one's time.
Written by :class:`~frontier_rl.rl.callbacks.ValidationCallback`; read to resume a run (its best so
far) and to draw its learning curve."""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

from frontier_rl.atomic_write import describe_os_error
from frontier_rl.errors import ConfigError, short_repr

VALIDATION_FILE = "validation.csv"
"""The log's name in a run's folder."""

_COLUMNS = ("timesteps", "mean_time_s", "times")


@dataclass(frozen=True)
class Validation:
    """One validation.

    Attributes:
        timesteps: the decisions the policy had trained on.
        mean_time_s: the validation episodes' mean exploration time (s; written to the millisecond).
        times_s: each episode's exploration time (s; written to a tenth).
    """

    timesteps: int
    mean_time_s: float
    times_s: tuple[float, ...]


def append_validation(path: Path, validation: Validation) -> None:
    """Append ``validation`` to the log at ``path`` (with the header, for a new log)."""
    new = not path.exists()
    with path.open("a", newline="") as sink:
        writer = csv.writer(sink)
        if new:
            writer.writerow(_COLUMNS)
        times = " ".join(f"{t:.1f}" for t in validation.times_s)
        writer.writerow([validation.timesteps, f"{validation.mean_time_s:.3f}", times])


def read_validations(path: Path) -> list[Validation]:
    """The validations of the log at ``path``, in order; none where there is no log.

    Raises:
        ConfigError: a log that cannot be read, or a line of it that is no validation, named.
    """
    if not path.exists():
        return []
    try:
        with path.open(newline="") as source:
            rows = list(csv.DictReader(source))
    except OSError as exc:
        raise ConfigError(f"{path}: cannot be read ({describe_os_error(exc)})") from None
    except (UnicodeDecodeError, csv.Error) as exc:
        raise ConfigError(f"{path} is not a validation log ({exc})") from None
    validations = []
    for number, row in enumerate(rows, start=2):  # line 1 is the header
        try:
            times = tuple(float(t) for t in row["times"].split())
            validations.append(Validation(int(row["timesteps"]), float(row["mean_time_s"]), times))
        except (KeyError, TypeError, ValueError, AttributeError):
            raise ConfigError(f"{path} line {number} is not a validation: {short_repr(row)}") from None
    return validations
