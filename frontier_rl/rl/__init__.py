"""Training with Stable-Baselines3 (needs the ``rl`` extra: torch, stable-baselines3, tensorboard)."""
