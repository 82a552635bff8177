"""Models 3 and 4's action without Gymnasium: a bin of the ranking weight w of eq. 3.1."""

from __future__ import annotations

WEIGHT_BINS = 100
"""Number of discrete weights: action a means w = a / 100 (the thesis's output layer)."""


def bin_to_weight(action: int) -> float:
    """The ranking weight of action bin ``action`` (0 ≤ w ≤ 0.99)."""
    return action / WEIGHT_BINS
