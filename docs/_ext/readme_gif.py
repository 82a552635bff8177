"""The README's animation: an office world explored by model 7, made small enough for a page.

``frontier-rl explore --gif`` writes one full frame per decision (about 1.8 MB for an office world).
This script runs that command, keeps every second frame at three quarters of the size, and stores
each frame after the first as its difference from the one before (unchanged pixels transparent), on
one palette taken from frames across the run, so that the colours of the ranked frontiers survive:

    .venv/bin/python docs/_ext/readme_gif.py        # writes docs/_static/office_model7.gif
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
from PIL import Image, ImageSequence

REPO = Path(__file__).resolve().parents[2]
TARGET = REPO / "docs" / "_static" / "office_model7.gif"
COMMAND = ("explore", "--world", "office", "--seed", "3", "--policy", "learned:models/model7.zip")
FRAME_STEP = 2
SCALE = 0.75
COLOURS = 255
"""Palette entries; one more is the transparent index."""
MONTAGE_FRAMES = 8
"""Frames across the run whose colours make the palette."""
FRAME_MS, LAST_FRAME_MS = 150, 2500


def shrink(frames: list[Image.Image]) -> list[Image.Image]:
    """Every :data:`FRAME_STEP`-th frame (and the last) at :data:`SCALE`, as difference frames on one palette."""
    kept = [f.convert("RGB") for f in frames[::FRAME_STEP]] + [frames[-1].convert("RGB")]
    width, height = (round(SCALE * side) for side in kept[0].size)
    small = [f.resize((width, height), Image.Resampling.LANCZOS) for f in kept]
    samples = small[:: max(1, len(small) // MONTAGE_FRAMES)][:MONTAGE_FRAMES]
    montage = Image.new("RGB", (width, height * len(samples)))
    for row, frame in enumerate(samples):
        montage.paste(frame, (0, row * height))
    palette = montage.quantize(colors=COLOURS, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
    indexed = [np.array(f.quantize(palette=palette, dither=Image.Dither.NONE)) for f in small]
    colours = [*(palette.getpalette() or [])[: 3 * COLOURS], 0, 0, 0]
    out = []
    for previous, current in zip([None, *indexed[:-1]], indexed, strict=True):
        frame = current.copy()
        if previous is not None:
            frame[current == previous] = COLOURS  # unchanged: transparent, the frame below shows through
        image = Image.fromarray(frame, "P")
        image.putpalette(colours)
        out.append(image)
    return out


def main() -> None:
    """Run the episode, shrink its animation into :data:`TARGET`."""
    with tempfile.TemporaryDirectory() as tmp:
        raw = Path(tmp) / "raw.gif"
        frontier_rl = Path(sys.executable).with_name("frontier-rl")
        subprocess.run([str(frontier_rl), *COMMAND, "--gif", str(raw)], cwd=REPO, check=True, stdout=subprocess.DEVNULL)
        frames = shrink([frame.convert("RGB") for frame in ImageSequence.Iterator(Image.open(raw))])
    durations = [FRAME_MS] * (len(frames) - 1) + [LAST_FRAME_MS]
    frames[0].save(
        TARGET,
        save_all=True,
        append_images=frames[1:],
        duration=durations,
        loop=0,
        disposal=1,
        transparency=COLOURS,
        optimize=False,
    )
    print(f"{TARGET.relative_to(REPO)}: {len(frames)} frames, {TARGET.stat().st_size / 1000:.0f} kB")


if __name__ == "__main__":
    main()
