"""frontier_rl: learn where a search-and-rescue robot should look next.

A fast 2D frontier-exploration simulator (LiDAR, log-odds mapping, move_base-like navigation),
the classic frontier-selection baselines, and the thesis's frontier-ranking models.
"""

__version__ = "0.1.0"
