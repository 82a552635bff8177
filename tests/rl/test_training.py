"""Training: a smoke run per model that saves, reloads and acts; resuming; the run directory."""

from __future__ import annotations

import zipfile
from dataclasses import replace
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import torch
from PIL import Image
from stable_baselines3 import A2C
from stable_baselines3.common.callbacks import BaseCallback

from frontier_rl.core.mapping.mapper import MapperConfig
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import run_episode
from frontier_rl.core.world.catalog import generate_world
from frontier_rl.errors import ConfigError, TrainingDivergedError
from frontier_rl.inference.model_file import METADATA_ENTRY, read_metadata
from frontier_rl.policies import make_policy
from frontier_rl.rl.callbacks import ValidationCallback
from frontier_rl.rl.config import TrainConfig
from frontier_rl.rl.model_file import load_policy, save_model
from frontier_rl.rl.run_folder import interruption_note, latest_checkpoint
from frontier_rl.rl.train import train

pytestmark = pytest.mark.slow  # training runs

SHORT = SimConfig(max_sim_time=120.0)


def _config(model: int, **changes: object) -> TrainConfig:
    values: dict[str, object] = {
        "model": model, "timesteps": 200, "n_envs": 1, "observation_size": 64, "eval_every": 100,
        "eval_episodes": 1, "checkpoint_every": 100, "n_steps": 8, "max_decisions": 24,
    }  # fmt: skip
    values.update(changes)
    return TrainConfig(**values)  # type: ignore[arg-type]


@pytest.mark.parametrize("model", [1, 2, 3, 4, 5, 6, 7])
def test_smoke_training_saves_reloads_and_acts(model: int, tmp_path: Path) -> None:
    run = tmp_path / f"model{model}"
    final = train(_config(model), run, progress=False)
    assert final == run / "model.zip"
    for name in ("config.yaml", "learning_curve.png", "validation.csv", "best_model.zip", "training_time.txt"):
        assert (run / name).exists(), name
    assert latest_checkpoint(run) is not None
    assert list((run / "tb").iterdir())
    info = read_metadata(final)
    assert info is not None and info.model == model and info.timesteps >= 200
    best = read_metadata(run / "best_model.zip")
    # validated at 100 and 200 decisions, inside rollouts of 8: the weights had learnt from 96 and 192
    # (the final model from all 200: both files said 200 when the last validation was the best)
    assert best is not None and best.timesteps in (96, 192)
    policy = make_policy(f"learned:{final}")
    result = run_episode(generate_world("office", 0), policy, SHORT, seed=0)
    assert result.sim_time_s > 0 and result.decisions > 0
    if model in (3, 4, 6):
        weights = [d.weight for d in result.decision_log]
        assert all(w is not None and 0 <= w < 1 for w in weights)


def test_ppo_and_subprocess_envs(tmp_path: Path) -> None:
    final = train(_config(4, algo="ppo", n_envs=2, timesteps=48, eval_every=0), tmp_path / "ppo", progress=False)
    info = read_metadata(final)
    assert info is not None and info.algo == "ppo"
    assert not (tmp_path / "ppo" / "validation.csv").exists()


class _Interrupt(BaseCallback):
    """Stops training like a Ctrl-C once ``at`` steps are done."""

    def __init__(self, at: int) -> None:
        super().__init__()
        self.at = at

    def _on_step(self) -> bool:
        if self.num_timesteps >= self.at:
            raise KeyboardInterrupt
        return True


class _FirstObservation(BaseCallback):
    """Keeps the observations a run segment starts from (its envs' first reset)."""

    def __init__(self) -> None:
        super().__init__()
        self.first: object = None

    def _on_training_start(self) -> None:
        self.first = self.model._last_obs.copy()  # type: ignore[union-attr]

    def _on_step(self) -> bool:
        return True


def test_a_training_run_is_not_written_into_an_evaluation_folder(tmp_path: Path) -> None:
    """Its config.yaml, checkpoints and model went in among the evaluation's rows."""
    (tmp_path / "episodes.csv").write_text("method,world,seed\n")
    with pytest.raises(ConfigError, match="holds an evaluation's results"):
        train(_config(4), tmp_path, progress=False)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["episodes.csv"]


def test_a_model_file_without_its_run_is_not_overwritten(tmp_path: Path) -> None:
    """A model downloaded into a folder (or a run whose config.yaml was deleted) was overwritten."""
    (tmp_path / "model.zip").write_bytes(b"a model")
    with pytest.raises(ConfigError, match=r"holds a model\.zip or checkpoints of another run"):
        train(_config(4), tmp_path, progress=False)
    assert (tmp_path / "model.zip").read_bytes() == b"a model"


def test_interrupted_run_resumes_from_its_last_checkpoint(tmp_path: Path) -> None:
    run = tmp_path / "run"
    config = _config(4, timesteps=96, eval_every=0, checkpoint_every=32)
    opening = _FirstObservation()
    with pytest.raises(KeyboardInterrupt):
        train(config, run, progress=False, extra_callbacks=[opening, _Interrupt(70)])
    assert not (run / "model.zip").exists()
    checkpoint = latest_checkpoint(run)
    assert checkpoint is not None and checkpoint[1] == 64
    assert interruption_note(config, run) == (  # the line the command line ends with
        f"interrupted: the last checkpoint (64 decisions) is {checkpoint[0]}; "
        "add --resume to the same command to continue"
    )
    assert "cannot be resumed" in interruption_note(_config(5, algo="dagger"), run)
    assert interruption_note(config, tmp_path) == f"interrupted: no checkpoint was written in {tmp_path}/ yet"
    with pytest.raises(ConfigError, match="--resume"):
        train(config, run, progress=False)
    with pytest.raises(ConfigError, match=r"different configuration \(gamma: 0\.99 there, 0\.9 now\)"):
        train(_config(4, timesteps=96, eval_every=0, checkpoint_every=32, gamma=0.9), run, resume=True, progress=False)
    resumed = _FirstObservation()
    final = train(config, run, resume=True, progress=False, extra_callbacks=[resumed])
    info = read_metadata(final)
    assert info is not None and info.timesteps == 96
    # the envs were seeded as at the run's start: it replayed the world and start it opened with
    assert not np.array_equal(resumed.first, opening.first)  # type: ignore[arg-type]
    segments = (run / "training_time.txt").read_text().splitlines()  # the interrupted one too
    assert [line.split(":")[0] for line in segments] == ["steps 0..70", "steps 64..96"], segments
    assert (run / "monitor_0.monitor.csv").exists() and (run / "monitor_64.monitor.csv").exists()
    before = final.read_bytes(), sorted(p.name for p in run.iterdir())
    assert train(config, run, resume=True, progress=False) == final  # a finished run: nothing left to do
    assert (final.read_bytes(), sorted(p.name for p in run.iterdir())) == before  # its file's hash unchanged
    forged = run / "checkpoints" / "model_99999999999999_steps.zip"  # its model file's metadata was refused
    forged.write_bytes((run / "checkpoints" / "model_64_steps.zip").read_bytes())
    with pytest.raises(ConfigError, match=r"claims 99999999999999 decisions, more than the run takes \(103\)"):
        train(config, run, resume=True, progress=False)


def _two_room_maps(folder: Path, n: int) -> Path:
    """``n`` bitmap maps of two rooms (2.5 m each, 0.05 m cells) joined by a 0.6 m door."""
    folder.mkdir()
    image = np.zeros((60, 110), np.uint8)
    image[3:-3, 3:-3] = 255
    image[3:-3, 55] = 0
    image[24:36, 55] = 255
    for k in range(n):
        Image.fromarray(image).save(folder / f"room_{k:03d}.png")
    return folder


def test_a_run_is_resumed_only_on_the_map_files_it_was_trained_on(tmp_path: Path) -> None:
    """A folder of maps with a map edited or added was trained on as if nothing had changed."""
    folder = _two_room_maps(tmp_path / "maps", 2)
    run = tmp_path / "run"
    # the largest seed: a resume seeds with it plus the checkpoint's step, past what NumPy takes
    config = _config(4, worlds=str(folder), timesteps=48, eval_every=0, checkpoint_every=16, seed=2**32 - 1)
    with pytest.raises(KeyboardInterrupt):
        train(config, run, progress=False, extra_callbacks=[_Interrupt(20)])
    listed = (run / "map_files.txt").read_text().splitlines()
    assert [line.split("#sha256:")[0] for line in listed] == [
        str(folder / "room_000.png"),
        str(folder / "room_001.png"),
    ]
    image = np.array(Image.open(folder / "room_001.png"))
    image[10:12, 10:30] = 0  # a wall drawn into the second room
    Image.fromarray(image).save(folder / "room_001.png")
    with pytest.raises(ConfigError, match=r"other map files \('.*/room_001\.png' changed\); resume it"):
        train(config, run, resume=True, progress=False)
    Image.fromarray(np.array(Image.open(folder / "room_000.png"))).save(folder / "room_001.png")  # as it was
    (folder / "room_002.png").write_bytes((folder / "room_000.png").read_bytes())
    with pytest.raises(ConfigError, match=r"\('.*/room_002\.png' added\)"):
        train(config, run, resume=True, progress=False)
    (folder / "room_002.png").unlink()
    info = read_metadata(train(config, run, resume=True, progress=False))
    assert info is not None and info.timesteps == 48


def test_a_run_goes_on_for_longer_with_more_timesteps(tmp_path: Path) -> None:
    """A finished run could not be extended: more --timesteps was "a different configuration"."""
    run = tmp_path / "run"
    config = _config(4, timesteps=40, eval_every=0, checkpoint_every=16)
    train(config, run, progress=False)
    assert latest_checkpoint(run) == (run / "checkpoints" / "model_40_steps.zip", 40)  # at its end, not at 32
    with pytest.raises(ConfigError, match=r"has made 40 decisions; --timesteps 24 would take some of them back"):
        train(replace(config, timesteps=24), run, resume=True, progress=False)
    with pytest.raises(KeyboardInterrupt):  # a longer run cut short: config.yaml still says the model's count
        train(replace(config, timesteps=64), run, resume=True, progress=False, extra_callbacks=[_Interrupt(58)])
    past = (run / "checkpoints" / "model_56_steps.zip", 56)  # past the 40 config.yaml says: not refused as forged
    assert TrainConfig.load(run / "config.yaml") == config and latest_checkpoint(run) == past
    longer = replace(config, timesteps=64)
    info = read_metadata(train(longer, run, resume=True, progress=False))
    assert info is not None and info.timesteps == 64
    assert TrainConfig.load(run / "config.yaml") == longer
    segments = (run / "training_time.txt").read_text().splitlines()
    assert [line.split(":")[0] for line in segments] == ["steps 0..40", "steps 40..58", "steps 56..64"], segments
    without = tmp_path / "without"  # no checkpoint at its end: it would go on from an earlier one
    train(replace(config, checkpoint_every=0), without, progress=False)
    with pytest.raises(ConfigError, match=r"finished run of 40 decisions without a checkpoint at its end \(none\)"):
        train(replace(config, checkpoint_every=0, timesteps=64), without, resume=True, progress=False)


def test_worlds_that_cannot_start_are_one_line_with_worker_envs(tmp_path: Path) -> None:
    """Rooms the sensor sees whole: with two worker envs, a worker's traceback and a broken pipe."""
    rooms = tmp_path / "rooms"
    rooms.mkdir()
    image = np.zeros((24, 24), np.uint8)  # 1.2 m across: seen whole from every start
    image[3:-3, 3:-3] = 255
    Image.fromarray(image).save(rooms / "room.png")
    with pytest.raises(ConfigError, match="had no frontier left at its start"):
        train(_config(4, worlds=str(rooms), n_envs=2, eval_every=0), tmp_path / "run", progress=False)


def test_a_run_whose_last_rollout_passed_its_timesteps_resumes_from_that_checkpoint(tmp_path: Path) -> None:
    """SB3 ends with a whole rollout: a checkpoint at 104 decisions of a 100-decision run was refused."""
    run = tmp_path / "run"
    config = _config(4, timesteps=100, n_steps=8, eval_every=0, checkpoint_every=52)
    final = train(config, run, progress=False)
    checkpoint = latest_checkpoint(run)
    assert checkpoint is not None and checkpoint[1] == 104
    assert train(config, run, resume=True, progress=False) == final


def test_an_interrupted_runs_best_model_is_a_model_file(tmp_path: Path) -> None:
    """The best model is saved with its metadata when it is found: it got them only when the run
    finished, so an interrupted run's best model loaded only with --trust-model."""
    run = tmp_path / "run"
    with pytest.raises(KeyboardInterrupt):
        train(_config(5, timesteps=96, eval_every=32, checkpoint_every=0), run, progress=False,
              extra_callbacks=[_Interrupt(70)])  # fmt: skip
    best = read_metadata(run / "best_model.zip")
    assert best is not None and best.model == 5 and best.timesteps in (24, 56)
    assert make_policy(f"learned:{run / 'best_model.zip'}").name


@pytest.mark.parametrize(
    ("rows", "resumed_at", "due"),
    [((), 0, 32), ((32,), 64, 64), ((33, 64), 64, 96), ((), 64, 32), ((32, 64), 80, 96)],
)
def test_a_resumed_run_makes_up_for_a_validation_an_interrupt_cut_short(
    tmp_path: Path, rows: tuple[int, ...], resumed_at: int, due: int
) -> None:
    """A Ctrl-C during the validation at 64 decisions, after that step's checkpoint, lost the point:
    the run resumed at 64 validated next at 96."""
    csv_path = tmp_path / "validation.csv"
    if rows:
        csv_path.write_text("timesteps,mean_time_s,times\n" + "".join(f"{r},300.0,300.0\n" for r in rows))
    callback = ValidationCallback(None, 32, 1, csv_path, tmp_path / "best_model.zip", None)  # type: ignore[arg-type]
    callback.num_timesteps = resumed_at
    callback._on_training_start()
    assert callback._next == due


def test_a_resumed_run_missing_validations_makes_up_for_one_not_for_each(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Resumed at 320 with no validation.csv, it validated at each of the next ten decisions."""
    import frontier_rl.rl.callbacks as callbacks

    ran: list[int] = []
    callback = ValidationCallback(None, 32, 1, tmp_path / "validation.csv", tmp_path / "best.zip", None)  # type: ignore[arg-type]
    monkeypatch.setattr(callbacks, "run_validation", lambda env, predict, episodes: ran.append(0) or [300.0])
    callback.model = SimpleNamespace(logger=SimpleNamespace(record=lambda *args: None))  # type: ignore[assignment]
    callback.num_timesteps = 320
    callback._on_training_start()
    callback.best = 0.0  # no model is better: none to save
    validated_at = []
    for step in range(321, 400):
        callback.num_timesteps = step
        before = len(ran)
        callback._on_step()
        if len(ran) > before:
            validated_at.append(step)
    assert validated_at == [321, 352, 384]


class _RecordSim(BaseCallback):
    """Records the simulator settings the training envs run on."""

    def __init__(self) -> None:
        super().__init__()
        self.seen: list[SimConfig] = []

    def _on_step(self) -> bool:
        self.seen = [config.sim for config in self.training_env.get_attr("config")]
        return True


def test_the_envs_train_on_the_runs_simulator_settings(tmp_path: Path) -> None:
    sim = SimConfig(mapper=MapperConfig(hit=0.85, miss=-0.4, occupied_above=0.6, free_below=-0.35))
    config = _config(5, timesteps=16, eval_every=0, checkpoint_every=0, sim=sim)
    recorder = _RecordSim()
    train(config, tmp_path / "run", progress=False, extra_callbacks=[recorder])
    assert recorder.seen == [sim]
    assert TrainConfig.load(tmp_path / "run" / "config.yaml") == config
    assert TrainConfig.load(tmp_path / "run" / "config.yaml").sim.mapper.hit == 0.85


def test_resume_without_a_run_is_an_error(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match="nothing to resume"):
        train(_config(4), tmp_path / "none", resume=True, progress=False)


@pytest.mark.parametrize(
    ("changes", "match"),
    [({"model": 8}, "model 8"), ({"algo": "dqn"}, "dqn"), ({"observation_size": 128}, "128"),
     ({"worlds": "office,venus"}, "venus"), ({"reward": "gold"}, "gold"), ({"timesteps": 0}, "timesteps"),
     ({"learning_rate": -1.0}, "learning_rate"), ({"gamma": 1.5}, "gamma"), ({"init": 3}, "init"),
     ({"ent_coef": -0.01}, "ent_coef"), ({"ent_coef": float("nan")}, "ent_coef"),
     ({"vf_coef": float("inf")}, "vf_coef"), ({"learning_rate": float("inf")}, "learning_rate"),
     ({"learning_rate": 1e300}, "learning_rate"), ({"ent_coef": 1e308}, "ent_coef"), ({"n_envs": 5000}, "5000"),
     ({"n_steps": 10**9, "timesteps": 10**10}, "1,000,000,000"), ({"n_steps": 300, "timesteps": 16}, "timesteps 16"),
     ({"n_steps": 2000, "observation_size": 250, "n_envs": 4, "timesteps": 10**6}, "8,000 decisions"),
     ({"algo": "ppo", "n_steps": 1, "n_envs": 1}, "PPO")],
)  # fmt: skip
def test_bad_training_options_are_named(changes: dict[str, object], match: str) -> None:
    values = {"model": 4, **changes}
    with pytest.raises(Exception, match=match):
        TrainConfig(**values)  # type: ignore[arg-type]


def test_dagger_has_no_rollout_to_check() -> None:
    TrainConfig(model=5, algo="dagger", n_steps=300, timesteps=16)


class _Poison(BaseCallback):
    """Sets one weight of the policy to NaN at the second step, as a diverging update would."""

    def _on_step(self) -> bool:
        if self.n_calls == 2:
            with torch.no_grad():
                next(iter(self.model.policy.parameters())).view(-1)[0] = float("nan")
        return True


@pytest.mark.parametrize("algo", ["a2c", "ppo"])
def test_a_run_whose_weights_stop_being_finite_ends_with_a_one_line_error(algo: str, tmp_path: Path) -> None:
    config = _config(4, algo=algo, timesteps=32, eval_every=0, checkpoint_every=0)
    with pytest.raises(TrainingDivergedError, match="diverged by decision"):
        train(config, tmp_path / "run", extra_callbacks=[_Poison()], progress=False)
    assert not (tmp_path / "run" / "model.zip").exists()


def test_weights_that_are_not_finite_are_never_saved(tmp_path: Path, trained: Path) -> None:
    model = A2C.load(str(trained), device="cpu")
    with torch.no_grad():
        next(iter(model.policy.parameters())).view(-1)[0] = float("inf")
    with pytest.raises(TrainingDivergedError, match="no longer finite"):
        save_model(model, tmp_path / "model.zip")
    assert not (tmp_path / "model.zip").exists()


# ------------------------------------------------------------------------------ model files
@pytest.fixture(scope="module")
def trained(tmp_path_factory: pytest.TempPathFactory) -> Path:
    run = tmp_path_factory.mktemp("trained")
    return train(_config(4, timesteps=16, eval_every=0, checkpoint_every=0), run / "run", progress=False)


def test_missing_and_corrupt_model_files(tmp_path: Path, trained: Path) -> None:
    with pytest.raises(ConfigError, match="not found"):
        make_policy(f"learned:{tmp_path / 'none.zip'}")
    junk = tmp_path / "junk.zip"
    junk.write_bytes(b"not a zip at all")
    with pytest.raises(ConfigError, match=r"junk\.zip"):
        make_policy(f"learned:{junk}")
    truncated = tmp_path / "truncated.zip"
    truncated.write_bytes(trained.read_bytes()[: trained.stat().st_size // 2])
    with pytest.raises(ConfigError, match=r"truncated\.zip"):
        make_policy(f"learned:{truncated}")
    with pytest.raises(ConfigError, match="needs a model file"):
        make_policy("learned:")


def _rewrite(src: Path, dst: Path, metadata: bytes | None) -> None:
    with zipfile.ZipFile(src) as zin, zipfile.ZipFile(dst, "w") as zout:
        for name in zin.namelist():
            if name != METADATA_ENTRY:
                zout.writestr(name, zin.read(name))
        if metadata is not None:
            zout.writestr(METADATA_ENTRY, metadata)


def test_foreign_zip_needs_trust(tmp_path: Path, trained: Path) -> None:
    foreign = tmp_path / "foreign.zip"
    _rewrite(trained, foreign, None)
    with pytest.raises(ConfigError, match="--trust-model"):
        make_policy(f"learned:{foreign}")
    policy = make_policy(f"learned:{foreign}", trust_model=True)
    result = run_episode(generate_world("office", 1), policy, SHORT, seed=1)
    assert result.decisions > 0


def test_model_for_another_observation_is_refused(tmp_path: Path, trained: Path) -> None:
    wrong = tmp_path / "wrong.zip"
    metadata = zipfile.ZipFile(trained).read(METADATA_ENTRY).replace(b"WeightMap64", b"WeightMapFrontiersPose64")
    _rewrite(trained, wrong, metadata.replace(b'"model": 4', b'"model": 3'))
    with pytest.raises(ConfigError, match="does not fit"):
        make_policy(f"learned:{wrong}")


def test_learned_weight_is_deterministic(trained: Path) -> None:
    policy = make_policy(f"learned:{trained}")
    runs = [run_episode(generate_world("office", 2), policy, SHORT, seed=2) for _ in range(2)]
    assert runs[0].sim_time_s == runs[1].sim_time_s
    assert [d.weight for d in runs[0].decision_log] == [d.weight for d in runs[1].decision_log]
    assert np.isfinite(runs[0].sim_time_s)


class _FirstWeights(BaseCallback):
    """Keeps a copy of the policy's weights as training starts."""

    def __init__(self) -> None:
        super().__init__()
        self.weights: dict[str, torch.Tensor] = {}

    def _on_training_start(self) -> None:
        self.weights = {k: v.clone() for k, v in self.model.policy.state_dict().items()}

    def _on_step(self) -> bool:
        return True


def test_init_starts_the_run_from_a_model_files_weights(tmp_path: Path, trained: Path) -> None:
    first = _FirstWeights()
    config = _config(4, timesteps=8, eval_every=0, checkpoint_every=0, init=str(trained))
    train(config, tmp_path / "run", progress=False, extra_callbacks=[first])
    source = load_policy(trained)[0].state_dict()
    assert source.keys() == first.weights.keys()
    assert all(torch.equal(source[k], first.weights[k]) for k in source)
    assert TrainConfig.load(tmp_path / "run" / "config.yaml").init == str(trained)
    assert f"--init {trained}" in config.command()


def test_init_of_another_kind_or_origin_is_refused_before_any_output(tmp_path: Path, trained: Path) -> None:
    foreign = tmp_path / "foreign.zip"
    _rewrite(trained, foreign, None)
    cases = [(_config(5, init=str(trained)), "holds model 4"),
             (_config(4, init=str(foreign)), "not written by 'frontier-rl train'"),
             (_config(4, init=str(tmp_path / "none.zip")), "not found"),
             (_config(4, init="m" * 5000), "cannot be read")]  # fmt: skip
    for config, match in cases:
        with pytest.raises(ConfigError, match=match):
            train(config, tmp_path / "run", progress=False)
        assert not (tmp_path / "run").exists()


def test_a_resumed_run_with_a_checkpoint_does_not_read_init(tmp_path: Path, trained: Path) -> None:
    init = tmp_path / "init.zip"
    init.write_bytes(trained.read_bytes())
    run = tmp_path / "run"
    config = _config(4, timesteps=48, eval_every=0, checkpoint_every=16, init=str(init))
    with pytest.raises(KeyboardInterrupt):
        train(config, run, progress=False, extra_callbacks=[_Interrupt(20)])
    init.unlink()  # moved away after the run started: its checkpoint holds the weights now
    info = read_metadata(train(config, run, resume=True, progress=False))
    assert info is not None and info.timesteps == 48


def test_sb3_stock_cnn_policy_takes_the_map_image() -> None:
    """The 64 × 64 image is a valid SB3 image space: its stock CnnPolicy (NatureCNN) runs on it."""
    import gymnasium as gym
    from stable_baselines3 import A2C

    env = gym.make("FrontierRL/WeightMap64-v0")
    model = A2C("CnnPolicy", env, n_steps=4, device="cpu")
    obs, _ = env.reset(seed=0)
    action, _ = model.predict(obs, deterministic=True)
    assert 0 <= int(action) < 100


def test_ctrl_c_ends_a_run_of_worker_envs_with_its_checkpoints_line(tmp_path: Path) -> None:
    """With --n-envs 2 the workers, interrupted too, printed tracebacks and the run ended "aborted"
    (exit 1); a Ctrl-C that cut a step's answer mid-message left SB3's close waiting for good."""
    import os
    import signal
    import subprocess
    import sys
    import time

    from tests.processes import sigint_as_in_a_terminal

    out = tmp_path / "run"
    command = [sys.executable, "-c", "import sys; from frontier_rl.launch import main; sys.exit(main())", "train",
               "--model", "7", "--worlds", "rooms", "--timesteps", "4000", "--n-envs", "2", "--eval-every", "0",
               "--checkpoint-every", "32", "--out", str(out), "--no-progress"]  # fmt: skip
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               start_new_session=True, preexec_fn=sigint_as_in_a_terminal)  # fmt: skip
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and len(list((out / "checkpoints").glob("*.zip"))) < 2:
        time.sleep(0.05)
    os.killpg(process.pid, signal.SIGINT)
    stdout, stderr = process.communicate(timeout=60)
    assert process.returncode == 130, stdout + stderr
    assert stderr.startswith("interrupted: the last checkpoint") and stderr.count("\n") == 1, stderr
