"""The studies behind the documentation's results pages: run one, and keep its small summary files.

Each study is one or more commands of the project (``frontier-rl evaluate``, the scripts of
``experiments/``, the speed benchmark). ``run`` executes them into ``results/studies/STUDY/`` (an
evaluation folder resumes where it stopped), then copies the files the results pages read into
``docs/results/data/STUDY/``: ``summary.json`` files, ``episodes.csv`` cut to the columns the pages
use, and ``study.json`` (the commands, their wall time, the commit and the machine). The pages are
generated from those files when the documentation is built (``docs/_ext/results_pages.py``), so a
change of the engine only needs the studies run again:

    .venv/bin/python experiments/studies.py list
    .venv/bin/python experiments/studies.py run thesis office
    .venv/bin/python experiments/studies.py collect thesis      # copy again without running
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import platform
import shlex
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
RUNS = Path("results/studies")
DATA = Path("docs/results/data")

EPISODE_COLUMNS = (
    "method",
    "world",
    "episode",
    "seed",
    "sim_time_s",
    "path_length_m",
    "coverage",
    "free_coverage",
    "t90_s",
    "t99_s",
    "decisions",
    "aborts",
    "end_reason",
    "unknown_left_m2",
    "mean_weight",
    "robots",
)
"""The columns of ``episodes.csv`` kept for the pages (the rest stay in the run folder)."""

FRONTIER_RL = ".venv/bin/frontier-rl"
PYTHON = ".venv/bin/python"


@dataclass(frozen=True)
class Study:
    """One results page's measurements.

    Attributes:
        name: the page's file name and data folder.
        commands: shell commands run from the repository root; ``{out}`` is the study's run folder.
        keep: files of the run folder (glob patterns) copied into the data folder.
    """

    name: str
    commands: tuple[str, ...]
    keep: tuple[str, ...] = ("summary.json", "episodes.csv")


def _teams(out: str, methods: str, robots: str, strategy: str, extra: str = "") -> str:
    return (
        f"{FRONTIER_RL} evaluate --methods {methods} --robots {robots} --strategy {strategy} "
        f"--worlds office,rooms --episodes 20 --no-oracle {extra}--out {out}"
    )


STUDIES: tuple[Study, ...] = (
    Study(
        "thesis",
        (
            f"{FRONTIER_RL} evaluate --methods fixed:0.75,learned:models/model4.zip --worlds office --episodes 120 "
            "--out {out}",
        ),
    ),
    Study(
        "office",
        (
            f"{PYTHON} experiments/weight_sweep.py --methods learned:models/model4.zip,learned:models/model5.zip,"
            "learned:models/model7.zip,tour,nearest,explore-lite,info-gain --worlds office --episodes 100 --out {out}",
        ),
    ),
    Study(
        "families",
        (
            f"{PYTHON} experiments/generalisation.py --methods tour,learned:models/model7.zip --episodes 100 "
            "--maps 100 --building-episodes 24 --out {out}",
        ),
        keep=("generalisation.json", "*/summary.json", "*/episodes.csv"),
    ),
    Study(
        "thesis_models",
        (
            *(
                f"{FRONTIER_RL} train --model {n} --worlds office --timesteps 25000 --n-envs 2 --out {{out}}/model{n}"
                for n in (1, 2, 3)
            ),
            f"{FRONTIER_RL} evaluate --methods learned:{{out}}/model1/model.zip,learned:{{out}}/model2/model.zip,"
            "learned:{out}/model3/model.zip,learned:models/model4.zip,learned:models/model5.zip,"
            "learned:models/model7.zip,fixed:0.75,nearest --worlds office --episodes 30 --out {out}/evaluation",
        ),
        keep=("evaluation/summary.json", "evaluation/episodes.csv", "model*/validation.csv", "model*/config.yaml"),
    ),
    Study(
        "teams",
        (
            _teams("{out}/strategies", "fixed:0.75", "1,2,3,4", "uncoordinated,coordinated,rendezvous"),
            _teams("{out}/policies", "fixed:0.75,nearest,tour,learned:models/model7.zip", "1,2,4", "coordinated"),
            *(
                _teams(f"{{out}}/fail_{s}", "fixed:0.75", "3", s, "--fail 2@82 ")
                for s in ("uncoordinated", "coordinated", "rendezvous")
            ),
        ),
        keep=("*/summary.json", "*/episodes.csv"),
    ),
    Study(
        "real_buildings",
        (
            f"{PYTHON} experiments/real_maps.py --methods nearest,fixed:0.75,tour,learned:models/model7.zip "
            "--out {out}",
        ),
        keep=("*.json", "*/summary.json", "*/episodes.csv"),
    ),
    Study(
        "harder_buildings",
        (f"{PYTHON} experiments/harder_survey.py --out {{out}}",),
        keep=("survey.json", "*/summary.json", "*/episodes.csv", "worst/*.png"),
    ),
    Study("speed", (f"{PYTHON} benchmarks/run.py --json {{out}}/speed.json",), keep=("speed.json",)),
)


def study(name: str) -> Study:
    """The study called ``name``; exits with a one-line error naming the known ones otherwise."""
    for entry in STUDIES:
        if entry.name == name:
            return entry
    raise SystemExit(f"unknown study {name!r}; choose from {', '.join(s.name for s in STUDIES)}")


def run(entry: Study) -> None:
    """Run ``entry``'s commands (each resumes what an earlier run of it finished), then collect."""
    out = RUNS / entry.name  # relative: the commands run in the repository and show it so
    (REPO / out).mkdir(parents=True, exist_ok=True)
    provenance = _provenance()
    timings = []
    for template in entry.commands:
        command = template.format(out=out)
        print(f"$ {command}", flush=True)
        started = time.monotonic()
        subprocess.run(shlex.split(command), cwd=REPO, check=True)
        timings.append({"command": _shown(command), "wall_time_s": round(time.monotonic() - started, 1)})
    collect(entry, {"commands": timings, **provenance})


def _shown(command: str) -> str:
    """A command as the pages show it: the installed ``frontier-rl``, not the venv's path."""
    return command.replace(f"{FRONTIER_RL} ", "frontier-rl ").replace(f"{PYTHON} ", "python ")


def _provenance() -> dict[str, object]:
    """The code a run measures: its commit, whether the package or the models differed from it, the
    day and the machine."""
    return {
        "commit": _git("rev-parse", "--short", "HEAD"),
        "changes_not_committed": bool(
            _git("status", "--porcelain", "--untracked-files=no", "frontier_rl", "models", "experiments", "benchmarks")
        ),
        "measured": time.strftime("%Y-%m-%d"),
        "machine": {"cores": os.cpu_count(), "cpu": _cpu_name(), "python": platform.python_version()},
    }


def collect(entry: Study, run_record: dict[str, object] | None = None) -> None:
    """Copy ``entry``'s kept files from its run folder into its data folder, with ``study.json``
    (``run_record``: the commands' wall times and the run's provenance; by default those of the data
    folder's last ``study.json``, or the commands alone with no times)."""
    source, target = REPO / RUNS / entry.name, REPO / DATA / entry.name
    if run_record is None and (target / "study.json").exists():
        run_record = json.loads((target / "study.json").read_text())
    if run_record is None:
        commands = [{"command": _shown(c.format(out=RUNS / entry.name)), "wall_time_s": None} for c in entry.commands]
        run_record = {"commands": commands, **_provenance()}
    if target.exists():
        shutil.rmtree(target)
    target.mkdir(parents=True)
    for pattern in entry.keep:
        for path in sorted(source.glob(pattern)):
            destination = target / path.relative_to(source)
            destination.parent.mkdir(parents=True, exist_ok=True)
            if path.name == "episodes.csv":
                _copy_columns(path, destination)
            else:
                shutil.copyfile(path, destination)
    meta = {"study": entry.name, **run_record}
    (target / "study.json").write_text(json.dumps(meta, indent=1) + "\n")
    print(f"collected {entry.name} into {target.relative_to(REPO)}")


def _copy_columns(source: Path, target: Path) -> None:
    with source.open(newline="") as src, target.open("w", newline="") as dst:
        reader = csv.DictReader(src)
        columns = [c for c in EPISODE_COLUMNS if c in (reader.fieldnames or ())]
        writer = csv.DictWriter(dst, columns, extrasaction="ignore", lineterminator="\n")
        writer.writeheader()
        writer.writerows(reader)


def _git(*args: str) -> str:
    return subprocess.run(["git", *args], cwd=REPO, capture_output=True, text=True, check=True).stdout.strip()


def _cpu_name() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("action", choices=("list", "run", "collect"))
    parser.add_argument("studies", nargs="*", help="study names (default for list: all)")
    args = parser.parse_args()
    if args.action == "list":
        for entry in STUDIES:
            print(entry.name)
            for command in entry.commands:
                print(f"    {_shown(command.format(out=RUNS / entry.name))}")
        return
    if not args.studies:
        raise SystemExit("name at least one study (see: studies.py list)")
    for name in args.studies:
        entry = study(name)
        run(entry) if args.action == "run" else collect(entry)


if __name__ == "__main__":
    sys.exit(main())
