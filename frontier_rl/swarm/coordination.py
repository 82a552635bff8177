"""Coordinated frontier assignment (Burgard et al. 2000) on top of any single-robot ranking.

Burgard et al. pick, robot after robot, the target of best utility minus cost, and lower the
utility of the targets near each one taken, by ``P(d) = 1 - d / range`` within the sensor range.
A frontier_rl policy gives a ranking rather than a utility, so its order is read as a utility
falling linearly from 1 (its first choice) to 1/n (its last), the teammates' goals are subtracted
as Burgard's discount, and a frontier a teammate is already heading for (within ``claim_radius``)
goes last: it is taken only when no other is left.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def coordinated_order(
    centres: NDArray[np.float64],
    order: NDArray[np.int64],
    claims: NDArray[np.float64],
    claim_radius: float,
    coordination_range: float,
) -> NDArray[np.int64]:
    """``order`` (frontier indices, best first) re-ranked for the teammates' goals.

    Args:
        centres: (n, 2) frontier centres (m).
        order: the robot's own ranking, best first (a permutation of some of range(n)).
        claims: (k, 2) goals (m) of the teammates it is in contact with.
        claim_radius: a frontier whose goal is this close (m) to a claim (a teammate's goal) is taken.
        coordination_range: the discount reaches this far (m) from a claim.
    """
    order = np.asarray(order, dtype=np.int64)
    if len(claims) == 0 or len(order) == 0:
        return order
    n = len(order)
    utility = 1.0 - np.arange(n) / n
    xy = centres[order]
    d = np.hypot(xy[:, None, 0] - claims[None, :, 0], xy[:, None, 1] - claims[None, :, 1])
    utility = utility - np.clip(1.0 - d / coordination_range, 0.0, 1.0).sum(axis=1)
    taken = (d <= claim_radius).any(axis=1)
    # lexsort: the last key is the primary one; stable, so ties keep the policy's order
    return order[np.lexsort((-utility, taken))]
