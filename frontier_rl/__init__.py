"""frontier_rl: learn where a search-and-rescue robot should look next.

A fast 2D frontier-exploration simulator (LiDAR, log-odds mapping, move_base-like navigation),
the classic frontier-selection baselines, and the thesis's frontier-ranking models as Gymnasium
environments (registered under the ``FrontierRL/`` namespace by ``import frontier_rl.envs``).
Importing this package loads neither Gymnasium nor torch.
"""

from frontier_rl.registration import ENV_IDS, env_id

__version__ = "0.1.0"
__all__ = ["ENV_IDS", "__version__", "env_id"]
