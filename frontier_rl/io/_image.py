"""Decoding of map images (PGM, PNG, any Pillow mode) into plain NumPy arrays.

Every failure (missing file, truncated or corrupt data, not an image) becomes a one-line
:class:`~frontier_rl.errors.MapError` that names the file. Before any pixel is decoded:

* an image larger than :data:`MAX_MAP_PIXELS` is refused (from its header, before allocating);
* a Netpbm file (PBM/PGM/PPM, ``P1``-``P6``) must hold exactly the pixel data its header
  announces, its maxval 1..65535 and no sample above it (:mod:`frontier_rl.io.netpbm`): a header
  claiming fewer rows (or columns) than the data holds, or more, is an error naming the header's
  width, height and maxval and the data's actual size, never a cropped or padded map.
"""

from __future__ import annotations

import re
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from PIL import Image

from frontier_rl.errors import MapError, short_text
from frontier_rl.io.netpbm import data_size_mismatch, read_netpbm_header, sample_above_maxval

#: Largest map image accepted (pixels, width x height): 4096 x 4096 or the same area in any shape,
#: about 5 times the largest map the package ships (ipa_plant, 1985 x 1536 = 3.0 Mpx).
#: Decoding one takes about 32 bytes of memory per pixel (0.5 GiB at the limit).
MAX_MAP_PIXELS = 4096 * 4096
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


def _too_large(path: Path, width: int, height: int) -> str | None:
    """The message refusing an image of ``width`` x ``height`` pixels, or None when it is allowed."""
    if width * height <= MAX_MAP_PIXELS:
        return None
    return (
        f"{path}: the image is {width} x {height} pixels (width x height), {width * height} in all; "
        f"at most {MAX_MAP_PIXELS} are allowed"
    )


def _bomb_size(exc: Exception) -> str:
    match = re.search(r"\((\d+) pixels\)", str(exc))
    return f"{match.group(1)} pixels" if match else "too many pixels"


def read_image(path: Path) -> RasterImage:
    """Decode the image file at ``path`` (PGM, PNG or anything Pillow reads).

    Raises:
        MapError: the file is missing or is not an image; it has more than :data:`MAX_MAP_PIXELS`
            pixels; its data is truncated or corrupt; a PBM/PGM/PPM header does not match its data.
    """
    if not path.is_file():
        raise MapError(f"map image not found: {path}")
    try:
        header = read_netpbm_header(path)
    except OSError as exc:
        raise MapError(f"cannot read map image {path}: {exc.strerror or exc}") from exc
    too_large = None if header is None else _too_large(path, header.width, header.height)
    if too_large is not None:  # before Pillow allocates anything
        raise MapError(too_large)
    try:
        with warnings.catch_warnings():
            # the limit here is MAX_MAP_PIXELS, well below the size that Pillow warns about
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)
            opened = Image.open(path)
        with opened as image:
            too_large = _too_large(path, *image.size)
            if too_large is not None:
                raise MapError(too_large)
            if header is not None and image.size != (header.width, header.height):  # never expected
                raise MapError(f"{path}: unsupported {header.kind} header: read as {image.size[0]} x {image.size[1]}")
            image.load()
            raster = _decode(image)
    except MapError:
        raise
    except Image.DecompressionBombError as exc:
        raise MapError(
            f"{path}: the image's header claims {_bomb_size(exc)}; at most {MAX_MAP_PIXELS} are allowed"
        ) from None
    # Pillow's decoders raise many unrelated types on corrupt input (OSError, SyntaxError,
    # ValueError, struct.error, IndexError, ...): every one of them means "bad image file".
    except Exception as exc:
        mismatch = data_size_mismatch(path, header) if header is not None else None
        raise MapError(mismatch or f"cannot read map image {path}: {short_text(str(exc), 200)}") from exc
    if header is not None:
        problem = data_size_mismatch(path, header) or sample_above_maxval(path, header)
        if problem is not None:
            raise MapError(problem)
    return raster
