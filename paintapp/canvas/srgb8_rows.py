"""A preview's 8-bit sRGB pixels in one pass over the picture.

:func:`srgb8_rows` gives, per pixel and colour, the code :func:`paintapp.canvas.preview.srgb8`
gives for the value times the exposure's scale (the same float32 product, the same tables over
the value's bits), flipping the rows on the way: no float32 or index temporaries the size of the
picture, and the interpreter lock released, so the EXR and the force plot written beside it are
not kept waiting.
"""

from __future__ import annotations

import numpy as np

from solver import kernel


@kernel
def srgb8_rows(rgba, scale, tables, shift, out):
    """``out`` (H, W, 3) uint8, top row first, from ``rgba`` (H, W, C >= 3) float32, row 0 =
    bottom: each colour value times ``scale`` (float32), then NaN as 0, clipped to [0, 1] by its
    bits and looked up in ``tables`` = (first code of each bucket, uint8; the bits where the
    code steps up in it, int32), a bucket being the bits shifted right by ``shift``."""
    first, step_bits = tables
    height, width = out.shape[0], out.shape[1]
    one = np.int32(0x3F800000)  # the bits of 1.0
    value = np.empty(1, np.float32)
    bits = value.view(np.int32)
    for y in range(height):
        row = height - 1 - y
        for x in range(width):
            for c in range(3):
                value[0] = rgba[row, x, c] * scale
                b = np.int32(0) if np.isnan(value[0]) else bits[0]
                b = min(max(b, np.int32(0)), one)  # negatives (and -0) to 0, past 1 to 1
                bucket = b >> shift
                out[y, x, c] = first[bucket] + (np.uint8(1) if b >= step_bits[bucket] else 0)
