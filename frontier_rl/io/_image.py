"""Decoding of map images (PGM, PNG, any Pillow mode) into plain NumPy arrays.

Every failure (missing file, truncated or corrupt data, not an image) becomes a
:class:`~frontier_rl.errors.MapError` that names the file.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from PIL import Image

from frontier_rl.errors import MapError

#: Divisor that maps 16-bit samples (0..65535) onto the 8-bit scale (0..255).
_SIXTEEN_TO_EIGHT_BIT = 257.0
_GREY_MODES = frozenset({"1", "L", "LA", "La"})
_ALPHA_MODES = frozenset({"RGBA", "RGBa", "LA", "La", "PA"})


@dataclass(frozen=True)
class RasterImage:
    """A decoded image in image order (row 0 is the top row).

    Attributes:
        colour: float64 array (rows, cols, n) of colour samples on the 0..255 scale; n is 1 for a
            greyscale image and 3 (R, G, B) for a colour one.
        alpha: float64 array (rows, cols) of opacities on the 0..255 scale (0 = fully transparent),
            or None when the image carries no transparency.
    """

    colour: NDArray[np.float64]
    alpha: NDArray[np.float64] | None

    @property
    def shape(self) -> tuple[int, int]:
        """(rows, cols) of the image in pixels."""
        return (int(self.colour.shape[0]), int(self.colour.shape[1]))

    @property
    def shade(self) -> NDArray[np.float64]:
        """Brightness (0..255): the mean of the colour channels, as ROS ``map_server`` computes it."""
        return np.asarray(self.colour.mean(axis=2), dtype=np.float64)

    @property
    def transparent(self) -> NDArray[np.bool_]:
        """Mask of the fully transparent pixels (alpha 0)."""
        if self.alpha is None:
            return np.zeros(self.shape, dtype=np.bool_)
        return np.asarray(self.alpha == 0)


def _decode(image: Image.Image) -> RasterImage:
    """Arrays of an open Pillow image of any mode."""
    if image.mode.startswith("I"):  # 16/32-bit integer greyscale (16-bit PNG or PGM)
        grey = np.clip(np.asarray(image, dtype=np.float64) / _SIXTEEN_TO_EIGHT_BIT, 0.0, 255.0)
        return RasterImage(colour=grey[:, :, np.newaxis], alpha=None)
    has_alpha = image.mode in _ALPHA_MODES or "transparency" in image.info
    target = ("L" if image.mode in _GREY_MODES else "RGB") + ("A" if has_alpha else "")
    pixels = np.asarray(image.convert(target), dtype=np.float64)
    if pixels.ndim == 2:
        pixels = pixels[:, :, np.newaxis]
    if has_alpha:
        return RasterImage(colour=pixels[:, :, :-1], alpha=pixels[:, :, -1])
    return RasterImage(colour=pixels, alpha=None)


def read_image(path: Path) -> RasterImage:
    """Decode the image file at ``path`` (PGM, PNG or anything Pillow reads).

    Raises:
        MapError: the file is missing, is not an image, or its data is truncated or corrupt.
    """
    if not path.is_file():
        raise MapError(f"map image not found: {path}")
    try:
        with Image.open(path) as image:
            image.load()
            return _decode(image)
    # Pillow's decoders raise many unrelated types on corrupt input (OSError, SyntaxError,
    # ValueError, struct.error, IndexError, ...): every one of them means "bad image file".
    except Exception as exc:
        raise MapError(f"cannot read map image {path}: {exc}") from exc
