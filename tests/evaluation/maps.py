"""Small map files for tests of how episodes end."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image


def write_slit_map(folder: Path) -> Path:
    """A ROS map (``slit.yaml`` and ``slit.pgm``) of a 3 m x 2 m box split by a wall at x = 2 m
    with a 0.1 m slit, narrower than the robot: it sees into the other room but cannot go there,
    so its episodes end "unreachable". A start at (1, 1) lies in the larger room."""
    image = np.full((40, 60), 254, dtype=np.uint8)  # 0.05 m cells, row 0 at the top
    image[0, :] = image[-1, :] = image[:, 0] = image[:, -1] = 0
    image[:, 40] = 0
    image[19:21, 40] = 254
    Image.fromarray(image).save(folder / "slit.pgm")
    path = folder / "slit.yaml"
    path.write_text(
        "image: slit.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )
    return path
