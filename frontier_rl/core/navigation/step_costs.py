"""The planner's step cost factor of a cell: 1, plus the inflation cost by its clearance from the
nearest wall, plus a penalty where it is unknown (passable, as move_base's ``allow_unknown``)."""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.world.grid import UNKNOWN_I8

_COST_STEPS = 64  # inflation table entries per cell of clearance


@nb.njit(cache=True)
def inflation_table(
    lethal_below: float, inflation_radius: float, cost_scaling: float, inflation_cost: float
) -> NDArray[np.float64]:
    """The inflation cost by clearance (cells), in steps of 1/64 cell: ``inflation_cost`` up to the
    lethal distance, then decaying by ``cost_scaling`` per cell. A lookup costs less than exp()
    per cell, and 1/64 cell is far finer than the costmap needs."""
    table = np.empty(int(math.ceil(inflation_radius * _COST_STEPS)) + 2)
    for k in range(table.shape[0]):
        table[k] = inflation_cost * math.exp(-cost_scaling * max(k / _COST_STEPS - lethal_below, 0.0))
    return table


@nb.njit(cache=True, inline="always")
def step_cost(
    clearance: float, unknown: bool, table: NDArray[np.float64], inflation_radius: float, unknown_cost: float
) -> float:
    """The step cost factor of a cell of ``clearance`` (cells): 1 + inflation + unknown penalties."""
    index = int(min(clearance, inflation_radius) * _COST_STEPS)  # in the table even where it is not used
    extra = table[index] if clearance < inflation_radius else 0.0
    extra += unknown_cost if unknown else 0.0
    return 1.0 + extra


@nb.njit(cache=True)
def step_costs(
    state: NDArray[np.int8],
    clearance_padded: NDArray[np.float64],
    table: NDArray[np.float64],
    inflation_radius: float,
    unknown_cost: float,
) -> NDArray[np.float64]:
    """The step cost factor of every cell (:func:`step_cost`), with a border of 1."""
    rows, cols = state.shape
    cost = np.ones((rows + 2, cols + 2))
    for r in range(rows):
        for c in range(cols):
            cost[r + 1, c + 1] = step_cost(
                clearance_padded[r + 1, c + 1], state[r, c] == UNKNOWN_I8, table, inflation_radius, unknown_cost
            )
    return cost
