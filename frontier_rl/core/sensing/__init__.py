"""sensing: the world's grid + a robot pose → a LiDAR scan (ranges with the thesis's noise)."""
