"""How an observation becomes a network's input: the one preprocessing of the plain-torch actor and
of a trusted SB3 policy, SB3's own arithmetic done in NumPy."""

from __future__ import annotations

from typing import Any

import numpy as np
import torch


def observation_tensor(value: Any, shape: tuple[int, ...], image: bool) -> torch.Tensor:
    """One entry of an observation as a network takes it, a batch of one of ``shape``: float32,
    an ``image`` divided by 255 (the same float32 division as SB3's preprocessing)."""
    array = np.asarray(value)
    if image:
        array = array.astype(np.float32) / np.float32(255.0)
    array = np.ascontiguousarray(array, np.float32)
    if not array.flags.writeable:  # torch shares the array's memory, and warns on a read-only one
        array = array.copy()
    return torch.from_numpy(array).reshape((-1, *shape))
