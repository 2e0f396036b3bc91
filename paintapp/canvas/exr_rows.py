"""The canvas EXR's channels built in one pass over the texels, each in the type it is stored in.

:func:`file_rows` computes, per texel, every channel of the file (:mod:`paintapp.canvas.exr`'s
layout) and stores it at once as a half float's bits (:func:`~paintapp.canvas.half_floats.half_of`)
or a float32, image rows top first: the values numpy gives (the picture clipped to
+-``HALF_MAX`` with NaN as 0, the height the float32 sum over the pigments, each concentration
``paint / height`` in float32 and 0 where there is no paint, then numpy's cast) without the
float32 temporaries, and with the interpreter lock released, so the preview and the force plot
written beside it are not kept waiting.
"""

from __future__ import annotations

import numpy as np

from paintapp.canvas.half_floats import half_of
from solver import kernel

#: Kinds of channel in :func:`file_rows`'s ``kinds``.
HALF, FLOAT = 0, 1
#: The largest finite 16-bit float: the picture's values are clipped to it.
HALF_MAX = 65504.0


@kernel
def file_rows(rgba, paint, wetness, tooth, layout, halves, floats):
    """Fill the file's channels, image rows top first (canvas row ``H - 1`` first).

    Args:
        rgba: (H, W, 4) float32, the picture, row 0 = canvas bottom.
        paint: (P, H, W) float32, paint per pigment (m).
        wetness: (H, W) float32.
        tooth: (H, W) float32, the surface's tooth (read only when ``layout`` names a channel
            past the pigments; else any array).
        layout: (kinds, slots), each (C,) int64 for the channels R, G, B, A, height, wetness,
            the P concentrations[, tooth]: channel ``c`` goes to ``halves[slots[c]]`` as half
            float bits where ``kinds[c]`` is :data:`HALF`, else to ``floats[slots[c]]``.
        halves: (Ch, H, W) uint16; floats: (Cf, H, W) float32.
    """
    kinds, slots = layout
    pigments, height, width = paint.shape
    n = kinds.size
    half_max = np.float32(HALF_MAX)
    zero = np.float32(0.0)
    values = np.empty(n, np.float32)
    bits = values.view(np.uint32)
    for y in range(height):
        row = height - 1 - y
        for x in range(width):
            for c in range(4):
                v = rgba[row, x, c]
                values[c] = zero if np.isnan(v) else min(max(v, -half_max), half_max)
            total = paint[0, row, x] if pigments > 0 else zero  # numpy's sum starts so
            for p in range(1, pigments):
                total = np.float32(total + paint[p, row, x])
            values[4] = total
            values[5] = wetness[row, x]
            for p in range(pigments):
                values[6 + p] = np.float32(paint[p, row, x] / total) if total > zero else zero
            if n > 6 + pigments:
                values[6 + pigments] = tooth[row, x]
            for c in range(n):
                if kinds[c] == HALF:
                    halves[slots[c], y, x] = half_of(bits[c])
                else:
                    floats[slots[c], y, x] = values[c]
