"""Models 5 and 7 with a privileged critic: the value head reads what only the simulator knows
(with ``privileged_map``, the true map's unseen space as an image too), the model file leaves it out
(so the deployed policy needs no privileged input and acts as trained), the checkpoints keep it (so
a run resumes), and ``--init`` starts such a run from a plain model file."""

from __future__ import annotations

import io
import zipfile
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
import torch
from stable_baselines3.common.callbacks import BaseCallback

import frontier_rl.envs
from frontier_rl.errors import ConfigError
from frontier_rl.inference.model_file import WEIGHTS_ENTRY
from frontier_rl.inference.sb3_zip import predict_action
from frontier_rl.registration import env_id
from frontier_rl.rl.config import TrainConfig
from frontier_rl.rl.model_file import load_policy, policy_setup
from frontier_rl.rl.networks import PRIVILEGED_HEAD
from frontier_rl.rl.run_folder import latest_checkpoint
from frontier_rl.rl.train import train


def _config(**changes: object) -> TrainConfig:
    values: dict[str, object] = {
        "model": 5, "algo": "ppo", "privileged_critic": True, "timesteps": 64, "n_envs": 1, "n_steps": 16,
        "observation_size": 64, "eval_every": 32, "eval_episodes": 1, "checkpoint_every": 32, "max_decisions": 12,
        "learning_rate": 0.003,
    }  # fmt: skip
    values.update(changes)
    return TrainConfig(**values)  # type: ignore[arg-type]


def _weight_names(path: Path) -> list[str]:
    with zipfile.ZipFile(path) as archive:
        state = torch.load(io.BytesIO(archive.read(WEIGHTS_ENTRY)), map_location="cpu", weights_only=True)
    return list(state)


class _Capture(BaseCallback):
    """Keeps the policy's weights as training ends (the head included), and can interrupt."""

    def __init__(self, stop_at: int = 0) -> None:
        super().__init__()
        self.stop_at = stop_at
        self.state: dict[str, torch.Tensor] = {}

    def _on_step(self) -> bool:
        if self.stop_at and self.num_timesteps >= self.stop_at:
            raise KeyboardInterrupt
        return True

    def _on_training_end(self) -> None:
        self.state = {key: value.clone() for key, value in self.model.policy.state_dict().items()}


@pytest.mark.parametrize(("model", "with_map"), [(5, False), (7, False), (7, True)])
def test_the_model_file_leaves_the_head_out_and_acts_as_trained(model: int, with_map: bool, tmp_path: Path) -> None:
    run = tmp_path / "privileged"
    capture = _Capture()
    final = train(_config(model=model, privileged_map=with_map), run, progress=False, extra_callbacks=[capture])
    head = [key for key in capture.state if key.startswith(f"{PRIVILEGED_HEAD}.")]
    assert head and float(capture.state[head[-1]].abs().sum()) > 0  # the head was trained (it starts at 0)
    for deployed in (final, run / "best_model.zip"):
        assert not any(name.startswith(PRIVILEGED_HEAD) for name in _weight_names(deployed)), deployed
    checkpoint = latest_checkpoint(run)
    assert checkpoint is not None
    assert any(name.startswith(f"{PRIVILEGED_HEAD}.") for name in _weight_names(checkpoint[0]))  # for --resume

    deployed_policy, info = load_policy(final)  # the project's loader: the model's plain observation
    assert info is not None and info.timesteps == 64
    plain_state = deployed_policy.state_dict()
    assert list(plain_state) == [key for key in capture.state if key not in head]
    assert all(torch.equal(plain_state[key], capture.state[key]) for key in plain_state)  # the actor as trained

    frontier_rl.envs.register_envs()
    env = gym.make(env_id(model, 64), privileged=True, privileged_map=with_map)
    policy_cls, kwargs = policy_setup(model, 128)
    trained = policy_cls(env.observation_space, env.action_space, lambda _: 0.0, **kwargs)
    trained.load_state_dict(capture.state)
    trained.set_training_mode(False)
    obs, _ = env.reset(seed=3)
    for _ in range(6):
        plain = {key: value for key, value in obs.items() if not key.startswith("privileged")}
        action = predict_action(deployed_policy, plain)
        for share in (0.0, 0.5, 1.0):  # the actor never reads the privileged entries
            changed = {**obs, "privileged": np.full(2, share, np.float32)}
            if with_map:
                changed["privileged_map"] = np.full_like(obs["privileged_map"], round(255 * share))
            assert predict_action(trained, changed) == action
        obs, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            break
    values = []
    for share in (0.1, 0.9):
        tensors, _ = trained.obs_to_tensor({**obs, "privileged": np.full(2, share, np.float32)})
        with torch.no_grad():
            values.append(float(trained.predict_values(tensors)))
    assert values[0] != values[1]  # the critic reads it
    if with_map:
        images = []
        for fill in (0, 255):
            tensors, _ = trained.obs_to_tensor({**obs, "privileged_map": np.full_like(obs["privileged_map"], fill)})
            with torch.no_grad():
                images.append(float(trained.predict_values(tensors)))
        assert images[0] != images[1]  # and the image


def test_a_privileged_run_resumes_and_starts_from_a_plain_model(tmp_path: Path) -> None:
    plain = train(_config(privileged_critic=False, eval_every=0, timesteps=32), tmp_path / "plain", progress=False)
    run = tmp_path / "from_plain"
    config = _config(init=str(plain), eval_every=0, timesteps=64)
    with pytest.raises(KeyboardInterrupt):
        train(config, run, progress=False, extra_callbacks=[_Capture(stop_at=40)])
    resumed = train(config, run, resume=True, progress=False)
    policy, info = load_policy(resumed)
    assert info is not None and info.timesteps == 64
    started, _ = load_policy(plain)
    assert any(not torch.equal(a, b) for a, b in zip(started.state_dict().values(), policy.state_dict().values(),
                                                      strict=True))  # fmt: skip


@pytest.mark.parametrize(("changes", "needle"), [({"model": 4}, "model 4"), ({"model": 6}, "model 6"),
                                                 ({"algo": "dagger"}, "dagger"),
                                                 ({"privileged_critic": "yes"}, "true or false"),
                                                 ({"privileged_map": 1}, "true or false"),
                                                 ({"privileged_critic": False, "privileged_map": True},
                                                  "set privileged_critic too")])  # fmt: skip
def test_a_privileged_critic_is_refused_where_it_does_not_apply(changes: dict[str, object], needle: str) -> None:
    with pytest.raises(ConfigError, match=needle):
        _config(**changes)


def test_the_command_names_the_option() -> None:
    command = _config().command()
    assert "--privileged-critic" in command and "--privileged-critic True" not in command
    assert "--privileged-map" not in command
    assert "--privileged-critic --privileged-map" in _config(privileged_map=True).command()
    assert "privileged" not in _config(privileged_critic=False).command()


def test_a_head_on_the_image_alone_reads_it() -> None:
    frontier_rl.envs.register_envs()
    env = gym.make(env_id(7, 64), privileged_map=True)
    policy_cls, kwargs = policy_setup(7, 128)
    policy = policy_cls(env.observation_space, env.action_space, lambda _: 0.0, **kwargs)
    head = getattr(policy, PRIVILEGED_HEAD)
    torch.nn.init.ones_(head.mlp[-1].weight)  # it starts at zero: the plain critic
    obs, _ = env.reset(seed=0)
    values = []
    for fill in (0, 255):
        tensors, _ = policy.obs_to_tensor({**obs, "privileged_map": np.full_like(obs["privileged_map"], fill)})
        with torch.no_grad():
            values.append(float(policy.predict_values(tensors)))
    assert values[0] != values[1]
