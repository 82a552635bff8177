"""What a loaded model is to the code that runs it: the observation it reads, its shape and the
:class:`Actor` protocol every loader's model follows (the plain-torch network of
:mod:`frontier_rl.inference.actor`, a trusted SB3 policy of :mod:`frontier_rl.inference.sb3_zip`).
No torch here: the policies name these types without loading it."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol

from numpy.typing import NDArray

Observation = NDArray[Any] | dict[str, NDArray[Any]]
"""What a model reads: a map image, or (the frontier-table models) a dict of ``map``, ``frontiers``
and ``mask`` arrays, as :mod:`frontier_rl.observation` encodes them."""


@dataclass(frozen=True)
class ObservationShape:
    """What a model reads and how many actions it answers with.

    Attributes:
        image: the map image's (channels, height, width), uint8.
        actions: the number of discrete actions.
        table_rows: the frontier table's rows (K), 0 for a model without a table.
        table_length: the flattened table's length (K × columns), 0 without a table.
    """

    image: tuple[int, int, int]
    actions: int
    table_rows: int = 0
    table_length: int = 0


class Actor(Protocol):
    """A loaded model: what it reads, and its most likely action for an observation."""

    @property
    def shape(self) -> ObservationShape:
        """What the model reads and answers."""

    def act(self, observation: Observation) -> int:
        """The model's most likely action for ``observation`` (deterministic)."""
