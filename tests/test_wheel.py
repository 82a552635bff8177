"""The wheel: it carries the maps with their licences and sources but not Stage's GPL bitmaps, and
installed with nothing else of the checkout (a fresh venv, its third-party packages taken from the
project's venv) it runs an episode on a catalogue map and lists the catalogue from any folder."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import pytest

from frontier_rl.io.catalogue import MAPS_DIR, catalogue

pytestmark = pytest.mark.slow

REPO = Path(__file__).resolve().parents[1]
MAPS = "frontier_rl/data/maps/"


@pytest.fixture(scope="module")
def wheel(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A wheel built from a copy of the working tree (so no build/ folder lands in the checkout)."""
    root = tmp_path_factory.mktemp("wheel")
    source = root / "source"
    source.mkdir()
    for name in ("pyproject.toml", "README.md", "LICENSE"):
        shutil.copy(REPO / name, source / name)
    shutil.copytree(REPO / "frontier_rl", source / "frontier_rl", ignore=shutil.ignore_patterns("__pycache__"))
    args = [
        sys.executable,
        "-m",
        "pip",
        "wheel",
        "--no-deps",
        "--no-build-isolation",
        "-q",
        "-w",
        str(root),
        "./source",
    ]
    subprocess.run(args, cwd=root, check=True, capture_output=True, timeout=120)
    (built,) = root.glob("frontier_rl-*.whl")
    return built


def test_the_wheel_holds_the_maps_and_their_licences_but_no_stage_bitmap(wheel: Path) -> None:
    with zipfile.ZipFile(wheel) as archive:
        names = set(archive.namelist())
    maps = {name.removeprefix(MAPS) for name in names if name.startswith(MAPS)}
    assert "catalogue.yaml" in maps
    for folder in ("turtlebot3_world", "aws_small_house", "nav2_depot", "nav2_warehouse", "lse_arena", "dungeon"):
        assert {f"{folder}/LICENSE", f"{folder}/SOURCE.md"} <= maps, folder
    assert {"houseexpo/LICENSE_HouseExpo", "houseexpo/SOURCE.md", "stage/SOURCE.md"} <= maps
    assert {
        "nav2_warehouse/warehouse.pgm",
        "nav2_warehouse/warehouse.yaml",
        "houseexpo/house_expo_room_0000.json",
    } <= maps
    for level, count in (("train", 500), ("easy", 100), ("medium", 100), ("complex", 100)):
        assert sum(m.startswith(f"dungeon/{level}/") and m.endswith(".png") for m in maps) == count
    stage = {m for m in maps if m.startswith("stage/")}
    assert not any(m.endswith(".png") for m in stage) and "stage/COPYING.txt" not in stage
    assert "stage/cave.yaml" in stage  # this project's YAMLs stay: the catalogue reads their resolution
    for entry in catalogue().maps:  # every map the catalogue leaves out of the wheel is out of it
        image = entry.path.with_suffix(".png").relative_to(MAPS_DIR).as_posix()
        assert (image in maps) == entry.in_wheel or not entry.path.with_suffix(".png").exists(), entry.name
    assert not any("__pycache__" in name or name.endswith((".nbi", ".nbc")) for name in names)


def _run(command: list[str], cwd: Path, expect: int = 0) -> subprocess.CompletedProcess[str]:
    done = subprocess.run(command, cwd=cwd, capture_output=True, text=True, timeout=240)
    assert done.returncode == expect, done.stdout + done.stderr
    return done


def test_the_wheel_installed_alone_explores_a_catalogue_map(wheel: Path, tmp_path: Path) -> None:
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True, timeout=60)
    python = venv / "bin" / "python"
    site = Path(
        _run([str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"], tmp_path).stdout.strip()
    )
    # numpy, typer, ... from the project's venv; its editable frontier_rl is a .pth file there, and
    # .pth files in a folder that a .pth line adds are not read, so it does not come along:
    (site / "project_packages.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    away = tmp_path / "elsewhere"
    away.mkdir()
    _run([str(python), "-c", "import numpy, typer, PIL"], away)
    assert "No module named 'frontier_rl'" in _run([str(python), "-c", "import frontier_rl"], away, expect=1).stderr
    _run([sys.executable, "-m", "pip", "--python", str(python), "install", "--no-deps", "-q", str(wheel)], away)

    where = _run([str(python), "-c", "import frontier_rl; print(frontier_rl.__file__)"], away).stdout.strip()
    assert Path(where).is_relative_to(venv)
    frontier_rl = str(venv / "bin" / "frontier-rl")
    # The episode takes most of this test's time: numba compiles the engine afresh for the new venv's
    # copy of it (about 17 s of CPU, against 2 s with NUMBA_DISABLE_JIT=1). Compiled it stays: without
    # the JIT the engine hands back NumPy scalars (truncated is numpy.False_, sim_time_s a float64,
    # path_length_m differs in its 16th digit) and explore --json fails on them: not the same episode.
    with subprocess.Popen([frontier_rl, "maps", "--json"], cwd=away, stdout=subprocess.PIPE, text=True) as listing:
        try:
            episode = _run([frontier_rl, "explore", "--world", "lse_arena", "--policy", "nearest", "--json"], away)
            out, _ = listing.communicate(timeout=120)
        finally:
            listing.kill()  # ended (a no-op once it has), so that a failure above leaves no process behind
    result = json.loads(episode.stdout.strip().splitlines()[-1])
    assert result["world"] == "lse_arena" and result["end_reason"] == "explored" and result["coverage"] > 0.99
    records = {r["name"]: r for r in json.loads(out)}
    assert records["nav2_depot"]["installed"] is True
    assert (records["dungeon/easy"]["count"], records["dungeon/easy"]["installed_count"]) == (100, 100)
    stage = records["stage"]  # a collection of 5 maps, none of them in the wheel
    assert (stage["installed"], stage["count"], stage["installed_count"]) == (False, 5, 0)
    assert stage["source"].startswith("https://github.com/rtv/Stage")
    refused = _run([frontier_rl, "explore", "--world", "stage/cave"], away, expect=2)
    assert "'stage/cave' is not installed" in refused.stderr and "github.com/rtv/Stage" in refused.stderr
