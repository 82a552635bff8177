"""A training run's folder: what it holds (its configuration, the map files it trains on, its
checkpoints), and whether a run may start, continue or go on for longer in it."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from stable_baselines3.common.base_class import BaseAlgorithm

from frontier_rl.atomic_write import describe_os_error, write_text_atomic
from frontier_rl.bounded_read import UnreadableFileError, read_bounded
from frontier_rl.config_diff import ABSENT, describe_differences, differences_between
from frontier_rl.errors import ConfigError, short_path
from frontier_rl.inference.model_file import CHECKPOINT_NAME, checkpoint_name, read_metadata
from frontier_rl.map_fingerprint import MapFingerprint
from frontier_rl.registration import Algorithm
from frontier_rl.rl.config import TrainConfig
from frontier_rl.rl.model_file import save_model
from frontier_rl.run_folders import RunKind, refuse_other_runs, run_kind


def latest_checkpoint(run: Path) -> tuple[Path, int] | None:
    """The newest checkpoint of ``run`` and its step count, if any."""
    found = []
    for path in (run / "checkpoints").glob("model_*_steps.zip"):
        match = CHECKPOINT_NAME.search(path.name)
        if match:
            found.append((int(match.group(1)), path))
    if not found:
        return None
    steps, path = max(found)
    return path, steps


FINAL_MODEL_NAME = "model.zip"
"""The final model of a run folder."""

MAP_FILES_NAME = "map_files.txt"
"""The file of a run folder that lists the run's map files, each with a hash of its map."""

_MAP_CHANGES_SHOWN = 4
"""A run refused for its map files names at most this many that changed."""

MAX_MAP_FILES_BYTES = 64 * 2**20
"""The most of :data:`MAP_FILES_NAME` read (a line per map: about 200,000 maps)."""


def prepare_run_folder(config: TrainConfig, out: Path, resume: bool, maps: tuple[str, ...]) -> int:
    """Prepare ``out`` for a run of ``config`` on map files ``maps`` (``spec#sha256:HASH``);
    returns the step count to start from (0, or the last checkpoint's).

    With ``resume``, the run in ``out`` must have the same configuration and maps, but for
    ``timesteps``: a run may be given more decisions (or fewer, not below those it has made); its
    ``config.yaml`` says the new count once the run's model is saved (:func:`record_timesteps`)."""
    refuse_other_runs(out, RunKind.TRAINING)
    saved_path = out / "config.yaml"
    if saved_path.exists():
        if not resume:
            raise ConfigError(f"{str(out)!r} already holds a training run; pass --resume to continue it")
        saved = TrainConfig.load(saved_path)
        _check_same_run(saved, config, out)
        _check_map_files(out, maps)
        return _resumed_from(saved, config, out)
    if resume:
        raise ConfigError(f"nothing to resume: {str(out)!r} holds no training run")
    if run_kind(out) is RunKind.TRAINING:  # a model file or checkpoints without their run's config.yaml
        raise ConfigError(f"{str(out)!r} holds a model.zip or checkpoints of another run; choose another --out")
    out.mkdir(parents=True, exist_ok=True)
    if maps:
        write_text_atomic(out / MAP_FILES_NAME, "".join(f"{m}\n" for m in maps))
    config.dump(saved_path)
    return 0


def _check_same_run(saved: TrainConfig, config: TrainConfig, out: Path) -> None:
    """Refuse to resume the run ``saved`` in ``out`` with a ``config`` that differs from it in more
    than its ``timesteps``."""
    if replace(saved, timesteps=config.timesteps) == config:
        return
    there, now = saved.to_dict(), config.to_dict()
    differs = [
        d for key in now if key != "timesteps" for d in differences_between(there.get(key, ABSENT), now[key], key)
    ]
    raise ConfigError(f"{str(out)!r} holds a run with a different configuration ({describe_differences(differs)})")


def _resumed_from(saved: TrainConfig, config: TrainConfig, out: Path) -> int:
    """The step count the run ``saved`` in ``out`` resumes from (its last checkpoint's, or 0),
    checked against what the run wrote and against ``config.timesteps``."""
    checkpoint = latest_checkpoint(out)
    # SB3 ends a run with a whole rollout, so its last checkpoints may pass the timesteps by less than one
    most = max(saved.timesteps, config.timesteps) + saved.n_steps * saved.n_envs - 1  # a grown run's too
    if checkpoint is not None and checkpoint[1] > most:  # a name the run did not write
        raise ConfigError(
            f"checkpoint {short_path(checkpoint[0])} claims {checkpoint[1]} decisions, more than the run "
            f"takes ({most}); remove it to resume from the one before"
        )
    start = 0 if checkpoint is None else checkpoint[1]
    if config.timesteps == saved.timesteps:
        return start
    finished = read_metadata(out / FINAL_MODEL_NAME) if (out / FINAL_MODEL_NAME).is_file() else None
    made = max(start, 0 if finished is None else finished.timesteps)
    if config.timesteps < made:
        raise ConfigError(
            f"{str(out)!r} holds a run that has made {made} decisions; --timesteps {config.timesteps} would "
            "take some of them back (train into another --out, with --init, to start from its model)"
        )
    if finished is not None and start < finished.timesteps:
        raise ConfigError(
            f"{str(out)!r} holds a finished run of {finished.timesteps} decisions without a checkpoint at its end "
            f"({f'the last at {start}' if start else 'none'}); it cannot go on for longer (train into another --out, "
            "with --init, to start from its model)"
        )
    return start


def _check_map_files(out: Path, maps: tuple[str, ...]) -> None:
    """Refuse to resume the run in ``out`` on map files other than those it was trained on (a
    folder of maps with a map edited, added or removed); a run written before the list was kept
    is not checked, and gets its list now."""
    listed = out / MAP_FILES_NAME
    if not listed.exists():  # a run an older version wrote: its maps from now on
        if maps:
            write_text_atomic(listed, "".join(f"{m}\n" for m in maps))
        return
    try:
        there = read_bounded(listed, MAX_MAP_FILES_BYTES).decode("utf-8", "replace").splitlines()
    except UnreadableFileError as exc:
        raise ConfigError(str(exc)) from None
    except OSError as exc:
        raise ConfigError(f"{listed}: cannot be read ({describe_os_error(exc)})") from None
    if there != list(maps):
        raise ConfigError(
            f"{str(out)!r} holds a run trained on other map files ({_map_changes(there, maps)}); "
            "resume it on the maps it was trained on"
        )


def _map_changes(there: list[str], now: tuple[str, ...]) -> str:
    """The map files that differ between two lists of ``spec#sha256:HASH``: changed, added, removed."""
    before = {(f := MapFingerprint.parse(line)).spec: f.digest for line in there}
    after = {(f := MapFingerprint.parse(line)).spec: f.digest for line in now}
    changes = [f"{short_path(m)} changed" for m in after if m in before and before[m] != after[m]]
    changes += [f"{short_path(m)} added" for m in after if m not in before]
    changes += [f"{short_path(m)} removed" for m in before if m not in after]
    shown = ", ".join(changes[:_MAP_CHANGES_SHOWN]) or "the same maps in another order"
    more = len(changes) - _MAP_CHANGES_SHOWN
    return shown + (f" and {more} more" if more > 0 else "")


def record_timesteps(config: TrainConfig, out: Path) -> None:
    """Say in ``out``'s ``config.yaml`` the decisions ``config`` trained the run for, once its model is
    saved: a run given more (or fewer) on ``--resume`` keeps the old count until then, so that the
    file always describes the run's ``model.zip``."""
    saved_path = out / "config.yaml"
    if TrainConfig.load(saved_path).timesteps != config.timesteps:
        config.dump(saved_path)


def keep_final_checkpoint(model: BaseAlgorithm, out: Path) -> None:
    """A checkpoint of ``model`` at the run's last decision, unless one is there: a finished run
    then goes on for longer (``--resume`` with more ``--timesteps``) from where its model is, not
    from the last periodic checkpoint."""
    last = latest_checkpoint(out)
    if last is None or last[1] != model.num_timesteps:
        save_model(model, out / "checkpoints" / checkpoint_name(model.num_timesteps))


def interruption_note(config: TrainConfig, out: Path) -> str:
    """The line that ends a run in ``out`` stopped by Ctrl-C: what it kept, and how to go on."""
    checkpoint = latest_checkpoint(out)
    if checkpoint is None:
        return f"interrupted: no checkpoint was written in {out}/ yet"
    kept = f"interrupted: the last checkpoint ({checkpoint[1]} decisions) is {checkpoint[0]}"
    if config.algo is Algorithm.DAGGER:
        return f"{kept}; a dagger run cannot be resumed"
    return f"{kept}; add --resume to the same command to continue"
