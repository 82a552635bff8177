"""A model file runs without the training stack: the plain-torch network has every weight SB3's
policy has, under the same name and shape, and chooses SB3's action; loading one leaves Gymnasium,
SB3 and the envs unimported."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
import torch
from stable_baselines3.common.preprocessing import preprocess_obs

from frontier_rl.inference.actor import ActorCritic, load_actor, model_shape
from frontier_rl.registration import ENV_IDS, MODELS, OBSERVATION_SIZES, Algorithm, env_id
from frontier_rl.rl.model_file import SB3_ALGORITHMS, env_spaces, load_policy, policy_setup

REPO = Path(__file__).resolve().parents[2]
SHIPPED = sorted((REPO / "models").glob("model*.zip"))


def _sb3_policy(model: int, size: int, features_dim: int) -> torch.nn.Module:
    policy_cls, kwargs = policy_setup(model, features_dim)
    obs_space, act_space = env_spaces(env_id(model, size))
    return policy_cls(obs_space, act_space, lambda _: 0.0, **kwargs)


@pytest.mark.parametrize("name", ENV_IDS)
def test_the_shape_of_a_model_is_its_envs(name: str) -> None:
    model, size = next((m, s) for m in MODELS for s in OBSERVATION_SIZES if env_id(m, s) == name)
    shape = model_shape(model, size)
    obs_space, act_space = env_spaces(name)
    assert shape.actions == getattr(act_space, "n", None)
    if isinstance(obs_space, gym.spaces.Dict):
        assert shape.image == obs_space["map"].shape
        assert (shape.table_rows,) == obs_space["mask"].shape
        assert (shape.table_length,) == obs_space["frontiers"].shape
    else:
        assert shape.image == obs_space.shape and shape.table_rows == shape.table_length == 0


@pytest.mark.parametrize("model", sorted(MODELS))
def test_the_network_has_sb3s_weights_and_chooses_sb3s_action(model: int) -> None:
    """Every weight of SB3's policy has a place of the same name, shape and dtype, and with SB3's
    (random) weights loaded the plain network's action is SB3's deterministic prediction."""
    torch.manual_seed(model)
    sb3 = _sb3_policy(model, 64, 32)
    sb3.set_training_mode(False)  # type: ignore[operator]
    ours = ActorCritic(model_shape(model, 64), model, 32)
    theirs = sb3.state_dict()
    assert {k: (v.shape, v.dtype) for k, v in ours.state_dict().items()} == {
        k: (v.shape, v.dtype) for k, v in theirs.items()
    }
    ours.load_state_dict(theirs)
    space = sb3.observation_space  # type: ignore[union-attr]
    space.seed(model)
    for _ in range(20):
        observation = space.sample()
        expected, _ = sb3.predict(observation, deterministic=True)  # type: ignore[operator]
        assert ours.act(observation) == int(np.asarray(expected))


@pytest.mark.parametrize("path", SHIPPED, ids=[p.stem for p in SHIPPED])
def test_a_shipped_model_chooses_sb3s_action(path: Path) -> None:
    actor, info = load_actor(path)
    policy, same = load_policy(path)
    assert info == same and info is not None
    space = policy.observation_space
    space.seed(0)
    for _ in range(25):
        observation = space.sample()
        expected, _ = policy.predict(observation, deterministic=True)
        assert actor.act(observation) == int(np.asarray(expected))


@pytest.mark.parametrize("path", SHIPPED, ids=[p.stem for p in SHIPPED])
def test_the_network_input_is_sb3s_bit_for_bit(path: Path) -> None:
    """The tensors the network is fed equal SB3's ``obs_to_tensor`` and ``preprocess_obs`` exactly
    (values, dtype and shape), also for a read-only observation."""
    actor, _ = load_actor(path)
    assert isinstance(actor, ActorCritic)
    policy, _ = load_policy(path)
    space = policy.observation_space
    space.seed(1)
    for _ in range(10):
        observation = space.sample()
        expected = preprocess_obs(policy.obs_to_tensor(observation)[0], space, normalize_images=policy.normalize_images)
        for value in observation.values() if isinstance(observation, dict) else (observation,):
            value.flags.writeable = False
        got = actor.network_input(observation)
        assert isinstance(got, dict) == isinstance(expected, dict)
        pairs = [(got[k], expected[k]) for k in expected] if isinstance(got, dict) else [(got, expected)]
        for mine, theirs in pairs:
            assert mine.dtype == theirs.dtype and mine.shape == theirs.shape
            assert torch.equal(mine, theirs)


def test_running_a_model_imports_neither_gymnasium_nor_sb3() -> None:
    script = (
        "import sys\n"
        "from frontier_rl.policies import make_policy\n"
        f"make_policy('learned:{REPO / 'models' / 'model7.zip'}')\n"
        "print(sorted(m for m in sys.modules if m.split('.')[0] in ('gymnasium', 'stable_baselines3') "
        "or m.startswith(('frontier_rl.envs', 'frontier_rl.rl'))))\n"
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120, check=True)
    assert done.stdout.strip() == "[]", done.stdout


def test_without_pytorch_a_learned_policy_is_one_line_naming_the_extra() -> None:
    script = (
        "import sys\n"
        "sys.modules['torch'] = None\n"  # as if PyTorch were not installed
        "from frontier_rl.policies import make_policy\n"
        f"make_policy('learned:{REPO / 'models' / 'model7.zip'}')\n"
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert done.returncode != 0
    assert "needs PyTorch: pip install 'frontier_rl[models]'" in done.stderr.strip().splitlines()[-1]


def test_every_algorithm_a_file_may_name_has_an_sb3_class() -> None:
    assert tuple(SB3_ALGORITHMS) == tuple(Algorithm)


def test_models_are_shipped() -> None:
    assert len(SHIPPED) >= 2, "the parametrized tests above need the shipped models"
