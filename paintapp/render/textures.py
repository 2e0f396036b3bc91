"""The canvas on the GPU: pigment concentrations and the paint surface as textures.

- ``concentration``: a 2D texture array, RGBA half floats; layer ``l`` channel ``j`` holds the
  volume fraction of pigment ``4 l + j``. Half precision (11 bits) is ample for a colour fraction
  and halves the memory of a 4096x4096 canvas (128 MiB per 4 pigments).
- ``surface``: RG 32-bit floats, r = paint height (metres; needs full precision for the relief),
  g = wetness.

Texture row 0 is canvas row 0 (the bottom), matching GL's texture coordinates. Uploads cover only
a texel box (the canvas's dirty region), processed in strips so a full 4096x4096 upload never
builds more than a few tens of MiB of temporaries. A large box (a new canvas, a rebuild) is first
zeroed, which is what bare canvas uploads as, and only the part of it holding paint or wetness
is computed and sent: a blank A4 canvas at 0.1 mm (6.2 million texels) uploads in milliseconds.
"""

from __future__ import annotations

import moderngl
import numpy as np
from numba import njit

from paintapp.canvas.model import Canvas
from paintapp.canvas.regions import Box, box_of_nonzero

#: Texels per upload strip (bounds temporary memory).
STRIP_TEXELS = 1 << 21
#: Boxes of at least this many texels are zeroed and only their painted part computed.
ZERO_FILL_TEXELS = 1 << 20


def layer_count(pigment_count: int) -> int:
    """Concentration layers needed for ``pigment_count`` pigments (at least 1)."""
    return max(1, -(-pigment_count // 4))


class CanvasTextures:
    """GPU textures mirroring one canvas size and pigment count."""

    def __init__(self, ctx: moderngl.Context, pixels: tuple[int, int], pigment_count: int) -> None:
        w, h = pixels
        self.pixels = (w, h)
        self.pigment_count = pigment_count
        self.layers = layer_count(pigment_count)
        self.concentration = ctx.texture_array((w, h, self.layers), 4, dtype="f2")
        self.surface = ctx.texture((w, h), 2, dtype="f4")
        for texture in (self.concentration, self.surface):
            texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
            texture.repeat_x = False
            texture.repeat_y = False

    def fits(self, canvas: Canvas) -> bool:
        """Whether these textures can hold ``canvas`` (same size, enough layers)."""
        return (
            self.pixels == canvas.pixels and layer_count(len(canvas.pigment_names)) == self.layers
        )

    def upload(self, canvas: Canvas, box: Box) -> None:
        """Copy the texels of ``box`` (x0, y0, x1, y1) from the canvas to the GPU."""
        x0, y0, x1, y1 = box
        if (x1 - x0) * (y1 - y0) >= ZERO_FILL_TEXELS:
            self._zero(box)
            content = content_box(canvas, box)
            if content is None:
                return
            x0, y0, x1, y1 = content
        rows = max(1, STRIP_TEXELS // max(1, x1 - x0))
        for r0 in range(y0, y1, rows):
            self._upload_strip(canvas, (x0, r0, x1, min(y1, r0 + rows)))

    def _zero(self, box: Box) -> None:
        """Write bare canvas (all zero) over ``box``, in strips."""
        x0, y0, x1, y1 = box
        w = x1 - x0
        rows = max(1, STRIP_TEXELS // max(1, w))
        for r0 in range(y0, y1, rows):
            h = min(y1, r0 + rows) - r0
            conc = np.zeros((self.layers, h, w, 4), np.float16)
            self.concentration.write(conc, viewport=(x0, r0, 0, w, h, self.layers))
            self.surface.write(np.zeros((h, w, 2), np.float32), viewport=(x0, r0, w, h))

    def _upload_strip(self, canvas: Canvas, box: Box) -> None:
        x0, y0, x1, y1 = box
        w, h = x1 - x0, y1 - y0
        conc = np.empty((self.layers, h, w, 4), np.float32)
        surface = np.empty((h, w, 2), np.float32)
        pack_region(canvas.paint_m, canvas.wetness, x0, y0, conc, surface)
        halves = np.empty(conc.shape, np.uint16)  # the half floats' bits
        half_bits(conc.reshape(-1).view(np.uint32), halves.reshape(-1))
        self.concentration.write(halves, viewport=(x0, y0, 0, w, h, self.layers))
        self.surface.write(surface, viewport=(x0, y0, w, h))

    def release(self) -> None:
        self.concentration.release()
        self.surface.release()


@njit(cache=True, nogil=True)
def half_bits(bits: np.ndarray, out: np.ndarray) -> None:
    """The IEEE half floats nearest float32 values (ties to even), given and returned as their
    bits (``bits`` uint32, ``out`` uint16, both 1D): what numpy's ``astype(np.float16)`` gives,
    subnormals, infinities and NaN included, at a fraction of its cost."""
    for i in range(bits.size):
        x = bits[i]
        sign = (x >> np.uint32(16)) & np.uint32(0x8000)
        exponent = np.int64((x >> np.uint32(23)) & np.uint32(0xFF))
        mantissa = x & np.uint32(0x7FFFFF)
        if exponent == 0xFF:  # infinity or NaN (kept a NaN)
            nan = np.uint32(0x200) if mantissa != 0 else np.uint32(0)
            out[i] = np.uint16(sign | np.uint32(0x7C00) | nan)
            continue
        e = exponent - 127 + 15
        if e >= 31:  # too large: infinity
            out[i] = np.uint16(sign | np.uint32(0x7C00))
            continue
        if e <= 0:  # a half subnormal, or zero
            if e < -10:
                out[i] = np.uint16(sign)
                continue
            mantissa |= np.uint32(0x800000)
            shift = np.uint32(14 - e)
            half = mantissa >> shift
            rest = mantissa & ((np.uint32(1) << shift) - np.uint32(1))
            tie = np.uint32(1) << (shift - np.uint32(1))
            if rest > tie or (rest == tie and (half & np.uint32(1)) != 0):
                half += np.uint32(1)
            out[i] = np.uint16(sign | half)
            continue
        half = sign | (np.uint32(e) << np.uint32(10)) | (mantissa >> np.uint32(13))
        rest = mantissa & np.uint32(0x1FFF)
        if rest > np.uint32(0x1000) or (rest == np.uint32(0x1000) and (half & np.uint32(1)) != 0):
            half += np.uint32(1)  # a carry into the exponent rounds up to the next binade
        out[i] = np.uint16(half)


@njit(cache=True, nogil=True)
def pack_region(
    paint: np.ndarray,
    wetness: np.ndarray,
    x0: int,
    y0: int,
    conc: np.ndarray,
    surface: np.ndarray,
) -> None:
    """One pass over the texels of a box from (``x0``, ``y0``): ``conc`` (layers, h, w, 4) gets
    each pigment's volume fraction (``paint / total`` in float32, 0 where there is no paint;
    channels past the pigments 0), ``surface`` (h, w, 2) the paint height (the float32 sum over
    the pigments) and the wetness. The same values as :meth:`Canvas.concentration_region` and
    ``paint.sum(axis=0, dtype=float32)``, without their temporaries."""
    pigments = paint.shape[0]
    channels = conc.shape[0] * 4
    zero = np.float32(0.0)
    for y in range(conc.shape[1]):
        for x in range(conc.shape[2]):
            total = zero
            for p in range(pigments):
                total += paint[p, y0 + y, x0 + x]
            surface[y, x, 0] = total
            surface[y, x, 1] = wetness[y0 + y, x0 + x]
            for q in range(channels):
                value = zero
                if q < pigments and total > zero:
                    value = paint[q, y0 + y, x0 + x] / total
                conc[q // 4, y, x, q % 4] = value


def content_box(canvas: Canvas, box: Box) -> Box | None:
    """The part of ``box`` holding any paint or wetness (canvas coordinates), or None."""
    x0, y0, x1, y1 = box
    mask = canvas.wetness[y0:y1, x0:x1] != 0.0
    for p in range(len(canvas.pigment_names)):
        mask |= canvas.paint_m[p, y0:y1, x0:x1] != 0.0
    inner = box_of_nonzero(mask)
    if inner is None:
        return None
    return (x0 + inner[0], y0 + inner[1], x0 + inner[2], y0 + inner[3])
