"""Reward presets: the thesis's tables 3.1 and 3.2, and a normalised preset that trains well."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from frontier_rl.core.sim.leg_result import LegResult
from frontier_rl.core.world.grid import CellState
from frontier_rl.errors import UnknownNameError, short_repr


@dataclass(frozen=True)
class RewardConfig:
    """One decision's reward: ``scale × (terms)``.

    Attributes:
        end_bonus: paid once when exploration ends by itself (no frontier left).
        per_free_cell: per cell first mapped free during the leg.
        per_occupied_cell: per cell first mapped occupied during the leg.
        per_second: subtracted per second of the leg's simulated time (driving, turning, recovery).
        per_coverage: paid per unit of coverage gained (the share of the explorable area, 0..1).
        chosen_free, chosen_unknown, chosen_occupied, chosen_next_to_wall: the cell rewards of the
            point-goal models (thesis table 3.1), by the state of the chosen cell in the robot's map;
            ``chosen_next_to_wall`` is added when the cell is 4-adjacent to an occupied cell.
        scale: multiplies the sum.
    """

    end_bonus: float
    per_free_cell: float
    per_occupied_cell: float
    per_second: float
    per_coverage: float = 0.0
    chosen_free: float = 0.0
    chosen_unknown: float = 0.0
    chosen_occupied: float = 0.0
    chosen_next_to_wall: float = 0.0
    scale: float = 1.0

    def leg_reward(self, leg: LegResult, coverage_gain: float, ended: bool) -> float:
        """The reward of one decision's drive; ``ended``: exploration finished with it."""
        total = (
            self.per_free_cell * leg.new_free
            + self.per_occupied_cell * leg.new_occupied
            + self.per_coverage * coverage_gain
            - self.per_second * leg.duration_s
            + (self.end_bonus if ended else 0.0)
        )
        return self.scale * total

    def cell_reward(self, state: NDArray[np.int8], row: int, col: int) -> float:
        """The point-goal reward for choosing cell (``row``, ``col``) of map ``state``."""
        value = int(state[row, col])
        if value == CellState.OCCUPIED:
            reward = self.chosen_occupied
        elif value == CellState.FREE:
            reward = self.chosen_free
        else:
            reward = self.chosen_unknown
        if _next_to_wall(state, row, col):
            reward += self.chosen_next_to_wall
        return self.scale * reward


def _next_to_wall(state: NDArray[np.int8], row: int, col: int) -> bool:
    """Whether a 4-neighbour of (row, col) is occupied."""
    rows, cols = state.shape
    for r, c in ((row - 1, col), (row + 1, col), (row, col - 1), (row, col + 1)):
        if 0 <= r < rows and 0 <= c < cols and state[r, c] == CellState.OCCUPIED:
            return True
    return False


THESIS_SECONDS_WEIGHT = 10_000.0
"""The thesis preset's time penalty (reward per second). An office episode maps about 40,000 free
cells (+50 each, +2·10⁶ in all) in about 400 s, so time outweighs the cell rewards above
2·10⁶ / 400 s = 5,000 per second; 10,000 makes the episode's time the dominant term, as the thesis asks."""

_TIME_SCALE = 0.01 / THESIS_SECONDS_WEIGHT
"""The normalised preset's time penalty over the thesis's: its cell terms are scaled by it too."""

REWARD_PRESETS: dict[str, RewardConfig] = {
    # Thesis tables 3.2 (weight models) and 3.1 (the cell terms, used by the point models only).
    "thesis": RewardConfig(
        end_bonus=500.0,
        per_free_cell=50.0,
        per_occupied_cell=25.0,
        per_second=THESIS_SECONDS_WEIGHT,
        chosen_free=400.0,
        chosen_unknown=500.0,
        chosen_occupied=-500.0,
        chosen_next_to_wall=-50.0,
    ),
    # Returns of order 1: −1 per 100 s of exploring, +1 for mapping the whole area (a constant per
    # world, so it shapes credit without changing which policy is fastest), +1 for finishing.
    # The cell terms are table 3.1's scaled as the time term is (10,000 per second -> 0.01), so
    # that, as in the thesis, the best cell is worth 0.05 s: at 1/1000 (0.5 a choice, 50 s) a
    # point model earned more by choosing cells it could not reach, decision after decision,
    # than by exploring.
    "normalised": RewardConfig(
        end_bonus=1.0,
        per_free_cell=0.0,
        per_occupied_cell=0.0,
        per_second=0.01,
        per_coverage=1.0,
        chosen_free=400 * _TIME_SCALE,
        chosen_unknown=500 * _TIME_SCALE,
        chosen_occupied=-500 * _TIME_SCALE,
        chosen_next_to_wall=-50 * _TIME_SCALE,
    ),
}


def reward_preset(name: str) -> RewardConfig:
    """The reward preset called ``name`` (one of :data:`REWARD_PRESETS`)."""
    try:
        return REWARD_PRESETS[name]
    except KeyError:
        choices = ", ".join(REWARD_PRESETS)
        raise UnknownNameError(f"unknown reward preset {short_repr(name)}; choose one of {choices}") from None
