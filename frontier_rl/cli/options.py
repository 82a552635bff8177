"""What several ``frontier-rl`` commands share: the seed, world and policy options, their checks, and
the simulation settings from ``--config`` and ``--max-time``. It loads none of the engine (the help
and the argument errors of every command need none): what the options quote are plain names."""

from __future__ import annotations

import dataclasses
import math
import os
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, NoReturn

import typer

from frontier_rl.core.navigation.config import MAX_STOPS
from frontier_rl.core.world.names import GENERATOR_NAMES
from frontier_rl.core.world.scale import checked_resolution, resolution_bounds
from frontier_rl.errors import ConfigError, short_path, short_repr
from frontier_rl.policies.spec import ENTRY_POINT_GROUP, POLICY_NAMES
from frontier_rl.seeds import MAX_SEED as MAX_SEED  # the largest --seed, named in the commands' help
from frontier_rl.seeds import checked_seed

if TYPE_CHECKING:
    from frontier_rl.core.sim.config import SimConfig

WORLD_HELP = f"{' | '.join(GENERATOR_NAMES)} | a map file (ROS .yaml, Dungeon .png, HouseExpo .json) | a catalogue map"
POLICY_HELP = (
    f"One of: {', '.join(POLICY_NAMES)} (W in [0, 1], N stops 1 to {MAX_STOPS}); or your own: FILE.py:CLASS, "
    f"MODULE:CLASS (on PYTHONPATH) or a name an installed package registers under {ENTRY_POINT_GROUP}."
)

_RES_LO, _RES_HI = resolution_bounds()

# Options that several commands share
ResolutionOption = Annotated[
    float | None,
    typer.Option(
        help=f"Cell size (m) for map files, {_RES_LO:.2g} to {_RES_HI:.3g} (the robot's radius); "
        "below 0.04 m the robot maps on 0.05 m cells."
    ),
]
TrustModelOption = Annotated[
    bool, typer.Option(help="Allow learned:PATH to be an SB3 zip from elsewhere (unpickles it: runs its code).")
]
SimConfigOption = Annotated[Path | None, typer.Option(help="SimConfig YAML (any subset of its fields).")]
WorkersOption = Annotated[int | None, typer.Option(help="Processes running episodes at once (default: every core).")]


def fail(message: str) -> NoReturn:
    """Stop the command with a one-line error."""
    raise ConfigError(message)


def checked_count(option: str, value: int) -> int:
    """A count option, checked: a whole number of at least 0."""
    if value < 0:
        fail(f"{option} must be 0 or more, got {short_repr(value)}")
    return value


def output_folder(path: Path, option: str = "--out") -> Path:
    """A results folder option, checked before any work: an existing folder, or a path whose
    nearest existing ancestor is a writable folder (the command creates the rest)."""
    if path.exists() and not path.is_dir():
        fail(f"{option} {short_path(path)} is a file, not a folder")
    _writable_ancestor(path, option)
    return path


def output_file(path: Path, suffix: str, option: str) -> Path:
    """An output file option (``--png``, ``--json``), checked before any work: it ends in ``suffix``
    (".png", ".gif", ".json", any case), is not a folder, and its folder exists and is writable or can
    be made (its nearest existing ancestor is a writable folder; the writer makes the rest)."""
    if path.is_dir():
        fail(f"{option} {short_path(path)} is a folder; name a {suffix} file inside it")
    if path.suffix.lower() != suffix:
        fail(f"{option} {short_path(path)} must be a {suffix} file name, got suffix {path.suffix!r}")
    _writable_ancestor(path.parent, option, path)
    return path


def _writable_ancestor(folder: Path, option: str, named: Path | None = None) -> None:
    """Nothing if ``folder`` or, where it does not exist yet, its nearest existing ancestor is a
    writable folder; else one line naming the option and ``named`` (default ``folder``)."""
    named = folder if named is None else named
    ancestor = folder
    while not ancestor.exists() and ancestor != ancestor.parent:
        ancestor = ancestor.parent
    if not ancestor.is_dir():
        fail(f"{option} {short_path(named)}: {short_path(ancestor)} is a file, not a folder")
    if not os.access(ancestor, os.W_OK | os.X_OK):
        fail(f"{option} {short_path(named)}: folder {short_path(ancestor)} is not writable")


def checked_run_arguments(seed: int, out: Path, resolution: float | None = None) -> float | None:
    """A run's ``--seed``, ``--out`` and ``--resolution``, checked before the engine's imports (a
    second): returns the resolution (m, None for the map's own)."""
    checked_seed(seed, "--seed")
    output_folder(out)
    return checked_resolution(resolution)


def checked_comm_range(value: float | None) -> float | None:
    """``--comm-range``, checked (m; None: the strategy's default)."""
    if value is not None and not value >= 0:
        raise ConfigError(f"--comm-range must be >= 0 m, got {value!r}")
    return value


def sim_config(config: Path | None, max_time: float | None) -> SimConfig:
    """The settings of ``--config`` (a SimConfig YAML; the defaults without one) with ``--max-time`` (s) applied."""
    from frontier_rl.config_files import load_sim_config
    from frontier_rl.core.sim.config import SimConfig

    cfg = load_sim_config(config) if config is not None else SimConfig()
    if max_time is not None:
        if not (max_time > 0 and math.isfinite(max_time)):
            raise ConfigError(f"--max-time must be a positive number of seconds, got {max_time!r}")
        cfg = dataclasses.replace(cfg, max_sim_time=max_time)
    return cfg
