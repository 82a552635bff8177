"""The page on experiment files (docs/reference/experiment-files.md), checked against what a tiny
``evaluate`` and a tiny ``train`` really write: every file written is listed, every file listed as
``always`` is written, and so is every conditional one this run exercises; the columns of
``episodes.csv`` are the ones the page describes."""

from __future__ import annotations

import csv
import fnmatch
from dataclasses import dataclass
from pathlib import Path

import pytest

from frontier_rl.core.sim.config import SimConfig
from frontier_rl.evaluation.report.run_pictures import AnimatedRun
from frontier_rl.evaluation.running.evaluate import evaluate
from frontier_rl.evaluation.running.experiment import ExperimentConfig
from tests.docs.markdown_pages import DOCS, ROOT, tokens

pytestmark = pytest.mark.slow

PAGE = DOCS / "reference" / "experiment-files.md"
NOT_EXERCISED = {"labels.npz"}
"""Files of the page the runs here do not make (``labels.npz``: a DAgger run, minutes long)."""


@dataclass(frozen=True)
class ListedFile:
    """A row of one of the page's file tables: a path pattern (``*`` any name) and when it is written."""

    pattern: str
    written: str


def tables(section: str) -> list[list[list[str]]]:
    """The tables of the page's section ``section`` (a level-2 heading's text): each a list of body
    rows, each a list of cell texts."""
    found: dict[str, list[list[list[str]]]] = {}
    items = tokens(PAGE)
    current, in_body = "", False
    for index, token in enumerate(items):
        if token.type == "heading_open" and token.tag == "h2":
            current = items[index + 1].content
        elif token.type == "table_open":
            found.setdefault(current, []).append([])
        elif token.type in ("tbody_open", "tbody_close"):
            in_body = token.type == "tbody_open"
        elif token.type == "tr_open" and in_body:
            found[current][-1].append([])
        elif token.type == "inline" and in_body and items[index - 1].type == "td_open":
            found[current][-1][-1].append(token.content)
    return found[section]


def listed_files(section: str) -> list[ListedFile]:
    """The files the first table of ``section`` lists."""
    return [ListedFile(row[0].strip("`"), row[1]) for row in tables(section)[0]]


def written_files(folder: Path) -> list[str]:
    return sorted(p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.is_file())


def check(listed: list[ListedFile], written: list[str]) -> None:
    unlisted = [f for f in written if not any(fnmatch.fnmatch(f, entry.pattern) for entry in listed)]
    assert not unlisted, f"written but not on {PAGE.name}: {unlisted}"
    missing = [
        entry.pattern
        for entry in listed
        if entry.pattern not in NOT_EXERCISED and not any(fnmatch.fnmatch(f, entry.pattern) for f in written)
    ]
    assert not missing, f"on {PAGE.name} but not written: {missing}"
    assert all(entry.written for entry in listed)


def test_the_files_of_an_experiment_are_those_the_page_lists(tmp_path: Path) -> None:
    out = tmp_path / "experiment"
    methods = ("fixed:0.75", f"learned:{ROOT / 'models' / 'model4.zip'}", "nearest@2")
    config = ExperimentConfig(methods=methods, worlds=("office",), episodes=1, sim=SimConfig(max_sim_time=120.0))
    evaluate(config, out, backend="serial", progress=False, pictures=1, animate=AnimatedRun("office", "fixed:0.75"))
    check(listed_files("`frontier-rl evaluate`"), written_files(out))
    with (out / "episodes.csv").open() as rows:
        columns = next(csv.reader(rows))
    described = [name.strip(" `") for row in tables("`frontier-rl evaluate`")[1] for name in row[0].split(",")]
    assert sorted(columns) == sorted(described)


def test_the_files_of_a_training_run_are_those_the_page_lists(tmp_path: Path) -> None:
    from frontier_rl.rl.config import TrainConfig
    from frontier_rl.rl.train import train

    out = tmp_path / "run"
    config = TrainConfig(
        model=4,
        worlds="office,lse_arena",  # a map file among them: map_files.txt
        timesteps=16,
        n_envs=1,
        n_steps=8,
        eval_every=8,
        eval_episodes=1,
        checkpoint_every=8,
        sim=SimConfig(max_sim_time=60.0),
    )
    train(config, out, progress=False)
    check(listed_files("`frontier-rl train`"), written_files(out))


def test_a_file_not_listed_or_listed_and_not_written_is_found() -> None:
    listed = [ListedFile("report.md", "always"), ListedFile("pictures/*.png", "with --pictures")]
    check(listed, ["report.md", "pictures/office_nearest.png"])
    with pytest.raises(AssertionError, match="written but not on"):
        check(listed, ["report.md", "pictures/office_nearest.png", "extra.csv"])
    with pytest.raises(AssertionError, match=r"but not written: \['pictures/\*\.png'\]"):
        check(listed, ["report.md"])
