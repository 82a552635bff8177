"""The committed data of the results pages (``docs/results/data/STUDY/``), read for the generator.

Each study folder holds ``study.json`` (the commands, their wall times, the commit and the machine;
written by ``experiments/studies.py``), one or more ``summary.json`` files of ``frontier-rl
evaluate`` and the ``episodes.csv`` beside each, cut to a few columns.
"""

from __future__ import annotations

import csv
import json
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

from frontier_rl.evaluation.results.summary import ExperimentSummary

DATA = Path(__file__).resolve().parents[1] / "results" / "data"


@dataclass(frozen=True)
class Command:
    """A command a study ran, and its wall time (s; None when not recorded)."""

    command: str
    wall_time_s: float | None


@dataclass(frozen=True)
class Provenance:
    """Where a study's numbers come from.

    Attributes:
        commands: what was run, in order.
        commit: the git commit the run measured.
        changes_not_committed: whether the package or the models differed from that commit.
        cores: the machine's CPU cores.
        cpu: the machine's CPU model.
        python: the Python version.
    """

    commands: tuple[Command, ...]
    commit: str
    changes_not_committed: bool
    cores: int
    cpu: str
    python: str

    @property
    def wall_time_s(self) -> float | None:
        """The commands' total wall time (s), if every one was timed."""
        times = [c.wall_time_s for c in self.commands]
        return None if any(t is None for t in times) else sum(t for t in times if t is not None)


@dataclass(frozen=True)
class Episode:
    """One row of a study's ``episodes.csv`` (times in s, lengths in m, areas in m²)."""

    method: str
    world: str
    episode: int
    sim_time_s: float
    path_length_m: float
    coverage: float
    t90_s: float | None
    decisions: int
    aborts: int
    end_reason: str
    unknown_left_m2: float
    mean_weight: float | None
    robots: int


@dataclass(frozen=True)
class Experiment:
    """One ``frontier-rl evaluate`` folder of a study: its summary and its episodes."""

    summary: ExperimentSummary
    episodes: tuple[Episode, ...]

    def times(self, method: str) -> list[float]:
        """``method``'s exploration times (s), in the experiment's episode order (paired)."""
        return [e.sim_time_s for e in self.episodes if e.method == method]

    def of(self, method: str) -> list[Episode]:
        """``method``'s episodes, in order."""
        return [e for e in self.episodes if e.method == method]


@dataclass(frozen=True)
class Study:
    """A study's data folder."""

    name: str
    provenance: Provenance
    folder: Path

    def experiment(self, part: str = "") -> Experiment:
        """The evaluation in ``part`` (a sub-folder; "" for the study's own folder)."""
        folder = self.folder / part if part else self.folder
        summary = ExperimentSummary.load(folder / "summary.json")
        return Experiment(summary, tuple(_episodes(folder / "episodes.csv")))

    def parts(self) -> list[str]:
        """The sub-folders that hold an evaluation, sorted."""
        return sorted(p.parent.name for p in self.folder.glob("*/summary.json"))

    def json(self, name: str) -> object:
        """Another JSON file of the study."""
        return json.loads((self.folder / name).read_text())


def load_study(name: str, data: Path = DATA) -> Study | None:
    """The study ``name``; None when its data folder has not been collected."""
    folder = data / name
    if not (folder / "study.json").exists():
        return None
    meta = json.loads((folder / "study.json").read_text())
    machine = meta["machine"]
    commands = tuple(Command(c["command"], c["wall_time_s"]) for c in meta["commands"])
    provenance = Provenance(
        commands, meta["commit"], meta["changes_not_committed"], machine["cores"], machine["cpu"], machine["python"]
    )
    return Study(name, provenance, folder)


def _optional(text: str) -> float | None:
    return None if text in ("", "None", "nan") else float(text)


def _episodes(path: Path) -> Iterable[Episode]:
    with path.open(newline="") as handle:
        for row in csv.DictReader(handle):
            yield Episode(
                row["method"],
                row["world"],
                int(row["episode"]),
                float(row["sim_time_s"]),
                float(row["path_length_m"]),
                float(row["coverage"]),
                _optional(row["t90_s"]),
                int(row["decisions"]),
                int(row["aborts"]),
                row["end_reason"],
                float(row["unknown_left_m2"]),
                _optional(row.get("mean_weight", "")),
                int(row.get("robots") or 1),
            )


_MODEL = re.compile(r"^learned:(?:.*/)?model(\d+)(?:/(?:best_)?model)?\.zip$")


def label(method: str) -> str:
    """A method's name on the pages: ``learned:models/model7.zip`` is "model 7"."""
    match = _MODEL.match(method)
    return f"model {match.group(1)}" if match else method


def labels(methods: Sequence[str]) -> dict[str, str]:
    """:func:`label` for each method."""
    return {m: label(m) for m in methods}
